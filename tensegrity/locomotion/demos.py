"""The workflow's demonstration runs (docs/design.md §6): `DEMOS` and their scenarios
(`Scenarios`, `demo_setup`: terrain, and a goal or the edges to roll over). The stage that runs
them and writes their datasets is `stages.locomotion.locomotion_runs`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import paper
from ..physics.terrain import Terrain

__all__ = ["DEMOS", "Scenarios", "demo_setup"]

DEMOS = ("paper", "flat", "slope_up", "slope_down", "terrain")


@dataclass(frozen=True)
class Scenarios:
    """Where the demonstration runs go (config `locomotion`; the defaults are the schema's,
    pinned by tests/io/test_settings.py): goal_distance m at goal_heading deg from +x (flat and
    terrain runs); slope_angle deg, the slope rising toward +x (slope runs); the random terrain
    of terrain_seed, height standard deviation terrain_amplitude m, cells terrain_spacing m."""

    goal_distance: float = 2.0
    goal_heading: float = 30.0
    slope_angle: float = 10.0
    terrain_seed: int = 1
    terrain_amplitude: float = 0.03
    terrain_spacing: float = 0.25


def demo_setup(name: str, scenarios: Scenarios = Scenarios()) -> dict:
    """Scenario of the demonstration run `name` (one of DEMOS): {"terrain": Terrain, and "goal":
    (2,) m world or "edges": [(a, b), ...] 1-based node pairs}. `paper`: the paper's experiment,
    edges 10-12 then 10-11 on flat ground (`paper.EXPERIMENT_EDGES`); `flat` and `terrain`: a goal
    goal_distance m away at goal_heading deg from +x; `slope_up` and `slope_down`: a slope of
    slope_angle deg rising toward +x, the goal up or down it."""
    if name not in DEMOS:
        raise ValueError(f"unknown locomotion run {name!r}: use one of {DEMOS}")
    c = scenarios
    dist, head = float(c.goal_distance), math.radians(float(c.goal_heading))
    toward = dist * np.array([math.cos(head), math.sin(head)])
    if name == "paper":
        return {"terrain": Terrain.flat(), "edges": [tuple(e) for e in paper.EXPERIMENT_EDGES]}
    if name == "flat":
        return {"terrain": Terrain.flat(), "goal": toward}
    if name in ("slope_up", "slope_down"):  # the slope rises toward +x
        sign = 1.0 if name == "slope_up" else -1.0
        return {"terrain": Terrain.slope(float(c.slope_angle)), "goal": np.array([sign * dist, 0.0])}
    return {
        "terrain": Terrain.random(
            int(c.terrain_seed),
            size=2 * dist + 4.0,
            spacing=float(c.terrain_spacing),
            amplitude=float(c.terrain_amplitude),
        ),
        "goal": toward,
    }
