from tensegrity import stages, study_stages

with stages.job(snakemake.log[0]):
    study_stages.merge_chunks(snakemake.params.cfg, snakemake.params.study, snakemake.input, snakemake.output[0])
