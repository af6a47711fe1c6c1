from tensegrity import stages
from tensegrity.stages import validate

with stages.job(snakemake.log[0], snakemake.threads):
    i, o = snakemake.input, snakemake.output
    validate.validate_gravity(snakemake.params.cfg, i.gravity, i.nominal, o.nc, o.md, o.html)
