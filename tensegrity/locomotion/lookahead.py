"""Rolls tried in simulation before the robot acts (issue 10 item 3; docs/design.md §6).

On a steep even slope which roll lands under control is a matter of the landing's dynamics,
which neither workspace predicts (benchmarks/bench_slope_reach.py: on 20 deg a third of the rolls
that move the robot tumble). `foresee` simulates candidate rolls from the robot's current state
with the run's own controller (`control.roll_controller`, a copy of its brake), all in one batch, so
each result is the roll the run would make; `rank` orders them for a goal; `choose` does both
for a run's step. `switchback` routes a run to a goal across a steep slope: straight uphill
first (the robot climbs in a two-roll gait, but loses height on most rolls across), then down.
"""

from __future__ import annotations

import copy
from collections.abc import Sequence

import numpy as np

from ..physics import dynamics as d
from ..physics.params import Params
from ..physics.terrain import Terrain
from ..workspace.lookup import Workspace
from .brake import Brake, escape
from .control import RollResult, roll_controller
from .lockstep import Obs, lockstep
from .plan import Plan
from .settings import RollSettings

__all__ = [
    "foresee",
    "moved",
    "lands",
    "rank",
    "choose",
    "switchback",
    "CLIMB_COST",
    "INCLINE_CLIMB_COST",
    "SLIDE",
    "REVISIT_COST",
    "CLIMB_CONE",
    "DESCENT_CONE",
]

CLIMB_COST = 5.0  # m of distance per m of height an end below the goal costs (climbing back is slow)
INCLINE_CLIMB_COST = 10.0  # the same on an even incline, where height lost is lost for good
SLIDE = 0.5  # m: on an even incline, a roll that moves the CoG further (horizontally) slid: a tumble
REVISIT_COST = 0.25  # m, landing on a face of the run's last few steps (a back-and-forth on a slope)
# On a steep even incline (lookahead_tilt) the robot climbs straight uphill in a two-roll gait and
# descends under control, but loses height on most rolls across (docs/benchmarks.md, 20 deg): a
# goal more than CLIMB_CONE deg and less than DESCENT_CONE deg from straight uphill is reached by
# a switchback, straight uphill first, then down toward the goal (`switchback`).
CLIMB_CONE = 10.0  # deg from straight uphill: 22.5 deg goals got stuck heading there directly
DESCENT_CONE = 135.0  # deg from straight uphill: the 135-225 deg goals arrive directly


def foresee(
    params: Params,
    terrain: Terrain,
    s: RollSettings,
    obs: Obs,
    acts: Sequence[tuple[int, ...]],
    max_pressure: float,
    brake: Brake | None,
    expect: dict[tuple[int, ...], float],
) -> list[RollResult]:
    """The rolls (one RollResult per action of `acts`, 1-based pairs) the robot observed in
    `obs` (with its `state`) would make, each with the run's settings `s`, a copy of `brake` and
    the planned pressure `expect[act]` MPa (NaN if absent), simulated together from the same
    state. Raises SimulationError if a simulation blows up."""
    if obs.state is None:
        raise ValueError("the observation carries no state to simulate from")
    if not acts:
        return []
    state = d.State.concat([obs.state] * len(acts))

    def make(b: int, ob: Obs):
        ob = Obs(obs.t, ob.nodes, ob.gap, ob.face, obs.speed, obs.pressure.copy())
        return roll_controller(
            params, s, ob, tuple(acts[b]), max_pressure, copy.deepcopy(brake), expect.get(tuple(acts[b]), float("nan"))
        )

    return [res for (res, _), _, _ in lockstep(params, terrain, state, make, s)]


def moved(r: RollResult) -> float:
    """How far the roll `r` moved the CoG horizontally, m (a roll: 0.1-0.3 m)."""
    return float(np.linalg.norm(np.subtract(r.cog_after, r.cog_before)[:2]))


def lands(r: RollResult, slide: float = np.inf) -> bool:
    """The roll `r` ends on a face, its CoG moved at most `slide` m horizontally (`moved`; more
    is a slide down an incline, which counts as a tumble)."""
    return r.face_after is not None and moved(r) <= slide


def rank(
    results: Sequence[RollResult],
    goal: np.ndarray,
    terrain: Terrain,
    avoid: Sequence[int] = (),
    climb: float = CLIMB_COST,
    slide: float = np.inf,
) -> list[int]:
    """Indices of `results` in the order to try them toward `goal` (3,) m: the rolls that end
    on another face first, closest to the goal first (horizontal distance, m, plus `climb`
    (m per m) times the height the CoG's ground point ends below the goal's, plus REVISIT_COST
    for landing on a face of `avoid`, 1-based); then those that did not roll; those that tumble
    (end on no face, or slide further than `slide` m: `lands`) last."""

    def key(i: int) -> tuple[int, float]:
        r = results[i]
        c = np.asarray(r.cog_after, float)
        below = max(0.0, float(goal[2] - terrain.height(c[0], c[1])))
        landed = lands(r, slide)
        return (
            0 if r.rolled and landed else 1 if landed else 2,
            float(np.linalg.norm(c[:2] - goal[:2])) + climb * below + REVISIT_COST * (r.face_after in avoid),
        )

    return sorted(range(len(results)), key=key)


def switchback(terrain: Terrain, start: np.ndarray, goal: np.ndarray) -> np.ndarray | None:
    """The turning point (3,) m (on the ground) of a switchback from `start` to `goal` (world
    points, m) on an incline: straight uphill of `start`, so far that the goal then lies
    DESCENT_CONE deg from straight uphill; None where the goal lies within CLIMB_CONE deg of
    straight uphill or at least DESCENT_CONE deg from it (headed for directly), or on level
    ground."""
    n = terrain.normal_at(start[0], start[1])
    if np.hypot(n[0], n[1]) < 1e-12:
        return None
    up = -n[:2] / np.hypot(n[0], n[1])  # uphill, horizontal unit vector
    g = np.subtract(goal[:2], start[:2])
    along, across = float(g @ up), abs(float(g @ [-up[1], up[0]]))
    angle = np.degrees(np.arctan2(across, along))
    if not CLIMB_CONE + 1e-6 < angle < DESCENT_CONE - 1e-6:
        return None
    turn = np.asarray(start[:2], float) + (along + across / np.tan(np.radians(180.0 - DESCENT_CONE))) * up
    return np.array([turn[0], turn[1], float(terrain.height(turn[0], turn[1]))])


def choose(
    workspace: Workspace,
    params: Params,
    terrain: Terrain,
    s: RollSettings,
    obs: Obs,
    face: int,
    pl: Plan,
    tried: set,
    goal: np.ndarray,
    brake: Brake | None,
    target: dict,
    avoid: Sequence[int] = (),
    incline: bool = False,
) -> tuple[list[tuple[int, ...]], tuple[RollResult, ...]]:
    """A run's step by lookahead on `face` (1-based): simulate up to s.lookahead actions not in
    `tried` (the plan's candidates, then `brake.escape`'s order toward `target`, a dict with
    goal= or direction=), and if every one of them tumbles, the face's other actions; return
    the s.max_attempts that land on a face, best first (`rank` toward `goal` (3,) m, landing on
    a face of `avoid` penalised; on an even `incline`, with INCLINE_CLIMB_COST and a slide
    further than SLIDE counted as a tumble), and the simulated rolls in the order simulated.
    A tumble is never returned."""
    climb, slide = (INCLINE_CLIMB_COST, SLIDE) if incline else (CLIMB_COST, np.inf)
    acts = [c.pairs for c in pl.candidates if c.pairs not in tried][: s.lookahead]
    acts += escape(workspace, face, obs.nodes, tried | set(acts), **target)[: s.lookahead - len(acts)]
    expect = {c.pairs: c.pressure for c in pl.candidates}
    simulated = tuple(foresee(params, terrain, s, obs, acts, workspace.max_pressure, brake, expect))
    if not any(lands(r, slide) for r in simulated):
        # every one tumbles: foresee the face's other actions too before giving up
        acts += escape(workspace, face, obs.nodes, tried | set(acts), **target)
        simulated += tuple(
            foresee(params, terrain, s, obs, acts[len(simulated) :], workspace.max_pressure, brake, expect)
        )
    return (
        [acts[i] for i in rank(simulated, goal, terrain, avoid, climb, slide) if lands(simulated[i], slide)][
            : s.max_attempts
        ],
        simulated,
    )
