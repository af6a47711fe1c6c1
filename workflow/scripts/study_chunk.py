from tensegrity import stages
from tensegrity.stages import study

with stages.job(snakemake.log[0], snakemake.threads):
    study.study_chunk(
        snakemake.params.cfg,
        snakemake.params.study,
        int(snakemake.wildcards.chunk),
        snakemake.output[0],
        snakemake.params.limit,
    )
