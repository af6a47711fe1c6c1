# The two-pair workspace (issue 10): pairs of actuator pairs over a 2-D pressure grid, swept once
# per stabiliser orbit on each canonical face, mapped to all 20 faces, fitted, validated, drawn.
# What the schema cannot check (levels increasing, discard < hold, hold a whole number of
# samples) stops the run before any job, naming the key (io.config.validate, in the Snakefile).

rule two_pair:
    """Free-mode staircase over the two-pair grid on each contact face (one robot per orbit),
    mapped by symmetry to all 20 faces, and the fitted surfaces CoG(p_a, p_b) per combination and
    axis as one JSON file of plain numbers (one job: a job costs about 1 s to start the simulator,
    and the map and the surfaces take 0.2 s)."""
    output:
        contacts=expand("results/two_pair/{contact}.nc", contact=CONTACTS),
        workspace="results/workspace_two_pair.nc",
        curves="results/curves/two_pair.json",
    params:
        cfg=stage_config(config, "two_pair"),
        map_cfg=stage_config(config, "two_pair_map"),
        curves_cfg=stage_config(config, "two_pair_curves"),
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


rule validate_two_pair:
    """Two-pair workspace against statics, direct simulation on other faces, superposition."""
    input:
        contacts=expand("results/two_pair/{contact}.nc", contact=CONTACTS),
        two_pair="results/workspace_two_pair.nc",
        workspace="results/workspace.nc",
    output:
        nc="results/validation/two_pair.nc",
        md="results/validation/two_pair.md",
        html=report("results/validation/two_pair.html", caption="../report/two_pair_validation.rst",
                    category="Validation"),
    params:
        cfg=stage_config(config, "validate_two_pair"),
    log:
        "results/logs/validate_two_pair.log",
    benchmark:
        "results/benchmarks/validate_two_pair.tsv"
    priority: 30
    threads: 1
    resources:
        mem_mb=1500,
        runtime=10,
    script:
        "../scripts/two_pair_validate.py"


rule two_pair_all:
    input:
        "results/workspace_two_pair.nc",
        "results/curves/two_pair.json",
        rules.validate_two_pair.output,
        expand("results/figures/two_pair_{contact}.png", contact=CONTACTS),
