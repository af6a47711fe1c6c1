"""The configuration sections each stage depends on (`STAGE_CONFIG`, `stage_config`).

A light module (no numerical imports): the Snakefile reads it while it builds the workflow.
"""
from __future__ import annotations

# The configuration sections each stage depends on: the Snakemake rules pass exactly these as
# `params: cfg=...` (so that editing another section re-runs nothing) and `tensegrity stage`
# stores the same, so a file's provenance does not depend on how it was made.
STAGE_CONFIG: dict[str, tuple[str, ...]] = {
    "sweep": ("params", "sim", "sweep"),
    "nominal": ("nominal",),
    "fit": ("fit",),
    "map": (),
    "render_robot": ("params",),
    "validate": ("params", "sim", "sweep", "nominal", "validate"),
    "locomotion_run": ("params", "sim", "locomotion"),
    "study": ("params", "sim", "locomotion"),  # design studies (study_stages)
    "two_pair": ("params", "sim", "two_pair"),  # the two-pair workspace (two_pair_stages)
    "two_pair_map": (),
    "two_pair_curves": ("fit",),
    "validate_two_pair": ("params", "sim", "two_pair"),
    "gravity": ("params", "sim", "locomotion", "gravity"),  # gravity-aware workspace (gravity_stages)
    "slope_limit": ("params", "sim", "locomotion", "gravity"),
    "validate_gravity": ("params", "sim", "locomotion", "gravity"),
}


def stage_config(cfg: dict, stage: str) -> dict:
    """The sections of the resolved configuration `cfg` that `stage` depends on (STAGE_CONFIG);
    a locomotion run (and a study) leaves out the list of runs and the animation settings; the
    gravity-aware workspace and the slope limit keep only the ramp, its hold and the strut damping
    of the rolls (locomotion.ramp_rate, interval, lift_tolerance, hold_time, strut_damping)."""
    if stage not in STAGE_CONFIG:
        raise ValueError(f"unknown stage {stage!r}: use one of {sorted(STAGE_CONFIG)}")
    out = {k: cfg[k] for k in STAGE_CONFIG[stage]}
    if stage in ("gravity", "slope_limit"):  # the ramp of the rolls, nothing else of locomotion
        out["locomotion"] = {k: out["locomotion"][k] for k in ("ramp_rate", "interval", "lift_tolerance",
                                                                "hold_time", "strut_damping")}
    if stage in ("locomotion_run", "study"):
        out["locomotion"] = {k: v for k, v in out["locomotion"].items()
                             if k != "runs" and not k.startswith("animation_")}
    return out
