"""Which configuration keys each stage reads (`STAGES`, `stage_config`): one table for the
Snakemake rules, the command line and the provenance of every file.

A light module (no numerical imports): the Snakefile reads it while it builds the workflow. A
rule passes `params: cfg=stage_config(config, "<stage>")`, the keys its job reads and nothing
else (PyPSA-Eur's `config_provider`), so that editing a key re-runs exactly the jobs that read
it; `tensegrity stage` passes the same, so a file's provenance does not depend on how it was
made. A key is `section.key`, or a section name for the whole section (`params`: every stage
that simulates depends on the whole robot).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import NamedTuple

# what a stage makes: a stage of kind SIMULATION runs the simulator for its numbers; VALIDATION
# and FIGURE stages read, check or draw (they may simulate to check, but nothing downstream reads
# their numbers)
SIMULATION, DATA, VALIDATION, FIGURE = "simulation", "data", "validation", "figure"

# keys shared by several stages
_SIM = ("params", "sim.dt")
_RAMP = (
    "locomotion.ramp_rate",
    "locomotion.interval",
    "locomotion.lift_tolerance",
    "locomotion.hold_time",
    "locomotion.strut_damping",
)
ROLL_KEYS = _RAMP + tuple(
    f"locomotion.{k}"
    for k in (
        "release_margin",
        "release_time",
        "catch_time",
        "settle_speed",
        "settle_time",
        "contact_tolerance",
        "combine",
        "min_alignment",
        "max_attempts",
        "max_rolls",
        "arrive_tolerance",
        "escape_attempts",
        "lookahead",
        "optimised_actions",
        "cable_actions",
        "brake",
        "brake_margin",
        "brake_rate",
        "brake_release_time",
    )
)
_SCENARIOS = tuple(
    f"locomotion.{k}"
    for k in ("goal_distance", "goal_heading", "slope_angle", "terrain_seed", "terrain_amplitude", "terrain_spacing")
)
_GRAVITY = (
    "gravity.pairs",
    "gravity.slopes",
    "gravity.headings",
    "gravity.max_pressure",
    "gravity.settle",
    "gravity.grid_step",
)
_TWO_PAIR = ("two_pair.levels", "two_pair.hold", "two_pair.discard", "two_pair.record_every")


class Stage(NamedTuple):
    """A stage: `function` "module:function" of `tensegrity.stages`, the `rule` whose job runs
    it, its `kind` and the configuration `keys` it reads."""

    function: str
    rule: str
    kind: str
    keys: tuple[str, ...]


STAGES: dict[str, Stage] = {
    "sweep": Stage(
        "sweep:sweep",
        "sweep",
        SIMULATION,
        (
            *_SIM,
            "sim.record_every",
            "sweep.pairs",
            "sweep.levels",
            "sweep.hold",
            "sweep.settle",
            "sweep.mode",
            "sweep.node_stride",
        ),
    ),
    "nominal": Stage("nominal:nominal", "nominal", DATA, ("nominal.discard", "nominal.method")),
    # the same rule under nominal.method statics: no sweep, the robot's equilibria
    "nominal_statics": Stage(
        "nominal:nominal_statics", "nominal", SIMULATION, ("params", "sweep.pairs", "sweep.levels", "nominal.method")
    ),
    "workspace": Stage("nominal:workspace", "nominal", DATA, ()),
    "curves": Stage("fit:curves", "fit", DATA, ("fit.max_degree", "fit.spline_knots", "fit.folds")),
    "curves_json": Stage("fit:curves_json", "fit", DATA, ()),
    "two_pair_surfaces": Stage("fit:two_pair_surfaces", "fit", DATA, ("fit.max_degree", "fit.folds")),
    "two_pair": Stage("two_pair:two_pair", "two_pair", SIMULATION, (*_SIM, *_TWO_PAIR, "two_pair.pairs")),
    "two_pair_map": Stage("two_pair:two_pair_map", "two_pair", DATA, ()),
    "gravity": Stage("gravity:gravity", "gravity", SIMULATION, (*_SIM, *_RAMP, *_GRAVITY)),
    "slope_limit": Stage(
        "gravity:slope_limit",
        "slope_limit",
        SIMULATION,
        (
            *_SIM,
            *_RAMP,
            *_GRAVITY,
            "gravity.iterations",
            "gravity.free_step",
            "gravity.multi_iterations",
            "gravity.cable_iterations",
            "locomotion.actuation_margin",
        ),
    ),
    "gravity_figure": Stage("gravity:gravity_figure", "slope_limit", FIGURE, ()),
    "locomotion_runs": Stage(
        "locomotion:locomotion_runs", "locomotion_runs", SIMULATION, (*_SIM, *ROLL_KEYS, *_SCENARIOS)
    ),
    "state_figures": Stage("locomotion:state_figures", "locomotion_figures", FIGURE, ()),
    "path_figures": Stage("locomotion:path_figures", "locomotion_figures", FIGURE, ()),
    "animation": Stage(
        "locomotion:animation", "locomotion_figures", FIGURE, ("locomotion.animation_fps", "locomotion.animation_speed")
    ),
    "robot_figures": Stage("render:robot_figures", "render", FIGURE, ("params",)),
    "cog_cloud": Stage("render:cog_cloud", "render", FIGURE, ()),
    "workspace_figure": Stage("render:workspace_figure", "render", FIGURE, ()),
    "two_pair_figure": Stage("render:two_pair_figure", "render", FIGURE, ()),
    "page": Stage("page:page", "page", FIGURE, ()),
    "validate": Stage(
        "validate:validate",
        "validate",
        VALIDATION,
        (
            *_SIM,
            "sim.record_every",
            "sweep.levels",
            "sweep.hold",
            "sweep.settle",
            "sweep.mode",
            "nominal.discard",
            "validate",
        ),
    ),
    "validate_two_pair": Stage(
        "validate:validate_two_pair",
        "validate",
        VALIDATION,
        (
            *_SIM,
            *_TWO_PAIR,
            "two_pair.check_combos",
            "two_pair.check_faces",
            "two_pair.tolerance",
            "validate.averaging_tolerance",
        ),
    ),
    "validate_gravity": Stage(
        "validate:validate_gravity",
        "validate_gravity",
        VALIDATION,
        (
            *_SIM,
            *ROLL_KEYS,
            "gravity.max_pressure",
            "gravity.settle",
            "gravity.validate_slopes",
            "gravity.tip_tolerance",
        ),
    ),
    "validate_prototype": Stage(
        "prototype:validate_prototype",
        "validate_prototype",
        VALIDATION,
        ("params", "sim.dt", "actuator.twisted_string", "prototype"),
    ),
    "prototype_figure": Stage("prototype:prototype_figure", "render_prototype", FIGURE, ()),
    "study_chunk": Stage("study:study_chunk", "study_chunk", SIMULATION, (*_SIM, *ROLL_KEYS)),
    "study_merge": Stage("study:study_merge", "study_merge", DATA, ()),
    "study_analyse": Stage("study:study_analyse", "study_analyse", DATA, ()),
    "simulate": Stage("simulate:simulate", "", SIMULATION, (*_SIM, "sim.record_every")),
    "calibrate": Stage("calibrate:calibrate", "", SIMULATION, (*_SIM, "actuator.twisted_string")),
}


# the stages that run with the twisted-string actuator (issue 31; docs/design.md §10): the workspace
# pipeline in volts, the gravity-aware workspace and slope limit, the validation (each check in
# volts or not evaluated, saying why), the paper's experiment (which runs the prototype whatever
# actuator.kind), the locomotion runs in volts (design.md §6), and `tensegrity simulate` and
# `calibrate` (a run in volts: voltage_cmd). The others (studies, ...) refuse it by name.
VOLTS = frozenset(
    (
        *("sweep", "nominal", "workspace", "curves", "curves_json", "two_pair", "two_pair_map"),
        *("two_pair_surfaces", "robot_figures", "cog_cloud", "workspace_figure", "two_pair_figure"),
        *("gravity", "slope_limit", "gravity_figure", "validate", "validate_two_pair", "validate_gravity"),
        *("validate_prototype", "prototype_figure", "simulate", "calibrate"),
        *("locomotion_runs", "state_figures", "path_figures", "animation", "page"),  # rolls in volts
    )
)


def actuator_kind(cfg: Mapping) -> str:
    """The configured actuator.kind; pneumatic where `cfg` has no `actuator` section (a stage's
    keys of a pneumatic configuration: `stage_config` leaves the section out)."""
    return str(cfg.get("actuator", {}).get("kind", "pneumatic"))


def actuator_error(cfg: Mapping, stage: str) -> str | None:
    """Why `stage` (a name of `STAGES`, or words naming a command) cannot run with the actuator
    of `cfg`, naming the key; None if it can."""
    kind = actuator_kind(cfg)
    if kind == "pneumatic" or stage in VOLTS:
        return None
    rule = STAGES[stage].rule if stage in STAGES else ""
    what = f"stage {stage}" + (f" (rule {rule})" if rule else "") if stage in STAGES else stage
    return (
        f"config key actuator.kind: {kind!r} runs the workspace pipeline in volts (sweeps, nominal, "
        f"curves, workspaces, gravity and slope limit, validation, locomotion, their figures), but {what} "
        "runs the pneumatic muscle only (studies in volts are not built yet); use actuator.kind: "
        "pneumatic for it"
    )


def stage_config(cfg: Mapping, stage: str) -> dict:
    """The keys of the resolved configuration `cfg` that `stage` reads (`STAGES`), as nested
    sections: e.g. {"nominal": {"discard": 0.2}}. KeyError naming the key if `cfg` lacks one.
    With an actuator other than the pneumatic muscle every stage reads the `actuator` section
    too; a pneumatic configuration leaves it out, so that its files stay as they were."""
    if stage not in STAGES:
        raise ValueError(f"unknown stage {stage!r}: use one of {sorted(STAGES)}")
    out: dict = {}
    for key in STAGES[stage].keys:
        section, _, name = key.partition(".")
        if section not in cfg or (name and name not in cfg[section]):
            raise KeyError(f"stage {stage}: the configuration has no key {key}")
        if name:
            out.setdefault(section, {})[name] = cfg[section][name]
        else:
            out[section] = cfg[section]
    if actuator_kind(cfg) != "pneumatic":
        out["actuator"] = cfg["actuator"]
    return out


def readers(key: str) -> list[str]:
    """The stages that read config key `key` (`section.key`): those listing it or its section."""
    section = key.partition(".")[0]
    return [s for s, st in STAGES.items() if key in st.keys or section in st.keys]
