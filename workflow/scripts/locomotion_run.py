from tensegrity import stages
from tensegrity.locomotion import demos as locomotion_io

with stages.logging_to(snakemake.log[0], snakemake.threads):
    locomotion_io.run_demo(snakemake.params.cfg, snakemake.wildcards.run, snakemake.input[0],
                        snakemake.output[0])
