# Rolling locomotion (paper III.C-D, IV): demonstration runs planned from the workspace and
# rolled in the grounded simulation, then Fig. 8-10, paths and an animation.
# Only the configured runs are run: Figs. 8-10 need `paper` and a slope run, the GIF its run
# (config/README.md); `runs: []` leaves out the locomotion stage.
STATE_FIGURES = "paper" in LOCO_RUNS and SLOPE_RUN in LOCO_RUNS
ANIMATION = LOCO["animation_run"] in LOCO_RUNS
LOCO_FIGURES = STATE_FIGURES or PATH_RUNS or ANIMATION  # the job of the runs' figures has work


if LOCO_RUNS:

    rule locomotion_runs:
        """The demonstration runs, one after the other: plan from the workspace (two pairs from
        the two-pair workspace), roll in the grounded simulation, repeat (one job: a job costs
        about 1 s to start the simulator, a run 1-3 s)."""
        input:
            workspace="results/workspace.nc",
            two_pair="results/workspace_two_pair.nc",
        output:
            expand("results/locomotion/{run}.nc", run=LOCO_RUNS),
        params:
            cfg=cfg("locomotion_runs"),
            runs=LOCO_RUNS,  # in the order of the outputs
        log:
            "results/logs/locomotion/runs.log",
        benchmark:
            "results/benchmarks/locomotion/runs.tsv"
        priority: 60  # the longest chain (sweep -> nominal -> runs -> figures): first
        threads: 1
        resources:
            mem_mb=1000,
            runtime=30,
        script:
            "../scripts/locomotion_runs.py"


def _state_figure(name, caption):
    return report(f"results/figures/{name}.png", caption=f"../report/{caption}.rst", category="Locomotion")


if LOCO_FIGURES:

    rule locomotion_figures:
        """Fig. 8 (stable), Fig. 9 (rolling) from the paper run and Fig. 10 (slope) from a slope
        run; the path of every run but `paper` over its terrain, from above and in 3D; the GIF of
        `animation_run` (one job: each job would pay the renderer's start-up again, about 2 s)."""
        input:
            paper=["results/locomotion/paper.nc"] if STATE_FIGURES else [],
            slope=[f"results/locomotion/{SLOPE_RUN}.nc"] if STATE_FIGURES else [],
            paths=expand("results/locomotion/{run}.nc", run=PATH_RUNS),
            animation=[f"results/locomotion/{LOCO['animation_run']}.nc"] if ANIMATION else [],
        output:
            states=[_state_figure("fig8_stable", "fig8"), _state_figure("fig9_rolling", "fig9"),
                    _state_figure("fig10_slope", "fig10")] if STATE_FIGURES else [],
            top=[report(f"results/figures/path_{run}_top.png", caption="../report/path.rst",
                        category="Locomotion", subcategory=run) for run in PATH_RUNS],
            three_d=[report(f"results/figures/path_{run}_3d.png", caption="../report/path.rst",
                            category="Locomotion", subcategory=run) for run in PATH_RUNS],
            gif=[report(f"results/figures/rolling_{LOCO['animation_run']}.gif",
                        caption="../report/animation.rst", category="Locomotion")] if ANIMATION else [],
        params:
            animation_cfg=cfg("animation"),
        log:
            "results/logs/locomotion/figures.log",
        benchmark:
            "results/benchmarks/locomotion/figures.tsv"
        priority: 55
        resources:
            mem_mb=1500,
            runtime=10,
        script:
            "../scripts/locomotion_figures.py"


rule locomotion_all:
    input:
        expand("results/locomotion/{run}.nc", run=LOCO_RUNS),
        rules.locomotion_figures.output if LOCO_FIGURES else [],
