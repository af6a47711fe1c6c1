from tensegrity import stages

with stages.logging_to(snakemake.log[0]):
    for curves, nominal, out in zip(snakemake.input.curves, snakemake.input.nominal, snakemake.output):
        stages.render_workspace(curves, nominal, out)
