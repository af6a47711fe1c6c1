from tensegrity import stages, validation

with stages.logging_to(snakemake.log[0], snakemake.threads):
    validation.run_stage(snakemake.params.cfg, snakemake.input.nominal, snakemake.input.workspace,
                         snakemake.output.nc, snakemake.output.md, snakemake.output.html)
