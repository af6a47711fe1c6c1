from tensegrity import stages

with stages.logging_to(snakemake.log[0]):
    for run, top, three_d in zip(snakemake.input, snakemake.output.top, snakemake.output.three_d):
        stages.locomotion_paths(run, top, three_d)
