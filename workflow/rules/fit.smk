rule fit:
    """Cross-validated curve of the nominal CoG against pressure, per pair and axis, of every
    contact case, and all of them as one JSON file of plain numbers (one job: scikit-learn
    takes 1.3 s to import)."""
    input:
        expand("results/nominal/{contact}.nc", contact=CONTACTS),
    output:
        curves=expand("results/curves/{contact}.nc", contact=CONTACTS),
        json="results/curves/curves.json",
    params:
        cfg=stage_config(config, "fit"),
    log:
        "results/logs/fit.log",
    benchmark:
        "results/benchmarks/fit.tsv"
    resources:
        mem_mb=1000,
        runtime=5,
    priority: 40  # feeds the figures of `render`
    localrule: True
    script:
        "../scripts/fit.py"
