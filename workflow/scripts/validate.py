from tensegrity import stages, two_pair_stages
from tensegrity.validation import report as validation_report

with stages.job(snakemake.log[0], snakemake.threads):
    validation_report.run_stage(snakemake.params.cfg, snakemake.input.nominal, snakemake.input.workspace,
                                snakemake.output.nc, snakemake.output.md, snakemake.output.html,
                                run_paths=snakemake.input.runs)
    two_pair_stages.validate_two_pair(snakemake.params.two_pair_cfg, snakemake.input.two_pair_contacts,
                                      snakemake.input.two_pair, snakemake.input.workspace,
                                      snakemake.output.two_pair_nc, snakemake.output.two_pair_md,
                                      snakemake.output.two_pair_html)
