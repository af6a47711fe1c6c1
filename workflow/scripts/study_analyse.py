from pathlib import Path

from tensegrity import stages
from tensegrity.stages import study

with stages.job(snakemake.log[0]):
    study.study_analyse(
        snakemake.params.cfg,
        snakemake.params.study,
        snakemake.input[0],
        snakemake.output.nc,
        Path(snakemake.output.figures[0]).parent,
    )
