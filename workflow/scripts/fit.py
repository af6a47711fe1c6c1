from tensegrity import stages
from tensegrity.stages import fit

with stages.job(snakemake.log[0]):
    for nominal, curves in zip(snakemake.input.nominal, snakemake.output.curves):
        fit.curves(snakemake.params.cfg, nominal, curves)
    fit.curves_json(snakemake.params.json_cfg, snakemake.output.curves, snakemake.output.json)
    fit.two_pair_surfaces(snakemake.params.two_pair_cfg, snakemake.input.two_pair, snakemake.output.two_pair)
