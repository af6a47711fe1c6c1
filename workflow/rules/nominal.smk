rule nominal:
    """Average each level's CoG samples into the nominal CoG, with spread, triangle and margin."""
    input:
        expand("results/sweeps/{{contact}}/pair{pair:02d}.nc", pair=PAIRS),
    output:
        "results/nominal/{contact}.nc",
    params:
        cfg=stage_config(config, "nominal"),
    log:
        "results/logs/nominal/{contact}.log",
    priority: 35  # feeds the locomotion runs (-> map)
    resources:
        mem_mb=1000,
        runtime=5,
    localrule: True
    script:
        "../scripts/nominal.py"
