rule nominal:
    """Average each level's CoG samples into the nominal CoG, with spread, triangle and margin,
    of every contact case (under nominal.method statics: solve the static equilibria instead,
    no sweep), and map the canonical workspaces to all 20 faces with the symmetry group (one
    job: every consumer reads both contact cases, and a job costs 0.45 s to start)."""
    input:
        [] if NOMINAL_STATICS else
        [expand(f"results/sweeps/{contact}/pair{{pair:02d}}.nc", pair=PAIRS) for contact in CONTACTS],
    output:
        nominal=expand("results/nominal/{contact}.nc", contact=CONTACTS),
        workspace="results/workspace.nc",
    params:
        cfg=cfg("nominal_statics" if NOMINAL_STATICS else "nominal"),
        contacts=CONTACTS,  # in the order of the outputs
        map_cfg=cfg("workspace"),
    log:
        "results/logs/nominal.log",
    priority: 45  # feeds the locomotion runs
    resources:
        mem_mb=1000,
        runtime=5,
    localrule: True
    script:
        "../scripts/nominal.py"
