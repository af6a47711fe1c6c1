from tensegrity import stages
from tensegrity.stages import nominal

with stages.job(snakemake.log[0]):
    if snakemake.params.cfg["nominal"]["method"] == "statics":
        nominal.nominal_statics(snakemake.params.cfg, snakemake.params.contacts, snakemake.output.nominal)
    else:
        n = len(snakemake.input) // len(snakemake.output.nominal)  # the sweep files of each contact case, in order
        for k, out in enumerate(snakemake.output.nominal):
            nominal.nominal(snakemake.params.cfg, snakemake.input[k * n : (k + 1) * n], out)
    nominal.workspace(snakemake.params.map_cfg, snakemake.output.nominal, snakemake.output.workspace)
