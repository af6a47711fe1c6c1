from tensegrity import stages

with stages.job(snakemake.log[0]):
    for nominal, curves in zip(snakemake.input, snakemake.output.curves):
        stages.run_fit(snakemake.params.cfg, nominal, curves)
    stages.curves_json(snakemake.output.curves, snakemake.output.json)
