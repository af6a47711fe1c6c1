from tensegrity import stages

with stages.job(snakemake.log[0], snakemake.threads):
    stages.run_sweep(snakemake.params.cfg, snakemake.wildcards.contact,
                     str(snakemake.output[0]).rsplit("/", 1)[0])
