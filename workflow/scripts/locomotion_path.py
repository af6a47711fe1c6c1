from tensegrity import stages
from tensegrity.render import locomotion as render_locomotion

with stages.logging_to(snakemake.log[0]):
    render_locomotion.render_paths(snakemake.input[0], snakemake.output.top,
                                   snakemake.output.three_d)
