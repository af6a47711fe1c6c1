from tensegrity import gravity_stages, stages

with stages.job(snakemake.log[0], snakemake.threads):
    gravity_stages.run_gravity(snakemake.params.cfg, snakemake.output[0])
