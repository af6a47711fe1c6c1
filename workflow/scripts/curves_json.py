from tensegrity import stages

with stages.logging_to(snakemake.log[0]):
    stages.curves_json(snakemake.input, snakemake.output[0])
