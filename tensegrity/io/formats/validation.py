"""The validation file of the workspace (docs/datasets.md, "Validation"): every number of every
check, with units and long names, as a netCDF dataset built from the checks' results.

- results/validation/validation.nc: `workspace_validation_dataset` (`validation.checks`).

The two-pair and gravity validation files: `two_pair_validation`, `gravity_validation`.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike

from ... import paper
from ...physics import topology as topo
from ...physics.topology import CONTACTS
from ...validation import summary
from ...validation.averaging import AveragingResult
from ...validation.checks import MappingResult, StaticsResult, TimestepResult
from ...validation.common import FAIL, PASS, SKIP, Result
from ...validation.grounded import GroundedResult
from ...validation.paper import PaperResult
from ...validation.runs import RunsResult
from .. import datasets

AXES = ("x", "y", "z")
_CP = ("contact", "pair")  # dimensions of the per-pair numbers
_CPP = (*_CP, "pressure")  # ... per level
_CPPA = (*_CPP, "axis")  # ... per level and axis


def _paper_vars(r: PaperResult) -> dict:
    return {
        "migration": datasets.var(
            _CP,
            r.migration,
            "m",
            f"in-plane distance of the nominal CoG from the unactuated CoG at {r.ranking_pressure:g} MPa",
            pressure_MPa=r.ranking_pressure,
        ),
        "tip_pressure": datasets.var(
            _CP,
            r.tip_pressure,
            "MPa",
            "least pressure at which the CoG projection leaves the support triangle (NaN: never)",
        ),
        "tip_edge": datasets.var(
            (*_CP, "end"), r.tip_edge, "1", "nodes of the edge the CoG projection crosses first (0: none)"
        ),
        "paper_tip_pressure": datasets.var(
            (),
            paper.TIP_PRESSURE,
            "MPa",
            "paper's pressure at which #10 rolls the robot off (9,10,12) (III.C)",
            tolerance_MPa=r.tip_tolerance,
        ),
        "orbit_pairs": datasets.var(("orbit", "member"), r.orbit_pairs, "1", "pairs of each 3-fold orbit of (9,10,12)"),
        "orbit_difference": datasets.var(
            ("orbit", "pressure"),
            r.orbit_difference,
            "m",
            "largest difference between the orbit members' CoG, each seen from the "
            "corner its rotation carries the reference vertex to",
            goal_m=r.orbit_tolerance,
        ),
        "orbit_magnitude_spread": datasets.var(
            ("orbit", "pressure"),
            r.orbit_magnitude_spread,
            "m",
            "spread of the orbit members' in-plane CoG distance from the centroid",
        ),
    }


def _statics_vars(r: StaticsResult) -> dict:
    return {
        "statics_cog": datasets.var(
            (*_CP, "statics_pressure", "axis"),
            r.cog,
            "m",
            "CoG of the free-mode static equilibrium in the support frame",
        ),
        "statics_difference": datasets.var(
            (*_CP, "statics_pressure"),
            r.difference,
            "m",
            "distance between the nominal CoG and the static-equilibrium CoG",
            goal_m=r.tolerance,
        ),
    }


def _mapping_vars(r: MappingResult) -> dict:
    dims = ("sample_face", "pair", "pressure")
    return {
        "sample_face_type": (
            ("sample_face",),
            np.array([str(topo.FACE_TYPES[f - 1]) for f in r.faces]),
            {"long_name": "kind of the sample face"},
        ),
        "direct_cog": datasets.var(
            (*dims, "axis"),
            r.cog,
            "m",
            "nominal CoG of a direct simulation standing on the sample face, in its support frame",
        ),
        "mapping_difference": datasets.var(
            dims,
            r.difference,
            "m",
            "distance between the mapped and the directly simulated nominal CoG",
            goal_m=r.tolerance,
        ),
        "mapping_support_difference": datasets.var(
            dims,
            r.support_difference,
            "m",
            "largest corner distance between the mapped and the directly simulated support triangle",
            goal_m=r.tolerance,
        ),
    }


def _grounded_vars(r: GroundedResult) -> dict:
    v = datasets.var
    return {
        "grounded_cog": v(
            _CPPA, r.cog, "m", "nominal CoG in the grounded mode, support frame (NaN once the robot rolled)"
        ),
        "grounded_shift": v(
            _CPPA,
            r.shift,
            "m",
            "grounded minus free nominal CoG, support frame (NaN once the robot rolled)",
            goal_m=r.tolerance,
        ),
        "grounded_margin_change": v(
            _CPP, r.margin_change, "m", "grounded minus free margin of the CoG projection (NaN once rolled)"
        ),
        "grounded_rolled": v(
            _CPP,
            r.rolled.astype(np.int8),
            "1",
            "1 if the grounded robot has left its contact face by the end of the level",
        ),
        "grounded_face": v(_CPP, r.end_face, "1", "face of the three lowest nodes at the end of the level (0: none)"),
        "grounded_roll_pressure": v(
            _CP, r.roll_pressure, "MPa", "level at which the grounded robot first left its face (NaN: never)"
        ),
        "grounded_roll_face": v(_CP, r.roll_face, "1", "face the grounded robot rolled onto (0: none)"),
        "free_roll_pressure": v(
            _CP,
            r.free_roll_pressure,
            "MPa",
            "first level at which the free nominal CoG projection is outside the triangle",
        ),
        "free_roll_face": v(_CP, r.free_roll_face, "1", "face across the edge the free CoG projection crosses"),
        "grounded_settle": v((), r.settle, "s", "time on the ground at zero pressure before the first level"),
    }


def _timestep_vars(r: TimestepResult) -> dict:
    return {
        "half_dt_cog": datasets.var(
            _CPPA, r.cog, "m", "nominal CoG at half the time step, support frame", dt_s=r.dt / 2
        ),
        "timestep_difference": datasets.var(
            _CPP, r.difference, "m", "distance between the nominal CoG at dt and at dt/2", goal_m=r.tolerance
        ),
    }


def _runs_vars(r: RunsResult) -> dict:
    if not r.runs:
        return {}
    return {
        "run_outcome": (
            ("run",),
            np.array(r.outcome, dtype=str),
            {
                "long_name": "how the demonstration run ended (arrived, stuck, no_contact, "
                "step_limit, off_terrain, sim_error)"
            },
        ),
        "run_arrived": datasets.var(
            ("run",), r.arrived.astype(np.int8), "1", "1 if the demonstration run arrived, else 0"
        ),
        "run_rolls": datasets.var(("run",), r.rolls, "1", "rolls of the demonstration run"),
        "run_distance_to_goal": datasets.var(
            ("run",),
            r.distance,
            "m",
            "horizontal distance of the final CoG from the goal (NaN: a run over given edges)",
        ),
    }


def _averaging_vars(r: AveragingResult) -> dict:
    long = "estimated averaging error of the nominal CoG (results/nominal/{contact}.nc averaging_error)"
    return {"averaging_error": datasets.var(_CPP, r.error, "m", long, goal_m=r.tolerance)}


# result type -> (its variables, the variables where NaN means 'not computed')
_VARIABLES = {
    PaperResult: (_paper_vars, ("migration", "tip_pressure", "orbit_difference", "orbit_magnitude_spread")),
    StaticsResult: (_statics_vars, ("statics_cog", "statics_difference")),
    MappingResult: (_mapping_vars, ("direct_cog", "mapping_difference", "mapping_support_difference")),
    GroundedResult: (
        _grounded_vars,
        ("grounded_cog", "grounded_shift", "grounded_margin_change", "grounded_roll_pressure", "free_roll_pressure"),
    ),
    TimestepResult: (_timestep_vars, ("half_dt_cog", "timestep_difference")),
    RunsResult: (_runs_vars, ("run_distance_to_goal",)),
    AveragingResult: (_averaging_vars, ("averaging_error",)),
}


def variables(result: Result) -> tuple[dict, tuple[str, ...]]:
    """One check's numbers as netCDF variable specs, name -> (dims, values, attrs with units and
    long_name), and the names of those that may hold NaN (not computed); nothing for a check
    that raised."""
    for kind, (make, allow_nan) in _VARIABLES.items():
        if isinstance(result, kind):
            return make(result), allow_nan
    return {}, ()


def workspace_validation_dataset(
    results: Sequence[Result], levels: ArrayLike, faces: Sequence[int], statics_pressures: Sequence[float]
) -> tuple[xr.Dataset, list[str]]:
    """All checks' numbers and verdicts as one dataset, and the names of the variables that may
    hold NaN. levels (P,) MPa, the sample faces (F,) of check 3 and the pressures (S,) MPa of
    check 2 are coordinates. Verdicts are on the dimension `check`: status (string), passed
    (1/0/-1) and the texts of `summary.verdicts`."""
    rows = [row for r in results for row in summary.verdicts(r)]
    data, allow = {}, []
    for r in results:
        more, nan = variables(r)
        data.update(more)
        allow += list(nan)
    data["passed"] = datasets.var(
        ("check",),
        np.array([1 if r.status == PASS else 0 if r.status == FAIL else -1 for r in rows], np.int8),
        "1",
        "1: passed, 0: failed, -1: not evaluated",
    )
    for key in ("statement", "measured", "reference", "status"):
        data[key] = (
            ("check",),
            np.array([getattr(r, key) for r in rows], dtype=str),
            {
                "long_name": {
                    "statement": "what is checked",
                    "measured": "measured value, with units",
                    "reference": "the paper's value or the goal",
                    "status": f"{PASS}, {FAIL} or {SKIP}",
                }[key]
            },
        )
    coords = {
        "check": ("check", np.array([r.id for r in rows], dtype=str), {"long_name": "check number"}),
        "contact": ("contact", np.array(CONTACTS), {"long_name": "contact case"}),
        "pair": ("pair", np.arange(1, topo.N_PAIRS + 1), {"units": "1", "long_name": "actuator pair number"}),
        "pressure": ("pressure", np.asarray(levels, float), {"units": "MPa", "long_name": "muscle pressure"}),
        "statics_pressure": (
            "statics_pressure",
            np.asarray(statics_pressures, float),
            {"units": "MPa", "long_name": "pressure of the statics check"},
        ),
        "sample_face": (
            "sample_face",
            np.asarray(faces, np.int64),
            {"units": "1", "long_name": "face number of the mapping check"},
        ),
        "axis": ("axis", np.array(AXES), {"long_name": "support-frame axis"}),
        "end": ("end", np.array([1, 2]), {"units": "1", "long_name": "edge end"}),
    }
    run_results = [r for r in results if isinstance(r, RunsResult)]
    if run_results:
        coords["run"] = (
            "run",
            np.array(run_results[0].runs, dtype=str),
            {"long_name": "demonstration run (results/locomotion/{run}.nc)"},
        )
    if "orbit_pairs" in data:
        n_orb, size = data["orbit_pairs"][1].shape
        coords["orbit"] = ("orbit", np.arange(1, n_orb + 1), {"units": "1", "long_name": "3-fold orbit number"})
        coords["member"] = ("member", np.arange(1, size + 1), {"units": "1", "long_name": "orbit member"})
    used = {d for v in data.values() for d in v[0]}
    ds = xr.Dataset(data, coords={k: v for k, v in coords.items() if k in used})
    return ds, [a for a in allow if a in ds]
