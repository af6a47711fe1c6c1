"""tensegrity: six-strut tensegrity rolling robot simulation, kinematic workspace, locomotion.

The public API (imported on first use, so `import tensegrity` stays light):

Simulation
    Params, Terrain, Schedule, State        parameters (SI, MPa), terrain, actuation, state
    stand_on(params, face, terrain, batch)  a robot at rest on a face -> State (B robots)
    simulate(params, state, schedule, terrain, dt, record_every) -> (State, Trajectory)
    step(params, state, pressure, dt, terrain) -> State
Workspace
    load_workspace(path, two_pair=...) -> Workspace   results/workspace.nc (and, by default,
                                            results/workspace_two_pair.nc beside it), for planning
    load_curves(path) -> dict               results/curves/curves.json
    evaluate_curve(curve, pressure)         a fitted curve (dict or Curve) at pressures (MPa) -> m
    query_workspace(curves, workspace, face, pair, pressure) -> Answer   CoG (m), margin, any face
Locomotion
    RollSettings                            how rolls are driven (config `locomotion`; defaults the schema's)
    plan_roll(workspace, face, nodes, direction=..., goal=...) -> Plan
    roll_to(workspace, goal, params, terrain, settings=RollSettings()) -> Run   as the pipeline rolls
Calibration
    read_measured(path) -> Measurement      a run file or a motion-capture CSV (nodes m, pressures MPa)
    calibrate(measured, params, fit, mode, dt) -> Calibration   fitted Params, intervals, what is not determined
"""

from __future__ import annotations

import importlib
import os
from typing import TYPE_CHECKING

from .version import __version__

if TYPE_CHECKING:
    from .workspace.lookup import Workspace

_API = {
    "Params": ("physics.params", "Params"),
    "Terrain": ("physics.terrain", "Terrain"),
    "Schedule": ("physics.schedule", "Schedule"),
    "State": ("physics.dynamics", "State"),
    "SimulationError": ("physics.dynamics", "SimulationError"),
    "stand_on": ("physics.dynamics", "stand_on"),
    "simulate": ("physics.dynamics", "simulate"),
    "step": ("physics.dynamics", "step"),
    "load_curves": ("io.formats", "read_curves"),
    "query_workspace": ("workspace.query", "query"),
    "evaluate_curve": ("workspace.fit", "evaluate"),
    "Workspace": ("workspace.lookup", "Workspace"),
    "RollSettings": ("locomotion.settings", "RollSettings"),
    "plan_roll": ("locomotion.plan", "plan"),
    "roll_to": ("locomotion.runs", "roll_to"),
    "read_measured": ("io.formats.measured", "read_measured"),
    "calibrate": ("calibration.fit", "calibrate"),
}

__all__ = ["__version__", "load_workspace", *_API]


def load_workspace(
    path: str | os.PathLike = "results/workspace.nc", two_pair: str | os.PathLike | None = "beside"
) -> Workspace:
    """The 20-face workspace (results/workspace.nc) as a `Workspace` for planning, with the
    measured two-pair curves of `two_pair` (results/workspace_two_pair.nc): by default the file
    workspace_two_pair.nc beside `path` if it exists, as the pipeline's runs plan; None: two
    pairs superposed from the single-pair curves."""
    from pathlib import Path

    from .io.formats import read_workspace

    if two_pair == "beside":
        beside = Path(path).with_name("workspace_two_pair.nc")
        two_pair = beside if beside.is_file() else None
    return read_workspace(path, two_pair)


def __getattr__(name):
    if name in _API:
        module, attr = _API[name]
        return getattr(importlib.import_module(f".{module}", __name__), attr)
    raise AttributeError(f"module 'tensegrity' has no attribute {name!r}")


def __dir__():
    return sorted(__all__)
