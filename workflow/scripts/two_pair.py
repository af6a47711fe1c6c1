from tensegrity import stages, two_pair_stages

with stages.job(snakemake.log[0], snakemake.threads):
    for contact, out in zip(snakemake.params.contacts, snakemake.output.contacts):
        two_pair_stages.run_two_pair(snakemake.params.cfg, contact, out)
    two_pair_stages.two_pair_map(snakemake.params.map_cfg, snakemake.output.contacts, snakemake.output.workspace)
