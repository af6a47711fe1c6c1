from tensegrity import stages

with stages.logging_to(snakemake.log[0]):
    stages.render_workspace(snakemake.input.curves, snakemake.input.nominal, snakemake.output[0])
