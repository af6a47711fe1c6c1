"""tensegrity: six-strut tensegrity rolling robot simulation, kinematic workspace, locomotion.

The public API (imported on first use, so `import tensegrity` stays light):

Simulation
    Params, Terrain, Schedule, State        parameters (SI, MPa), terrain, actuation, state
    stand_on(params, face, terrain, batch)  a robot at rest on a face -> State (B robots)
    simulate(params, state, schedule, terrain, dt, record_every) -> (State, Trajectory)
    step(params, state, pressure, dt, terrain) -> State
Workspace
    load_workspace(path) -> Workspace       results/workspace.nc, for planning
    load_curves(path) -> dict               results/curves/curves.json
    evaluate_curve(curve, pressure)         a fitted curve (dict or Curve) at pressures (MPa) -> m
    query_workspace(curves, workspace_ds, face, pair, pressure) -> Answer   CoG (m), margin, any face
Locomotion
    plan_roll(workspace, face, nodes, direction=..., goal=...) -> Plan
    roll_to(workspace, goal, params, terrain) -> Run
"""
from __future__ import annotations

import importlib
import os

from importlib.metadata import PackageNotFoundError, version as _version
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from .locomotion.lookup import Workspace

try:
    __version__ = _version("tensegrity")
except PackageNotFoundError:  # run from a source tree that was never installed
    __version__ = "0+unknown"

_API = {
    "Params": ("physics.params", "Params"),
    "Terrain": ("physics.terrain", "Terrain"),
    "Schedule": ("physics.schedule", "Schedule"),
    "State": ("physics.dynamics", "State"),
    "SimulationError": ("physics.dynamics", "SimulationError"),
    "stand_on": ("physics.dynamics", "stand_on"),
    "simulate": ("physics.dynamics", "simulate"),
    "step": ("physics.dynamics", "step"),
    "load_curves": ("workspace.query", "load_curves"),
    "query_workspace": ("workspace.query", "query"),
    "evaluate_curve": ("workspace.fit", "evaluate"),
    "Workspace": ("locomotion.lookup", "Workspace"),
    "plan_roll": ("locomotion.plan", "plan"),
    "roll_to": ("locomotion.runs", "roll_to"),
}

__all__ = ["__version__", "load_workspace", *_API]


def load_workspace(path: str | os.PathLike = "results/workspace.nc") -> Workspace:
    """The 20-face workspace (results/workspace.nc) as a locomotion.Workspace for planning."""
    from .io.formats import read_workspace
    return read_workspace(path)


def __getattr__(name):
    if name in _API:
        module, attr = _API[name]
        return getattr(importlib.import_module(f".{module}", __name__), attr)
    raise AttributeError(f"module 'tensegrity' has no attribute {name!r}")


def __dir__():
    return sorted(__all__)
