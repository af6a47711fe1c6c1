from tensegrity import stages

with stages.logging_to(snakemake.log[0]):
    stages.locomotion_states(snakemake.input.paper, snakemake.input.slope, snakemake.output.fig8,
                             snakemake.output.fig9, snakemake.output.fig10)
