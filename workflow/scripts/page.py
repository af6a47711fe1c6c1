from tensegrity import stages
from tensegrity.stages import page

with stages.job(snakemake.log[0]):
    inp = snakemake.input
    page.page(snakemake.params.cfg, inp.sweeps, inp.nominal, inp.curves, snakemake.output.html, runs=inp.runs)
