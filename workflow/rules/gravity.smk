# The gravity-aware workspace and the slope limit: single pairs ramped slowly on flat ground and
# slopes until the robot rolls; the steepest slopes to stand, roll up and roll down (checked
# against grounded rolls by rule `validate_gravity`, workflow/rules/validate.smk).

rule gravity:
    """Gravity-aware workspace of both contact cases (one batch per contact; its figure is drawn
    by `slope_limit`)."""
    output:
        "results/workspace_gravity.nc",
    params:
        cfg=cfg("gravity"),
    log:
        "results/logs/gravity.log",
    benchmark:
        "results/benchmarks/gravity.tsv"
    priority: 35  # fills the other core once the chain to the runs has started
    threads: 1  # beside the chain to the runs: on two it ran alone (the SLURM profile sets 2)
    resources:
        mem_mb=2000,
        runtime=10,
    script:
        "../scripts/gravity.py"


rule slope_limit:
    """Steepest slopes to stand, roll uphill and roll downhill under control, per face type
    and heading: predicted from the workspaces, checked by simulation; the figures of both
    workspaces' tipping pressures and of the slope limits (one job: a job costs about 1 s to
    start the simulator, and matplotlib 0.5 s)."""
    input:
        gravity="results/workspace_gravity.nc",
        workspace="results/workspace.nc",
        two_pair="results/workspace_two_pair.nc",
    output:
        nc="results/slope_limit.nc",
        png=report("results/figures/slope_limit.png", caption="../report/gravity_slope_limit.rst",
                   category="Gravity and slopes"),
        gravity_png=report("results/figures/workspace_gravity.png", caption="../report/gravity_workspace.rst",
                           category="Gravity and slopes"),
    params:
        cfg=cfg("slope_limit"),
    log:
        "results/logs/slope_limit.log",
    benchmark:
        "results/benchmarks/slope_limit.tsv"
    priority: 50  # with the runs' figures: the last long jobs, run side by side
    threads: 1  # one thread from when its inputs exist beats two once everything else is done
    resources:
        mem_mb=2000,
        runtime=10,
    script:
        "../scripts/slope_limit.py"


rule gravity_all:
    input:
        rules.gravity.output,
        rules.slope_limit.output,
        "results/validation/gravity.md",  # made by rule `validate_gravity`
