from tensegrity import stages

with stages.logging_to(snakemake.log[0]):
    stages.locomotion_paths(snakemake.input[0], snakemake.output.top, snakemake.output.three_d)
