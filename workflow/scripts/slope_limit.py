from tensegrity import stages
from tensegrity.stages import gravity

with stages.job(snakemake.log[0], snakemake.threads):
    gravity.slope_limit(
        snakemake.params.cfg,
        snakemake.input.gravity,
        snakemake.input.workspace,
        snakemake.output.nc,
        snakemake.output.png,
        snakemake.input.two_pair,
    )
    gravity.gravity_figure({}, snakemake.input.gravity, snakemake.output.gravity_png)
