rule nominal:
    """Average each level's CoG samples into the nominal CoG, with spread, triangle and margin,
    of every contact case (one job: every consumer reads both, and a job costs 0.45 s to start)."""
    input:
        [expand(f"results/sweeps/{contact}/pair{{pair:02d}}.nc", pair=PAIRS) for contact in CONTACTS],
    output:
        expand("results/nominal/{contact}.nc", contact=CONTACTS),
    params:
        cfg=stage_config(config, "nominal"),
    log:
        "results/logs/nominal.log",
    priority: 35  # feeds the locomotion runs (-> map)
    resources:
        mem_mb=1000,
        runtime=5,
    localrule: True
    script:
        "../scripts/nominal.py"
