from tensegrity import stages
from tensegrity.validation import report as validation_report

with stages.job(snakemake.log[0], snakemake.threads):
    validation_report.run_stage(snakemake.params.cfg, snakemake.input.nominal, snakemake.input.workspace,
                                snakemake.output.nc, snakemake.output.md, snakemake.output.html,
                                run_paths=snakemake.input.runs)
