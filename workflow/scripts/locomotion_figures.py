from tensegrity import stages
from tensegrity.stages import locomotion

with stages.job(snakemake.log[0]):
    if snakemake.output.states:
        locomotion.state_figures({}, snakemake.input.paper[0], snakemake.input.slope[0], *snakemake.output.states)
    for run, top, three_d in zip(snakemake.input.paths, snakemake.output.top, snakemake.output.three_d):
        locomotion.path_figures({}, run, top, three_d)
    if snakemake.output.gif:
        locomotion.animation(snakemake.params.animation_cfg, snakemake.input.animation[0], snakemake.output.gif[0])
