from tensegrity import stages

with stages.job(snakemake.log[0]):
    stages.run_nominal(snakemake.params.cfg, snakemake.input, snakemake.output[0])
