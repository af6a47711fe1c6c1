from tensegrity import stages
from tensegrity.render import locomotion as render_locomotion

with stages.logging_to(snakemake.log[0]):
    render_locomotion.render_animation(snakemake.input[0], snakemake.output[0],
                                       snakemake.params.fps, snakemake.params.speed)
