from tensegrity import stages

with stages.job(snakemake.log[0]):
    if snakemake.output.states:
        stages.locomotion_states(snakemake.input.paper[0], snakemake.input.slope[0], *snakemake.output.states)
    for run, top, three_d in zip(snakemake.input.paths, snakemake.output.top, snakemake.output.three_d):
        stages.locomotion_paths(run, top, three_d)
    if snakemake.output.gif:
        stages.locomotion_animation(snakemake.input.animation[0], snakemake.output.gif[0],
                                    snakemake.params.fps, snakemake.params.speed)
