from tensegrity import stages

with stages.job(snakemake.log[0], snakemake.threads):
    for contact, folder in snakemake.params.folders.items():
        stages.run_sweep(snakemake.params.cfg, contact, folder)
