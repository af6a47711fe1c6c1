rule fit:
    """Cross-validated curve of the nominal CoG against pressure, per pair and axis, of every
    contact case, and all of them as one JSON file of plain numbers; the fitted surfaces
    CoG(p_a, p_b) of the two-pair workspace, per combination and axis, as one JSON file (one
    job: each job pays about 0.5 s to start and read its inputs)."""
    input:
        nominal=expand("results/nominal/{contact}.nc", contact=CONTACTS),
        two_pair=expand("results/two_pair/{contact}.nc", contact=CONTACTS),
    output:
        curves=expand("results/curves/{contact}.nc", contact=CONTACTS),
        json="results/curves/curves.json",
        two_pair="results/curves/two_pair.json",
    params:
        cfg=cfg("curves"),
        json_cfg=cfg("curves_json"),
        two_pair_cfg=cfg("two_pair_surfaces"),
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
