"""Candidates tried in simulation before the robot acts (steep slopes): which roll lands under
control depends on the landing's dynamics, which no workspace predicts. Each candidate roll is
simulated from the robot's current state with the run's controller (`control._roll_gen`, the
same brake); the rolls that end resting on a face come first, closest to the goal first."""
from __future__ import annotations

import copy
from collections.abc import Sequence

import numpy as np

from ..physics import dynamics as d
from ..physics.params import Params
from ..physics.terrain import Terrain
from .brake import Brake
from .lockstep import Obs, lockstep


def order(params: Params, terrain: Terrain, s, obs: Obs, acts: Sequence[tuple[int, ...]],
          max_pressure: float, brake: Brake | None, expect: dict, goal: np.ndarray) -> list[tuple[int, ...]]:
    """`acts` reordered by their simulated outcome from `obs` (its `state`): the rolls that
    land on a face first, by the distance (m) of the CoG to `goal` (3,) after them; then the
    ones that did not roll; the tumbles last."""
    from .control import _roll_gen
    if obs.state is None or not acts:
        return list(acts)
    state = d.State.concat([obs.state] * len(acts))

    def make(b, ob):
        ob = Obs(obs.t, ob.nodes, ob.gap, ob.face, obs.speed, obs.pressure.copy())
        return _roll_gen(params, s, ob, acts[b], max_pressure, copy.deepcopy(brake),
                         expect.get(acts[b], float("nan")))
    try:
        out = lockstep(params, terrain, state, make, s)
    except d.SimulationError:
        return list(acts)
    key = []
    for act, (res, _, _) in zip(acts, out):
        res = res[0]
        dist = float(np.linalg.norm(res.cog_after[:2] - goal[:2]))
        # below the goal it is uphill: out of reach on a steep slope (a climb costs 5 times)
        dist += 5.0 * max(0.0, float(goal[2] - terrain.height(res.cog_after[0], res.cog_after[1])))
        key.append((0 if res.rolled and res.face_after is not None else 1 if res.face_after is not None else 2,
                    dist))
    import os, sys
    if os.environ.get("LOOKAHEAD_DEBUG"):
        best = min(range(len(acts)), key=lambda i: key[i])
        r = out[best][0][0]
        print(f"LA t={obs.t:.2f} face={obs.face} best={acts[best]} cat={key[best][0]} pred_after={r.face_after} "
              f"cats={[k[0] for k in key]}", file=sys.stderr)
    return [acts[i] for i in sorted(range(len(acts)), key=lambda i: key[i])]
