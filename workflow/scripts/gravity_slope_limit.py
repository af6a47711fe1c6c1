from tensegrity import gravity_stages, stages

with stages.job(snakemake.log[0], snakemake.threads):
    gravity_stages.run_slope_limit(snakemake.params.cfg, snakemake.input.gravity, snakemake.input.workspace,
                                   snakemake.output.nc, snakemake.output.png,
                                   (list(snakemake.input.two_pair) or [None])[0])
    gravity_stages.validate_gravity(snakemake.params.validate_cfg, snakemake.input.gravity, snakemake.input.nominal,
                                    snakemake.output.validation_nc, snakemake.output.validation_md,
                                    snakemake.output.validation_html)
    gravity_stages.render_gravity(snakemake.input.gravity, snakemake.output.gravity_png)
