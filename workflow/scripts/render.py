from tensegrity import stages, two_pair_stages

with stages.job(snakemake.log[0]):
    out = snakemake.output
    stages.render_robot(snakemake.params.cfg, out.fig1, out.fig4, out.fig5)
    stages.render_cloud(snakemake.input.sweep, snakemake.params.fig6_nominal, out.fig6,
                        snakemake.params.max_pressure)
    for curves, nominal, fig7 in zip(snakemake.input.curves, snakemake.input.nominal, out.fig7):
        stages.render_workspace(curves, nominal, fig7)
    for nominal, two_pair, fig in zip(snakemake.input.nominal, snakemake.input.two_pair, out.two_pair):
        two_pair_stages.render_two_pair(nominal, two_pair, fig)
