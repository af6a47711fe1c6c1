from tensegrity import stages, study_stages

with stages.job(snakemake.log[0], snakemake.threads):
    study_stages.run_chunk(snakemake.params.cfg, snakemake.params.study,
                           int(snakemake.wildcards.chunk), snakemake.output[0], snakemake.params.limit)
