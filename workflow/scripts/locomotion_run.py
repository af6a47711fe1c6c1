from tensegrity import stages

with stages.job(snakemake.log[0], snakemake.threads):
    stages.locomotion_run(snakemake.params.cfg, snakemake.wildcards.run, snakemake.input.workspace,
                          snakemake.output[0], snakemake.input.two_pair)
