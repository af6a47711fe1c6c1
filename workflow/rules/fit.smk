rule fit:
    """Cross-validated curve of the nominal CoG against pressure, per pair and axis."""
    input:
        "results/nominal/{contact}.nc",
    output:
        "results/curves/{contact}.nc",
    params:
        cfg=stage_config(config, "fit"),
    log:
        "results/logs/fit/{contact}.log",
    benchmark:
        "results/benchmarks/fit/{contact}.tsv"
    resources:
        mem_mb=1000,
        runtime=5,
    localrule: True
    script:
        "../scripts/fit.py"


rule curves_json:
    """Every contact case's curves as one JSON file of plain numbers."""
    input:
        expand("results/curves/{contact}.nc", contact=CONTACTS),
    output:
        "results/curves/curves.json",
    log:
        "results/logs/fit/curves_json.log",
    localrule: True
    script:
        "../scripts/curves_json.py"
