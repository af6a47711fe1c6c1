from tensegrity import stages

with stages.job(snakemake.log[0]):
    n = len(snakemake.input) // len(snakemake.output.nominal)  # the sweep files of each contact case, in order
    for k, out in enumerate(snakemake.output.nominal):
        stages.run_nominal(snakemake.params.cfg, snakemake.input[k * n:(k + 1) * n], out)
    stages.run_map(snakemake.params.map_cfg, snakemake.output.nominal, snakemake.output.workspace)
