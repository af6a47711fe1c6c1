from tensegrity import stages

with stages.job(snakemake.log[0]):
    stages.locomotion_animation(snakemake.input[0], snakemake.output[0], snakemake.params.fps,
                                snakemake.params.speed)
