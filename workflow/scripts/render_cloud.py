from tensegrity import stages

with stages.logging_to(snakemake.log[0]):
    stages.render_cloud(snakemake.input.sweep, snakemake.input.nominal, snakemake.output[0],
                        snakemake.params.max_pressure)
