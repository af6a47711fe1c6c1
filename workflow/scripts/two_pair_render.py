from tensegrity import stages, two_pair_stages

with stages.job(snakemake.log[0]):
    for nominal, two_pair, out in zip(snakemake.input.nominal, snakemake.input.two_pair, snakemake.output):
        two_pair_stages.render_two_pair(nominal, two_pair, out)
