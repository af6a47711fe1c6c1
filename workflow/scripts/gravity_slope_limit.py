from tensegrity import gravity_stages, stages

with stages.job(snakemake.log[0], snakemake.threads):
    gravity_stages.run_slope_limit(snakemake.params.cfg, snakemake.input.gravity, snakemake.input.workspace,
                                   snakemake.output.nc, snakemake.output.png,
                                   (list(snakemake.input.two_pair) or [None])[0])
