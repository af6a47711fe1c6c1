from tensegrity import stages
from tensegrity.stages import locomotion

with stages.job(snakemake.log[0], snakemake.threads):
    locomotion.locomotion_runs(
        snakemake.params.cfg,
        snakemake.params.runs,
        snakemake.input.workspace,
        snakemake.output,
        snakemake.input.two_pair,
    )
