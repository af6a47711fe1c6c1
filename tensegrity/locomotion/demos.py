"""The workflow's demonstration runs (design.md section 6): `DEMOS`, their scenarios from the
configuration (`demo_setup`: terrain, and a goal or the edges to roll over) and the parameters
of the rolling simulations (`locomotion_params`). The stage that runs one and writes its dataset
is `stages.locomotion_run`.
"""
from __future__ import annotations

import math

import numpy as np

from ..physics.params import Params
from ..physics.terrain import Terrain

__all__ = ["DEMOS", "demo_setup", "locomotion_params"]

DEMOS = ("paper", "flat", "slope_up", "slope_down", "terrain")


def demo_setup(cfg: dict, name: str) -> dict:
    """Scenario of the demonstration run `name` (one of DEMOS) from the resolved configuration's
    `locomotion` section: {"terrain": Terrain, and "goal": (2,) m world or "edges": [(a, b),
    ...] 1-based node pairs}. `paper`: edges 10-12 then 10-11 on flat ground; `flat` and
    `terrain`: a goal goal_distance m away at goal_heading deg from +x; `slope_up` and
    `slope_down`: a slope of slope_angle deg rising toward +x, the goal up or down it."""
    if name not in DEMOS:
        raise ValueError(f"unknown locomotion run {name!r}: use one of {DEMOS}")
    c = cfg["locomotion"]
    dist, head = float(c["goal_distance"]), math.radians(float(c["goal_heading"]))
    toward = dist * np.array([math.cos(head), math.sin(head)])
    if name == "paper":
        return {"terrain": Terrain.flat(), "edges": [(10, 12), (10, 11)]}
    if name == "flat":
        return {"terrain": Terrain.flat(), "goal": toward}
    if name in ("slope_up", "slope_down"):  # the slope rises toward +x
        sign = 1.0 if name == "slope_up" else -1.0
        return {"terrain": Terrain.slope(float(c["slope_angle"])), "goal": np.array([sign * dist, 0.0])}
    return {"terrain": Terrain.random(int(c["terrain_seed"]), size=2 * dist + 4.0,
                                      spacing=float(c["terrain_spacing"]),
                                      amplitude=float(c["terrain_amplitude"])), "goal": toward}


def locomotion_params(cfg: dict) -> Params:
    """Parameters of the rolling simulations: config `params` with locomotion.strut_damping
    (1/s)."""
    from ..io.config import params_from_config
    return params_from_config(cfg).replace(strut_damping=float(cfg["locomotion"]["strut_damping"]))

