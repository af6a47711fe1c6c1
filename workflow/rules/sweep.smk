rule sweep:
    """Pressure staircase on every configured pair, standing on one contact face."""
    output:
        expand("results/sweeps/{{contact}}/pair{pair:02d}.nc", pair=PAIRS),
    params:
        cfg=stage_config(config, "sweep"),
    log:
        "results/logs/sweep/{contact}.log",
    benchmark:
        "results/benchmarks/sweep/{contact}.tsv"
    priority: 35  # feeds the locomotion runs (-> map), the longest chain of short jobs
    threads: 1  # the jobs are short: two in parallel beat one with two threads
    resources:
        mem_mb=1000,
        runtime=10,
    script:
        "../scripts/sweep.py"
