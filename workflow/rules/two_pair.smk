# The two-pair workspace: pairs of actuator pairs over a 2-D pressure grid, swept once per
# stabiliser orbit on each canonical face, mapped to all 20 faces (fitted by rule `fit`, checked
# by rule `validate`, drawn by rule `render`).

rule two_pair:
    """Free-mode staircase over the two-pair grid on each contact face (one robot per orbit),
    mapped by symmetry to all 20 faces (one job: a job costs about 1 s to start the simulator,
    and the map takes 0.1 s)."""
    output:
        contacts=expand("results/two_pair/{contact}.nc", contact=CONTACTS),
        workspace="results/workspace_two_pair.nc",
    params:
        cfg=cfg("two_pair"),
        map_cfg=cfg("two_pair_map"),
        contacts=CONTACTS,  # in the order of the outputs
    log:
        "results/logs/two_pair/sweep.log",
    benchmark:
        "results/benchmarks/two_pair.tsv"
    priority: 45  # feeds the locomotion runs: beside the sweep
    threads: 1
    resources:
        mem_mb=1500,
        runtime=10,
    script:
        "../scripts/two_pair.py"


rule two_pair_all:
    input:
        "results/workspace_two_pair.nc",
        "results/curves/two_pair.json",
        "results/validation/two_pair.md",  # made by rule `validate`
        expand("results/figures/two_pair_{contact}.png", contact=CONTACTS),
