# The two-pair workspace (issue 10): pairs of actuator pairs over a 2-D pressure grid, swept once
# per stabiliser orbit on each canonical face, mapped to all 20 faces, fitted, validated, drawn.
# What the schema cannot check (levels increasing, discard < hold, hold a whole number of
# samples) stops the run before any job, naming the key (io.config.validate, in the Snakefile).

rule two_pair:
    """Free-mode staircase over the two-pair grid on one contact face (one robot per orbit)."""
    output:
        "results/two_pair/{contact}.nc",
    params:
        cfg=stage_config(config, "two_pair"),
    log:
        "results/logs/two_pair/{contact}.log",
    benchmark:
        "results/benchmarks/two_pair/{contact}.tsv"
    priority: 35  # feeds the locomotion runs (-> two_pair_map)
    threads: 1
    resources:
        mem_mb=1500,
        runtime=10,
    script:
        "../scripts/two_pair_sweep.py"


rule two_pair_map:
    """The two-pair workspace of all 20 faces, mapped by symmetry."""
    input:
        expand("results/two_pair/{contact}.nc", contact=CONTACTS),
    output:
        "results/workspace_two_pair.nc",
    params:
        cfg=stage_config(config, "two_pair_map"),
    log:
        "results/logs/two_pair/map.log",
    priority: 35
    localrule: True
    script:
        "../scripts/two_pair_map.py"


rule two_pair_curves:
    """Fitted surfaces CoG(p_a, p_b) per combination and axis as one JSON file of plain numbers."""
    input:
        expand("results/two_pair/{contact}.nc", contact=CONTACTS),
    output:
        "results/curves/two_pair.json",
    params:
        cfg=stage_config(config, "two_pair_curves"),
    log:
        "results/logs/two_pair/curves.log",
    localrule: True
    script:
        "../scripts/two_pair_curves.py"


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
    threads: 1
    resources:
        mem_mb=1500,
        runtime=10,
    script:
        "../scripts/two_pair_validate.py"


rule render_two_pair:
    """The CoG region one pair and two pairs reach, with the support triangle, of every contact
    case (one job: each job would pay the renderer's start-up again)."""
    input:
        nominal=expand("results/nominal/{contact}.nc", contact=CONTACTS),
        two_pair=expand("results/two_pair/{contact}.nc", contact=CONTACTS),
    output:
        [report(f"results/figures/two_pair_{contact}.png", caption="../report/two_pair.rst",
                category="Figures", subcategory=contact) for contact in CONTACTS],
    log:
        "results/logs/render/two_pair.log",
    localrule: True
    script:
        "../scripts/two_pair_render.py"


rule two_pair_all:
    input:
        "results/workspace_two_pair.nc",
        "results/curves/two_pair.json",
        rules.validate_two_pair.output,
        expand("results/figures/two_pair_{contact}.png", contact=CONTACTS),
