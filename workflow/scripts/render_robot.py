from tensegrity import stages

with stages.job(snakemake.log[0]):
    stages.render_robot(snakemake.params.cfg, snakemake.output.fig1, snakemake.output.fig4,
                        snakemake.output.fig5)
