"""Optimised actions of any set of pairs for the planner (issue 30, item 1): from the robot's
current state on its face, one weight vector per edge it can be rolled over
(`workspace.sensitivity`: the statics' sensitivity of the CoG projection to each pair and a
linear programme for the least total pressure), and a second per edge where it differs, the
deepest crossing (`workspace.cable_actions.reach_action`, which drives many pairs at once and
finds crossings the first misses; `workspace.slope_multi` judges both the same way), to roll
with `control.roll(..., weights=w)`.

With `levers` 24 the same searches on the 24 cables one by one (the prototype's actuators, section
IV; `sensitivity.grounded(..., levers=24)`, `sensitivity.cable_law`): weight vectors (24,), which
the kernel takes per cable (`topology.cable_levels`); config `locomotion.cable_actions`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..physics import contact as ct
from ..physics import dynamics as d
from ..physics import topology as topo
from ..physics.params import Params
from ..physics.terrain import Terrain
from ..workspace.cable_actions import reach_action
from ..workspace.lookup import Workspace
from ..workspace.sensitivity import ActuationSettings, EdgeAction, edge_actions, grounded
from .plan import Plan

__all__ = ["ActuationSettings", "Candidate", "World", "cables", "candidates", "optimised"]


@dataclass(frozen=True)
class Candidate:
    """weights (12,) per pair or (24,) per cable (largest 1: the roll ramps the pressures s w,
    `control.action_weights`);
    edge: two 1-based nodes of the face it rolls over; next_face (1-based) across it; scale
    MPa: the least s at which the model puts the CoG projection over the edge (`EdgeAction`);
    along: cosine between the edge's outward normal (horizontal, world) and the asked
    direction (NaN without one)."""

    weights: np.ndarray
    edge: tuple[int, int]
    next_face: int
    scale: float
    along: float


def _outward(nodes: np.ndarray, face: int, edge: tuple[int, int]) -> np.ndarray:
    """Horizontal outward unit normal (2,) in the world of `edge` of `face` on `nodes` (12, 3) m."""
    tri = nodes[topo.FACES[face - 1]]
    k = [topo.edge_nodes(face, i) for i in range(3)].index(edge)
    v = ct.edge_outward(tri)[k, :2]
    return v / max(float(np.linalg.norm(v)), 1e-12)


def candidates(
    params: Params,
    terrain: Terrain,
    state: d.State,
    face: int,
    direction: ArrayLike | None,
    settings: ActuationSettings,
    max_pressure: float,
    deepest: bool = True,
    levers: int = topo.N_PAIRS,
) -> list[Candidate]:
    """Optimised actions for one robot `state` (batch 1) resting on `face` (1..20) of `terrain`:
    per edge that some pressures up to max_pressure MPa roll it over by the model
    (`sensitivity.grounded`: the free statics about the robot's own pose and gravity), the
    least-total action and (`deepest`) the deepest-crossing one where it differs (module
    docstring), by `along` the world direction `direction` (2,) (x, y) first (None: by scale);
    `levers` 12 (pair pressures) or 24 (cable pressures, weights (24,)).
    ContactError if the robot does not rest on `face`."""
    if state.batch != 1:
        raise ValueError(f"candidates are for one robot; the state holds {state.batch}")
    nodes = d.nodes(state.x, state.q, params.strut_length)[0]
    r = float(np.max(params.strut_radius))
    on = ct.face_from_gaps(ct.clearance(nodes, terrain, r), r)
    f = topo.face_number(face)
    if on != f:
        raise ct.ContactError(f"the robot rests on face {topo.face_label(on)}, not {topo.face_label(f)}")
    model = grounded(params, f, nodes, levers)
    acts: list[EdgeAction] = edge_actions(model, max_pressure, settings)
    for k in range(3 if deepest else 0):
        a = reach_action(model, k, max_pressure, settings.actuation_margin)
        if a is not None and not any(b.edge == a.edge and np.allclose(b.weights, a.weights) for b in acts):
            acts.append(a)
    u = None if direction is None else np.asarray(direction, float)[:2]
    if u is not None and not (np.all(np.isfinite(u)) and np.linalg.norm(u) > 0):
        raise ValueError(f"direction {u.tolist()} must be a finite non-zero (x, y) vector")
    out = []
    for a in acts:
        along = float("nan") if u is None else float(_outward(nodes, f, a.edge) @ u / np.linalg.norm(u))
        out.append(Candidate(a.weights, a.edge, a.next_face, a.scale, along))
    key = (lambda c: c.scale) if u is None else (lambda c: (-c.along, c.scale))
    return sorted(out, key=key)


@dataclass(frozen=True)
class World:
    """What a generator may need beyond the plan: the run's `params`, `terrain`, the robot's
    `state` (batch 1) resting on the face, max_pressure MPa, and whether optimised actions of
    any set of pairs are offered (`optimised`: config locomotion.optimised_actions) and of the 24
    cables one by one (`cables`: config locomotion.cable_actions)."""

    params: Params
    terrain: Terrain
    state: d.State | None
    max_pressure: float
    optimised: bool = False
    actuation: ActuationSettings = ActuationSettings()
    cables: bool = False


def optimised(
    workspace: Workspace, face: int, nodes: np.ndarray, pl: Plan, target: dict, world: World | None = None
) -> list[np.ndarray]:
    """With world.optimised: one or two weight vectors (12,) per edge the statics can roll the
    robot over (`candidates` from world.state), toward the target first: a generator of
    `lookahead.GENERATORS` (its arguments). ~0.1 s CPU per pose."""
    return _optimised(face, nodes, target, world, topo.N_PAIRS) if world is not None and world.optimised else []


def cables(
    workspace: Workspace, face: int, nodes: np.ndarray, pl: Plan, target: dict, world: World | None = None
) -> list[np.ndarray]:
    """With world.cables: `optimised`'s weight vectors on the 24 cables one by one, (24,) each."""
    return _optimised(face, nodes, target, world, topo.N_CABLES) if world is not None and world.cables else []


def _optimised(face: int, nodes: np.ndarray, target: dict, world: World, levers: int) -> list[np.ndarray]:
    """The weight vectors of `candidates` with `levers` from world.state toward the target."""
    if world.state is None:
        return []
    u = target["direction"] if "direction" in target else np.subtract(target["goal"][:2], nodes.mean(axis=0)[:2])
    u = u if np.linalg.norm(u) > 0 else None  # at the goal itself: by scale
    try:
        got = candidates(
            world.params, world.terrain, world.state, face, u, world.actuation, world.max_pressure, levers=levers
        )
    except ct.ContactError:  # not resting on the face by the contact model: nothing to optimise about
        return []
    return [c.weights for c in got]
