from tensegrity import stages
from tensegrity.stages import gravity

with stages.job(snakemake.log[0], snakemake.threads):
    gravity.gravity(snakemake.params.cfg, snakemake.output[0])
