from pathlib import Path

from tensegrity import stages, study_stages

with stages.job(snakemake.log[0]):
    study_stages.analyse(snakemake.params.cfg, snakemake.params.study, snakemake.input[0],
                         snakemake.output.nc, Path(snakemake.output.figures[0]).parent)
