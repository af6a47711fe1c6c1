from tensegrity import render_locomotion, stages

with stages.logging_to(snakemake.log[0]):
    render_locomotion.render_paths(snakemake.input[0], snakemake.output.top,
                                   snakemake.output.three_d)
