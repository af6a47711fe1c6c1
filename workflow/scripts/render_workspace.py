from tensegrity import stages

with stages.job(snakemake.log[0]):
    stages.render_cloud(snakemake.input.sweep, snakemake.params.fig6_nominal, snakemake.output.fig6,
                        snakemake.params.max_pressure)
    for curves, nominal, out in zip(snakemake.input.curves, snakemake.input.nominal, snakemake.output.fig7):
        stages.render_workspace(curves, nominal, out)
