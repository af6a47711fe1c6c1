from tensegrity import stages
from tensegrity.stages import sweep

with stages.job(snakemake.log[0], snakemake.threads):
    for contact, folder in snakemake.params.folders.items():
        sweep.sweep(snakemake.params.cfg, contact, folder)
