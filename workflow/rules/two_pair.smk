# The two-pair workspace (issue 10): pairs of actuator pairs over a 2-D pressure grid, swept once
# per stabiliser orbit on each canonical face, mapped to all 20 faces (fitted by rule `fit`,
# checked by rule `validate`, drawn by rule `render`).
# What the schema cannot check (levels increasing, discard < hold, hold a whole number of
# samples) stops the run before any job, naming the key (io.config.validate, in the Snakefile).

rule two_pair:
    """Free-mode staircase over the two-pair grid on each contact face (one robot per orbit),
    mapped by symmetry to all 20 faces (one job: a job costs about 1 s to start the simulator,
    and the map takes 0.1 s)."""
    output:
        contacts=expand("results/two_pair/{contact}.nc", contact=CONTACTS),
        workspace="results/workspace_two_pair.nc",
    params:
        cfg=stage_config(config, "two_pair"),
        map_cfg=stage_config(config, "two_pair_map"),
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
