from tensegrity import stages
from tensegrity.stages import study

with stages.job(snakemake.log[0]):
    study.study_merge(snakemake.params.cfg, snakemake.params.study, snakemake.input, snakemake.output[0])
