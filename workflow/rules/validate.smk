rule validate:
    """Check the workspace against the paper, statics, symmetry, the grounded mode and dt/2, and
    that the demonstration runs arrived (check 6: it waits for the runs); check the two-pair
    workspace against statics, direct simulation on other faces and superposition (one job: a
    job costs about 1 s to start the simulator). Only the validation rules read the checks' keys:
    editing one re-runs them alone."""
    input:
        nominal=expand("results/nominal/{contact}.nc", contact=CONTACTS),
        workspace="results/workspace.nc",
        runs=expand("results/locomotion/{run}.nc", run=LOCO_RUNS),
        two_pair_contacts=expand("results/two_pair/{contact}.nc", contact=CONTACTS),
        two_pair="results/workspace_two_pair.nc",
        prototype="results/validation/prototype.nc",
    output:
        nc="results/validation/validation.nc",
        md="results/validation/summary.md",
        html=report("results/validation/summary.html", caption="../report/validation.rst",
                    category="Validation"),
        two_pair_nc="results/validation/two_pair.nc",
        two_pair_md="results/validation/two_pair.md",
        two_pair_html=report("results/validation/two_pair.html", caption="../report/two_pair_validation.rst",
                             category="Validation"),
    params:
        cfg=cfg("validate"),
        two_pair_cfg=cfg("validate_two_pair"),
    log:
        "results/logs/validate.log",
    benchmark:
        "results/benchmarks/validate.tsv"
    priority: 42  # before the fit and `render` (5 s together): the three end side by side
    threads: 1  # a second one only while the other core idles: the figures of the runs use it
    resources:
        mem_mb=2000,
        runtime=10,
    script:
        "../scripts/validate.py"


rule validate_gravity:
    """Check the gravity-aware workspace against grounded rolls with the controller (G.1) and
    measure the free-mode assumption on flat ground (G.2, G.3)."""
    input:
        gravity="results/workspace_gravity.nc",
        nominal=expand("results/nominal/{contact}.nc", contact=CONTACTS),
    output:
        nc="results/validation/gravity.nc",
        md="results/validation/gravity.md",
        html=report("results/validation/gravity.html", caption="../report/gravity_validation.rst",
                    category="Validation"),
    params:
        cfg=cfg("validate_gravity"),
    log:
        "results/logs/validate_gravity.log",
    benchmark:
        "results/benchmarks/validate_gravity.tsv"
    priority: 50  # with the slope limit and the runs' figures: the last jobs, side by side
    threads: 1
    resources:
        mem_mb=2000,
        runtime=10,
    script:
        "../scripts/validate_gravity.py"


rule validate_prototype:
    """The paper's experiment (IV.B) with the prototype's twisted-string actuators in the grounded
    simulation, for validation check 8 and Fig. 12 simulated: #10 at 11.1 V, then #11 at 6 V,
    #10 at 6 V, and each roll's lowest voltage (prototype.rounds x prototype.points robots; about
    10 s with the defaults, once the motor kernel is compiled)."""
    output:
        nc="results/validation/prototype.nc",
    params:
        cfg=cfg("validate_prototype"),
    log:
        "results/logs/validate_prototype.log",
    benchmark:
        "results/benchmarks/validate_prototype.tsv"
    priority: 42  # before `validate`, which reads it; after the sweep and two-pair chain heads (45)
    threads: 1
    resources:
        mem_mb=1000,
        runtime=10,
    script:
        "../scripts/validate_prototype.py"
