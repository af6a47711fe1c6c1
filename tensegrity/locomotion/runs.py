"""Runs: plan, roll, repeat toward a goal or over given edges (paper III.C, IV.B; design.md
section 6).

`roll_to` / `roll_many` / `roll_over` settle the robot, then repeat the paper's steps: find the
contact face, plan from the workspace (`plan`), roll in the dynamic simulator (`control`). A
plan the simulation does not follow is escalated along the ramp to the workspace's highest
level, then the next candidate is tried, then (escape_attempts) the actions `brake.escape`
orders, then the run ends "stuck" (with `lookahead`, where no roll simulated ahead is acceptable the
run makes none and ends "stuck": a run may so end with no step); a step limit bounds every
run, and every run ends with one of `outcome.OUTCOMES` and a message (`outcome.Run`). Runs of
a batch are simulated together (`lockstep`), each with its controller (`drive`); each equals
its single run.
"""

from __future__ import annotations

import time as _time
from collections.abc import Callable, Sequence

import numpy as np
from numpy.typing import ArrayLike

from .. import paper
from ..physics import contact as ct
from ..physics import dynamics as d
from ..physics.params import Params
from ..physics.terrain import Terrain
from ..workspace.lookup import Face, Workspace
from .drive import drive
from .lockstep import lockstep
from .outcome import Run
from .settings import RollSettings

__all__ = ["roll_to", "roll_many", "roll_over"]


def _start(
    params: Params,
    terrain: Terrain,
    state: d.State | None,
    face: Face,
    batch: int,
    position: Sequence[float],
    yaw_deg: float,
) -> tuple[d.State, np.ndarray]:
    """The checked start state of `batch` robots and their CoGs (batch, 3) m, world."""
    if terrain.kind == "none":
        raise ValueError("rolling needs a terrain: the free mode has no ground")
    if state is None:
        state = d.stand_on(params, face, terrain, batch=batch, position=position, yaw_deg=yaw_deg)
    elif state.batch != batch:
        raise ValueError(f"the state holds {state.batch} robots for {batch} runs")
    state.check()
    P = d.nodes(state.x, state.q, params.strut_length)
    for b in range(batch):
        ct.clearance(P[b], terrain, 0.0)  # nothing under the robot -> ValueError
    return state, P.mean(axis=1)


def _check_goal(goal, terrain: Terrain, start: np.ndarray, size: float) -> np.ndarray:
    """The goal (3,) m on the terrain, at least `size` m from the start."""
    gl = np.asarray(goal, float).ravel()
    if gl.size not in (2, 3) or not np.all(np.isfinite(gl)):
        raise ValueError(f"goal must be a finite world point (x, y) m, got {goal!r}")
    h = float(terrain.height(gl[0], gl[1]))
    if np.isnan(h):
        raise ValueError(f"terrain has nothing under the goal ({gl[0]:.3f}, {gl[1]:.3f}) m")
    dist = float(np.linalg.norm(gl[:2] - start[:2]))
    if dist < size * (1 - 1e-9):  # a goal at the strut length, to round-off, is allowed
        raise ValueError(
            f"goal ({gl[0]:.3f}, {gl[1]:.3f}) m is {dist:.3f} m from the robot, "
            f"closer than its size ({size} m, the strut length)"
        )
    return np.array([gl[0], gl[1], h])


def roll_many(
    workspace: Workspace,
    goals: ArrayLike,
    params: Params | None = None,
    terrain: Terrain | None = None,
    state: d.State | None = None,
    face: Face = paper.START_FACE,
    settings: RollSettings | None = None,
    position: Sequence[float] = (0.0, 0.0),
    yaw_deg: float = 0.0,
    direction: ArrayLike | None = None,
    progress: Callable[[float], None] | None = None,
    model: Params | None = None,
) -> list[Run]:
    """`roll_to` for several goals (G, 2) m at once, one robot each, simulated as one batch
    (same parameters and terrain); each run equals its single run."""
    params = params or Params()
    model = model or params
    terrain = terrain or Terrain.flat()
    s = settings or RollSettings()
    goals = np.asarray(goals, float)
    if goals.ndim != 2 or goals.shape[1] not in (2, 3) or not len(goals):
        raise ValueError(f"goals must have shape (G, 2) m, got {goals.shape}")
    state, start = _start(params, terrain, state, face, len(goals), position, yaw_deg)
    S = float(np.max(params.strut_length))
    checked = [_check_goal(gl, terrain, start[b], S) for b, gl in enumerate(goals)]
    t0 = _time.perf_counter()
    out = lockstep(
        params,
        terrain,
        state,
        lambda b, o: drive(workspace, model, terrain, s, o, goal=checked[b], direction=direction),
        s,
        progress,
    )
    wall = _time.perf_counter() - t0
    return [
        Run(res[0], res[1], checked[b], start[b], tuple(res[2]), rec, wall, st, *res[3:])
        for b, (res, st, rec) in enumerate(out)
    ]


def roll_to(
    workspace: Workspace,
    goal: ArrayLike,
    params: Params | None = None,
    terrain: Terrain | None = None,
    state: d.State | None = None,
    face: Face = paper.START_FACE,
    settings: RollSettings | None = None,
    position: Sequence[float] = (0.0, 0.0),
    yaw_deg: float = 0.0,
    direction: ArrayLike | None = None,
    progress: Callable[[float], None] | None = None,
    model: Params | None = None,
) -> Run:
    """Roll toward the world point `goal` (x, y) m: settle, then plan, roll, repeat (paper
    III.C) until the CoG is within arrive_tolerance of the goal ("arrived"), after max_rolls
    rolls ("step_limit"), when no candidate rolls the robot ("stuck"), it rests on no face
    ("no_contact"), leaves the terrain ("off_terrain") or the simulation fails ("sim_error").
    Starts from `state` (one robot), or stands the robot on `face` at `position` (m) turned by
    yaw_deg (deg). `direction` (a world vector) replaces the goal's direction for planning.
    `params` default: `Params()`; `settings` default: `RollSettings()`, the pipeline's defaults
    (the struts damped by settings.strut_damping in every roll). progress(seconds) receives
    the simulated time as it passes. `model`: the planner's Params, with which it simulates
    its candidate rolls ahead, where they differ from the world's `params` (a model error;
    default `params`).

    Raises ValueError for bad input: a goal closer than the robot's size (the strut length),
    a non-finite goal or state, a terrain with nothing under the robot or the goal."""
    gl = np.asarray(goal, dtype=float).ravel()
    if gl.size not in (2, 3):
        raise ValueError(f"goal must be a finite world point (x, y) m, got {goal!r}")
    return roll_many(
        workspace, gl[None, :2], params, terrain, state, face, settings, position, yaw_deg, direction, progress, model
    )[0]


def roll_over(
    workspace: Workspace,
    edges: Sequence[Sequence[int]],
    params: Params | None = None,
    terrain: Terrain | None = None,
    state: d.State | None = None,
    face: Face = paper.START_FACE,
    settings: RollSettings | None = None,
    position: Sequence[float] = (0.0, 0.0),
    yaw_deg: float = 0.0,
) -> Run:
    """Roll over each edge of `edges` (pairs of 1-based node numbers) in turn, planning each
    roll toward that edge's outward direction, e.g. the paper's experiment (IV.B):
    roll_over(ws, [(10, 12), (10, 11)]) from (9,10,12) by #10 onto (10,11,12), then by #11
    onto (6,10,11). Outcome "arrived" once every edge is crossed (the plan may choose any
    pair), "stuck" if an edge is not on the current face or nothing rolls the robot."""
    params = params or Params()
    terrain = terrain or Terrain.flat()
    s = settings or RollSettings()
    edges = [tuple(int(n) for n in e) for e in edges]
    if not edges or any(len(e) != 2 for e in edges):
        raise ValueError(f"edges must be pairs of node numbers, got {edges!r}")
    state, start = _start(params, terrain, state, face, 1, position, yaw_deg)
    t0 = _time.perf_counter()
    ((res, st, rec),) = lockstep(
        params, terrain, state, lambda b, o: drive(workspace, params, terrain, s, o, edges=edges), s
    )
    wall = _time.perf_counter() - t0
    return Run(res[0], res[1], np.full(3, np.nan), start[0], tuple(res[2]), rec, wall, st, *res[3:])
