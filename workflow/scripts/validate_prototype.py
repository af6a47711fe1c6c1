from tensegrity import stages
from tensegrity.stages import prototype

with stages.job(snakemake.log[0], snakemake.threads):
    prototype.validate_prototype(snakemake.params.cfg, snakemake.output.nc)
