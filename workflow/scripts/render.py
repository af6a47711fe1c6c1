from tensegrity import stages
from tensegrity.stages import render

with stages.job(snakemake.log[0]):
    out = snakemake.output
    render.robot_figures(snakemake.params.cfg, out.fig1, out.fig4, out.fig5)
    render.cog_cloud({}, snakemake.input.sweep or None, snakemake.params.fig6_nominal, out.fig6)
    for curves, nominal, fig7 in zip(snakemake.input.curves, snakemake.input.nominal, out.fig7):
        render.workspace_figure({}, curves, nominal, fig7)
    for nominal, two_pair, fig in zip(snakemake.input.nominal, snakemake.input.two_pair, out.two_pair):
        render.two_pair_figure({}, nominal, two_pair, fig)
