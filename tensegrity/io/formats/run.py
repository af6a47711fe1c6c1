"""The locomotion runs' files, results/locomotion/{run}.nc (docs/design.md §5, docs/datasets.md):
the builder (`run_dataset`, written by `datasets.write(..., allow_nan=RUN_ALLOW_NAN)`), the
readers the figures use (`terrain_from_dataset`, `run_sample`) and the one validation uses
(`read_run_summaries`).
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import xarray as xr

from ...physics import topology as topo
from ...physics.terrain import Terrain
from ...validation.runs import RunSummary
from .. import datasets
from ..datasets import strut_radius
from . import actuation

if TYPE_CHECKING:  # imported where used: importing io.run_formats loads no simulator (numba)
    from ...locomotion.outcome import Run
    from ...physics.params import Params

__all__ = [
    "RUN_ALLOW_NAN",
    "run_dataset",
    "commands",
    "terrain_from_dataset",
    "run_sample",
    "run_name",
    "run_summary",
    "read_run_summaries",
    "not_arrived",
]

RUN_ALLOW_NAN = ("planned_pressure", "tip_pressure", "goal")  # NaN: no roll predicted / none / no goal


def run_dataset(run: Run, terrain: Terrain, params: Params, name: str = "", unit: str = "MPa") -> xr.Dataset:
    """A run as an xarray Dataset (docs/design.md §5, results/locomotion/{run}.nc): samples
    (time), steps (step, with the chosen pair(s) and pressures; none in a run that made no roll,
    e.g. stuck with no roll simulated ahead acceptable), the faces visited (visit: the start face,
    then the face after each roll), the
    terrain and the robot's strut length and radius (of `params`), with units and long names.
    Nothing time-dependent (no wall time) is stored. A run of the twisted strings (`unit` V,
    `RollSettings.unit`) records the motor voltages applied as `voltage_cmd(time, pair)` V
    instead of `pressure`, and says V in the step's levels (`actuation.relabel`). A run that made a
    per-cable action (`locomotion.cable_actions`) has its levels and weights per cable (dim `cable`).
    Write it with `datasets.write(..., allow_nan=RUN_ALLOW_NAN)`."""
    var = datasets.var
    rec, steps = run.record, run.steps
    n = len(steps)
    used = [st.used for st in steps]
    slots = max([2] + [len(r.pairs) for r in used])  # more than two: an optimised action's pairs
    pairs = np.zeros((n, slots), np.int64)
    for i, r in enumerate(used):
        pairs[i, : len(r.pairs)] = r.pairs
    weighted = {}  # only if a step rolled with a weight vector: pairs-only runs stay as they were
    per = "cable" if rec.pressure.shape[1] == topo.N_CABLES else "pair"  # a per-cable action made: per cable
    if any(r.weights is not None for r in used):
        w = np.array(
            [np.eye(12)[np.asarray(r.pairs, int) - 1].sum(0) if r.weights is None else r.weights for r in used]
        )
        w = np.array([topo.cable_levels(x) if per == "cable" else x for x in w]).reshape(n, -1)
        weighted["step_weight"] = var(
            ("step", per), w, "1", f"weights of the step's action: {per} pressures level x weight (largest 1)"
        )
    edge = np.array([st.plan.edge for st in steps], np.int64).reshape(n, 2)
    kind = {actuation.units(k): k for k in actuation.UNITS}[unit]
    if kind == actuation.PNEUMATIC:
        command = {"pressure": var(("time", per), rec.pressure, "MPa", f"pressure applied to each actuator {per}")}
    else:
        command = {
            "voltage_cmd": var(
                ("time", per),
                rec.pressure,
                "V",
                f"motor voltage applied to each actuator {per} (negative: unwinding the strands)",
            )
        }
    ds = xr.Dataset(
        {
            "nodes": var(("time", "node", "axis"), rec.nodes, "m", "node positions, world frame"),
            "cog": var(("time", "axis"), rec.cog, "m", "centre of gravity, world frame"),
            **command,
            "contact_face": var(("time",), rec.face, "1", "face resting on the terrain (0: none)"),
            "face": var(("step",), np.array([st.face for st in steps], np.int64), "1", "face the step started on"),
            "next_face": var(
                ("step",),
                np.array([st.face_after or 0 for st in steps], np.int64),
                "1",
                "face the robot settled on after the step (0: none)",
            ),
            "predicted_face": var(
                ("step",),
                np.array([st.plan.next_face for st in steps], np.int64),
                "1",
                "face the plan predicted (across the planned edge)",
            ),
            "step_pair": var(
                ("step", "slot"), pairs, "1", "actuator pair(s) driven in the step's rolling attempt (0: none)"
            ),
            "planned_pressure": var(
                ("step",),
                np.array([st.plan.pressure for st in steps]),
                "MPa",
                "least rolling pressure predicted by the workspace (NaN: no roll predicted)",
            ),
            "tip_pressure": var(
                ("step",),
                np.array([r.tip_pressure for r in used]),
                "MPa",
                "pressure held when the robot tipped in the simulation (NaN: it did not roll)",
            ),
            "peak_pressure": var(
                ("step",),
                np.array([r.peak_pressure for r in used]),
                "MPa",
                "highest pressure applied in the step's last attempt",
            ),
            "edge": var(("step", "end"), edge, "1", "nodes of the planned edge"),
            "alignment": var(
                ("step",),
                np.array([st.plan.alignment for st in steps]),
                "1",
                "cosine between the planned edge's outward direction and the target direction",
            ),
            "reach": var(
                ("step",),
                np.array([st.plan.reach for st in steps]),
                "m",
                "predicted margin at the workspace's highest level (negative: outside)",
            ),
            "attempts": var(
                ("step",), np.array([len(st.attempts) for st in steps], np.int64), "1", "candidates tried in the step"
            ),
            "t_start": var(("step",), np.array([st.attempts[0].t_start for st in steps]), "s", "start of the step"),
            "t_end": var(("step",), np.array([r.t_end for r in used]), "s", "end of the step (settled)"),
            "position": var(
                ("step", "axis"),
                np.array([r.cog_after for r in used]).reshape(n, 3),
                "m",
                "centre of gravity after the step, world frame",
            ),
            **weighted,
            "faces": var(("visit",), np.array(run.faces, np.int64), "1", "contact faces visited, in order"),
            "goal": var(("axis",), run.goal, "m", "goal, world frame (NaN: a run over given edges)"),
            "start": var(("axis",), run.start, "m", "centre of gravity at the start, world frame"),
            "terrain_heights": var(
                ("tx", "ty"), terrain.heights, "m", "height field of the terrain (kind heightfield)"
            ),
            **datasets.geometry_vars(float(params.strut_length), float(params.strut_radius)),
        },
        coords={
            "time": ("time", rec.t, {"units": "s", "long_name": "time"}),
            "node": ("node", np.arange(1, 13), {"units": "1", "long_name": "node number"}),
            per: (per, np.arange(1, rec.pressure.shape[1] + 1), {"units": "1", "long_name": f"actuator {per} number"}),
            "axis": ("axis", ["x", "y", "z"], {"units": "1", "long_name": "world axis"}),
            "step": ("step", np.arange(1, n + 1), {"units": "1", "long_name": "step number"}),
            "slot": (
                "slot",
                np.arange(1, slots + 1),
                {"units": "1", "long_name": "pair slot (two pairs when combined)"},
            ),
            "end": ("end", [1, 2], {"units": "1", "long_name": "edge end"}),
            "visit": ("visit", np.arange(1, len(run.faces) + 1), {"units": "1", "long_name": "visit number"}),
        },
        attrs={
            "run": name,
            "outcome": run.outcome,
            "message": run.message,
            "rolls": run.rolls,
            "terrain_kind": terrain.kind,
            "terrain_normal": terrain.normal,
            "terrain_offset": float(terrain.offset),
            "terrain_origin": np.asarray(terrain.origin, float),
            "terrain_spacing": float(terrain.spacing),
        },
    )
    return actuation.relabel(ds, kind)


def commands(ds: xr.Dataset) -> tuple[np.ndarray, str]:
    """The levels (time, pair) applied in a run dataset and their unit: `pressure` MPa, or in a
    run of the twisted strings `voltage_cmd` V."""
    da = ds["voltage_cmd"] if "voltage_cmd" in ds else ds["pressure"]
    return da.values, str(da.attrs.get("units", "MPa"))


def terrain_from_dataset(ds: xr.Dataset) -> Terrain:
    """The terrain a run dataset (results/locomotion/{run}.nc) was simulated on: kind, normal,
    offset (m), origin (m), spacing (m) from the attributes, heights (m) from terrain_heights."""
    return Terrain(
        kind=str(ds.attrs["terrain_kind"]),
        normal=np.asarray(ds.attrs["terrain_normal"], float),
        offset=float(ds.attrs["terrain_offset"]),
        origin=tuple(np.asarray(ds.attrs["terrain_origin"], float)),
        spacing=float(ds.attrs["terrain_spacing"]),
        heights=ds["terrain_heights"].values,
    )


def run_sample(ds: xr.Dataset, terrain: Terrain, step: int, which: str) -> tuple[int, np.ndarray]:
    """Index and nodes (12, 3) m of a sample of step `step` (1-based) of a run dataset:
    'stable' or 'rolling' (`locomotion.outcome.sample`); ValueError naming the run if the step
    never leaves its face or the run has no such step (a run that made no roll has none)."""
    from ...locomotion.outcome import sample

    if not 1 <= step <= ds.sizes.get("step", 0):
        raise ValueError(f"run {ds.attrs.get('run')!r} has {ds.sizes.get('step', 0)} step(s), not a step {step}")
    t = ds["time"].values
    k0 = int(np.searchsorted(t, ds["t_start"].values[step - 1]))
    k1 = int(np.searchsorted(t, ds["t_end"].values[step - 1]))
    try:
        k = sample(
            ds["nodes"].values,
            commands(ds)[0].max(axis=1),
            k0,
            k1,
            int(ds["face"].values[step - 1]),
            float(ds["tip_pressure"].values[step - 1]),
            terrain,
            strut_radius(ds),
            which,
        )
    except ValueError:
        raise ValueError(f"step {step} of run {ds.attrs.get('run')!r} never leaves its face") from None
    return k, ds["nodes"].values[k]


def run_name(path: str | os.PathLike) -> str:
    """The run a file results/locomotion/{run}.nc holds: its stem."""
    return Path(path).stem


def run_summary(ds: xr.Dataset) -> RunSummary:
    """What validation check 6 reads of a run dataset: the attributes outcome (default
    'unknown'), message and rolls, the goal (3,) m and the last sample of cog (3,) m (NaN where
    the file holds none)."""
    goal = np.asarray(ds["goal"].values, float) if "goal" in ds else np.full(3, np.nan)
    cog = np.asarray(ds["cog"].values, float) if "cog" in ds else np.empty((0, 3))
    return RunSummary(
        str(ds.attrs.get("outcome", "unknown")),
        str(ds.attrs.get("message", "")),
        int(ds.attrs.get("rolls", 0)),
        goal,
        cog[-1] if cog.shape[0] else np.full(3, np.nan),
    )


def read_run_summaries(paths: Iterable[str | os.PathLike]) -> dict[str, RunSummary]:
    """The run files `paths` as run name -> `RunSummary` (validation check 6)."""
    out = {}
    for p in paths:
        ds = datasets.read(p)  # a corrupted or missing file is named in the error
        out[str(ds.attrs.get("run") or run_name(p))] = run_summary(ds)
    return out


def not_arrived(paths: Iterable[str | os.PathLike]) -> list[tuple[str, str, str]]:
    """(run, outcome, message) of every existing run file among `paths` whose run did not
    arrive; files that do not exist are left out (a workflow that did not make them). Reads
    the global attributes only (checked against the file's digest)."""
    out = []
    for p in paths:
        if not Path(p).is_file():
            continue
        attrs = datasets.read_attrs(p)
        outcome, message = str(attrs.get("outcome", "unknown")), str(attrs.get("message", ""))
        if outcome != "arrived":
            out.append((str(attrs.get("run") or run_name(p)), outcome, message))
    return out
