rule page:
    """The interactive 3D page: the robot, the support triangle, every pair's CoG samples,
    nominal CoGs and fitted curve of each contact case (Figs. 6-7 in 3D), and every
    demonstration run's path; one self-contained HTML file that opens offline."""
    input:
        sweeps=[] if NOMINAL_STATICS else expand("results/sweeps/{contact}/pair{pair:02d}.nc", contact=CONTACTS, pair=PAIRS),
        nominal=expand("results/nominal/{contact}.nc", contact=CONTACTS),
        curves=expand("results/curves/{contact}.nc", contact=CONTACTS),
        runs=expand("results/locomotion/{run}.nc", run=LOCO_RUNS),
    output:
        html=report("results/figures/workspace_3d.html", caption="../report/page.rst", category="Figures",
                    subcategory="interactive 3D"),
    params:
        cfg=cfg("page"),
    log:
        "results/logs/page.log",
    benchmark:
        "results/benchmarks/page.tsv"
    resources:
        mem_mb=1000,
        runtime=5,
    localrule: True
    script:
        "../scripts/page.py"
