from tensegrity import stages
from tensegrity.stages import validate

with stages.job(snakemake.log[0], snakemake.threads):
    i, o = snakemake.input, snakemake.output
    validate.validate(
        snakemake.params.cfg, i.nominal, i.workspace, o.nc, o.md, o.html, run_paths=i.runs, prototype_path=i.prototype
    )
    validate.validate_two_pair(
        snakemake.params.two_pair_cfg,
        i.two_pair_contacts,
        i.two_pair,
        i.workspace,
        o.two_pair_nc,
        o.two_pair_md,
        o.two_pair_html,
    )
