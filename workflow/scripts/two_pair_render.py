from tensegrity import stages, two_pair_stages

with stages.logging_to(snakemake.log[0]):
    two_pair_stages.render_two_pair(snakemake.input.nominal, snakemake.input.two_pair, snakemake.output[0])
