from tensegrity import stages, two_pair_stages

with stages.job(snakemake.log[0], snakemake.threads):
    two_pair_stages.run_two_pair(snakemake.params.cfg, snakemake.wildcards.contact, snakemake.output[0])
