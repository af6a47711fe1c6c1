from tensegrity import stages
from tensegrity.stages import two_pair

with stages.job(snakemake.log[0], snakemake.threads):
    for contact, out in zip(snakemake.params.contacts, snakemake.output.contacts):
        two_pair.two_pair(snakemake.params.cfg, contact, out)
    two_pair.two_pair_map(snakemake.params.map_cfg, snakemake.output.contacts, snakemake.output.workspace)
