from tensegrity import gravity_stages, stages

with stages.logging_to(snakemake.log[0], snakemake.threads):
    gravity_stages.run_gravity(snakemake.params.cfg, snakemake.output.nc, snakemake.output.png)
