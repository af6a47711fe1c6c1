from tensegrity import stages, two_pair_stages

with stages.job(snakemake.log[0]):
    two_pair_stages.two_pair_map(snakemake.params.cfg, snakemake.input, snakemake.output[0])
