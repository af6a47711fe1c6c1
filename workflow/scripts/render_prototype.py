from tensegrity import stages
from tensegrity.stages import prototype

with stages.job(snakemake.log[0]):
    prototype.prototype_figure(snakemake.params.cfg, snakemake.input.prototype, snakemake.output.fig12)
