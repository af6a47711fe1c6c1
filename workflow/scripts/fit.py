from tensegrity import stages

with stages.logging_to(snakemake.log[0]):
    stages.run_fit(snakemake.params.cfg, snakemake.input[0], snakemake.output[0])
