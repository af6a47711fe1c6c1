from tensegrity import stages
from tensegrity.render import locomotion as render_locomotion

with stages.logging_to(snakemake.log[0]):
    render_locomotion.render_states(snakemake.input.paper, snakemake.input.slope,
                                    snakemake.output.fig8, snakemake.output.fig9,
                                    snakemake.output.fig10)
