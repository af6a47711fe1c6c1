from tensegrity import stages

with stages.logging_to(snakemake.log[0], snakemake.threads):
    stages.locomotion_run(snakemake.params.cfg, snakemake.wildcards.run, snakemake.input[0],
                          snakemake.output[0])
