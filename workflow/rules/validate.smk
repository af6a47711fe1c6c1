rule validate:
    """Check the workspace against the paper, statics, symmetry, the grounded mode and dt/2, and
    that the demonstration runs arrived (check 6: it waits for the runs)."""
    input:
        nominal=expand("results/nominal/{contact}.nc", contact=CONTACTS),
        workspace="results/workspace.nc",
        runs=expand("results/locomotion/{run}.nc", run=config["locomotion"]["runs"]),
    output:
        nc="results/validation/validation.nc",
        md="results/validation/summary.md",
        html=report("results/validation/summary.html", caption="../report/validation.rst",
                    category="Validation"),
    params:
        cfg=stage_config(config, "validate"),
    log:
        "results/logs/validate.log",
    benchmark:
        "results/benchmarks/validate.tsv"
    priority: 25
    threads: 1  # a second one only while the other core idles: the figures of the runs use it
    resources:
        mem_mb=2000,
        runtime=10,
    script:
        "../scripts/validate.py"
