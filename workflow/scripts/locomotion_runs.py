from tensegrity import stages

with stages.job(snakemake.log[0], snakemake.threads):
    stages.locomotion_runs(snakemake.params.cfg, snakemake.params.runs, snakemake.input.workspace,
                           snakemake.output, snakemake.input.two_pair)
