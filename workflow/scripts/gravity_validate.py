from tensegrity import gravity_stages, stages

with stages.job(snakemake.log[0], snakemake.threads):
    gravity_stages.validate_gravity(snakemake.params.cfg, snakemake.input.gravity, snakemake.input.nominal,
                                    snakemake.output.nc, snakemake.output.md, snakemake.output.html)
