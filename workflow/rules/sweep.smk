rule sweep:
    """Pressure staircase on every configured pair, standing on each contact face (one job:
    a job costs about 1 s to start the simulator)."""
    output:
        [expand(f"results/sweeps/{contact}/pair{{pair:02d}}.nc", pair=PAIRS) for contact in CONTACTS],
    params:
        cfg=cfg("sweep"),
        folders={contact: f"results/sweeps/{contact}" for contact in CONTACTS},
    log:
        "results/logs/sweep.log",
    benchmark:
        "results/benchmarks/sweep.tsv"
    priority: 45  # heads the longest chain (-> nominal -> runs -> figures): first
    threads: 1  # short batches: beside the gravity-aware workspace
    resources:
        mem_mb=1000,
        runtime=10,
    script:
        "../scripts/sweep.py"
