from tensegrity import stages, two_pair_stages

with stages.job(snakemake.log[0]):
    for nominal, curves in zip(snakemake.input.nominal, snakemake.output.curves):
        stages.run_fit(snakemake.params.cfg, nominal, curves)
    stages.curves_json(snakemake.output.curves, snakemake.output.json)
    two_pair_stages.two_pair_curves(snakemake.params.two_pair_cfg, snakemake.input.two_pair, snakemake.output.two_pair)
