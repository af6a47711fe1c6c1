from tensegrity import stages

with stages.job(snakemake.log[0]):
    stages.run_map({}, snakemake.input, snakemake.output[0])
