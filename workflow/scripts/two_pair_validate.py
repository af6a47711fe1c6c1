from tensegrity import stages, two_pair_stages

with stages.job(snakemake.log[0], snakemake.threads):
    two_pair_stages.validate_two_pair(snakemake.params.cfg, snakemake.input.contacts, snakemake.input.two_pair,
                                      snakemake.input.workspace, snakemake.output.nc, snakemake.output.md,
                                      snakemake.output.html)
