# Rolling locomotion (paper III.C-D, IV): demonstration runs planned from the
# workspace and rolled in the grounded simulation, then Fig. 8-10, paths and an animation.
# Rules call tensegrity.stages (locomotion_run and the figure stages).

LOCO = config["locomotion"]
LOCO_RUNS = LOCO["runs"]
PATH_RUNS = [r for r in LOCO_RUNS if r != "paper"]
SLOPE_RUN = "slope_down" if "slope_down" in LOCO_RUNS or "slope_up" not in LOCO_RUNS else "slope_up"
# Only the configured runs are run: Figs. 8-10 need `paper` and a slope run, the GIF its run
# (config/README.md); `runs: []` leaves out the locomotion stage.
STATE_FIGURES = "paper" in LOCO_RUNS and SLOPE_RUN in LOCO_RUNS
ANIMATION = LOCO["animation_run"] in LOCO_RUNS


rule locomotion_run:
    """One demonstration run: plan from the workspace (two pairs from the two-pair workspace),
    roll in the grounded simulation, repeat."""
    input:
        workspace="results/workspace.nc",
        two_pair="results/workspace_two_pair.nc",
    output:
        "results/locomotion/{run}.nc",
    params:
        cfg=stage_config(config, "locomotion_run"),
    log:
        "results/logs/locomotion/{run}.log",
    benchmark:
        "results/benchmarks/locomotion/{run}.tsv"
    wildcard_constraints:
        run="|".join(LOCO_RUNS) or "^$",  # the configured runs only
    priority: 30  # the runs and their figures end the workflow: before the other figures
    threads: 1
    resources:
        mem_mb=1000,
        runtime=30,
    script:
        "../scripts/locomotion_run.py"


rule locomotion_states:
    """Fig. 8 (stable), Fig. 9 (rolling) from the paper run; Fig. 10 (slope) from a slope run."""
    input:
        paper="results/locomotion/paper.nc",
        slope=f"results/locomotion/{SLOPE_RUN}.nc",
    output:
        fig8=report("results/figures/fig8_stable.png", caption="../report/fig8.rst", category="Locomotion"),
        fig9=report("results/figures/fig9_rolling.png", caption="../report/fig9.rst", category="Locomotion"),
        fig10=report("results/figures/fig10_slope.png", caption="../report/fig10.rst", category="Locomotion"),
    log:
        "results/logs/locomotion/states.log",
    priority: 30
    localrule: True
    script:
        "../scripts/locomotion_states.py"


if PATH_RUNS:

    rule locomotion_path:
        """The path of every run but `paper` over its terrain, from above and in 3D (one job for
        all runs: each job would pay the renderer's start-up again)."""
        input:
            expand("results/locomotion/{run}.nc", run=PATH_RUNS),
        output:
            top=[report(f"results/figures/path_{run}_top.png", caption="../report/path.rst",
                        category="Locomotion", subcategory=run) for run in PATH_RUNS],
            three_d=[report(f"results/figures/path_{run}_3d.png", caption="../report/path.rst",
                            category="Locomotion", subcategory=run) for run in PATH_RUNS],
        log:
            "results/logs/locomotion/paths.log",
        priority: 30
        localrule: True
        script:
            "../scripts/locomotion_path.py"


rule locomotion_animation:
    """An animation (GIF) of one run."""
    input:
        "results/locomotion/{run}.nc",
    output:
        report("results/figures/rolling_{run}.gif", caption="../report/animation.rst",
               category="Locomotion"),
    params:
        fps=LOCO["animation_fps"],
        speed=LOCO["animation_speed"],
    log:
        "results/logs/locomotion/animation_{run}.log",
    priority: 30
    benchmark:
        "results/benchmarks/locomotion/animation_{run}.tsv"
    wildcard_constraints:
        run="|".join(LOCO_RUNS) or "^$",  # the configured runs only
    resources:
        mem_mb=1500,
        runtime=10,
    script:
        "../scripts/locomotion_animation.py"


rule locomotion_all:
    input:
        expand("results/locomotion/{run}.nc", run=LOCO_RUNS),
        rules.locomotion_states.output if STATE_FIGURES else [],
        expand("results/figures/path_{run}_{view}.png", run=PATH_RUNS, view=["top", "3d"]),
        [f"results/figures/rolling_{LOCO['animation_run']}.gif"] if ANIMATION else [],
