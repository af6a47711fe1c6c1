"""Runs: plan, roll, repeat toward a goal or over given edges (paper III.C, IV.B; design.md
section 6).

`roll_to` / `roll_many` / `roll_over` settle the robot, then repeat the paper's steps: find the
contact face, plan from the workspace (`plan`), roll in the dynamic simulator (`control`). A
plan the simulation does not follow is escalated along the ramp to the workspace's highest
level, then the next candidate is tried, then (escape_attempts) the actions `brake.escape`
orders, then the run ends "stuck"; a step limit bounds every
run, and every run ends with one of `outcome.OUTCOMES` and a message (`outcome.Run`). Runs of
a batch are simulated together (`lockstep`); each equals its single run.
"""

from __future__ import annotations

import time as _time
from collections.abc import Callable, Sequence

import numpy as np
from numpy.typing import ArrayLike

from .. import paper
from ..physics import contact as ct
from ..physics import dynamics as d
from ..physics import topology as topo
from ..physics.params import Params
from ..physics.terrain import Terrain
from ..workspace.lookup import Face, Workspace
from . import lookahead
from .brake import Brake, escape, on_incline
from .control import RollResult, roll_controller, settle_controller
from .lockstep import Controller, Obs, lockstep
from .outcome import Run, Step
from .plan import plan
from .settings import RollSettings

__all__ = ["roll_to", "roll_many", "roll_over"]

_TABU = 4  # a run avoids rolling back onto the faces of its last four steps


def _drive(
    workspace: Workspace,
    params: Params,
    terrain: Terrain,
    s: RollSettings,
    obs: Obs,
    goal: np.ndarray | None = None,
    edges: list[tuple[int, ...]] | None = None,
    direction: ArrayLike | None = None,
) -> Controller:
    """The run controller (paper III.C, repeated) on `terrain`: toward `goal` (3,) m, or over
    each edge of `edges` in turn. Returns (outcome, message, steps)."""
    steps: list[Step] = []
    visited: list[int] = []
    outcome, message = "step_limit", f"step limit of {s.max_rolls} rolls reached"
    brk = Brake(workspace, s.brake_margin, terrain=terrain, min_tilt=s.brake_tilt) if s.brake else None
    turn = None  # the turning point of a switchback up a steep incline (lookahead.switchback)
    try:
        face, obs = yield from settle_controller(s, obs, brk)
        if (
            goal is not None
            and direction is None
            and s.lookahead
            and face is not None
            and on_incline(terrain, face, obs.nodes, s.lookahead_tilt)
        ):
            turn = lookahead.switchback(terrain, obs.nodes.mean(axis=0), goal)
        via = turn  # while the run heads for the turning point
        for k in range(s.max_rolls + 1):
            if face is None:
                outcome, message = (
                    "no_contact",
                    (
                        f"the robot did not come to rest on a face within {s.settle_time} s (it is "
                        "tumbling, e.g. down a slope too steep, or its nodes on the terrain are not "
                        "one of the 20 faces)"
                    ),
                )
                break
            if edges is not None and k == len(edges):
                outcome, message = "arrived", (f"rolled over {len(edges)} edge(s) onto {topo.face_label(face)}")
                break
            if edges is None and np.linalg.norm(obs.nodes.mean(axis=0)[:2] - goal[:2]) <= s.arrive_tolerance:
                outcome, message = "arrived", f"within {s.arrive_tolerance} m of the goal"
                break
            if k == s.max_rolls:
                break
            if via is not None:  # reached (or passed above) the turning point: on to the goal
                c = obs.nodes.mean(axis=0)
                if np.linalg.norm(c[:2] - via[:2]) <= s.arrive_tolerance or terrain.height(c[0], c[1]) >= via[2]:
                    via = None
            aim = goal if via is None else via
            target = dict(goal=aim) if direction is None else dict(direction=direction)
            if edges is not None:
                e = tuple(sorted(int(n) for n in edges[k]))
                corners = [topo.edge_nodes(face, j) for j in range(3)]
                if e not in corners:
                    outcome, message = "stuck", (f"edge {e[0]}-{e[1]} is not an edge of face {topo.face_label(face)}")
                    break
                target = dict(direction=ct.edge_outward(obs.nodes[topo.FACES[face - 1]])[corners.index(e)])
            visited = (visited + [face])[-_TABU - 1 :]
            pl = plan(
                workspace,
                face,
                obs.nodes,
                avoid=visited[:-1],
                combine=s.combine,
                min_alignment=s.min_alignment,
                **target,
            )
            tries: list[RollResult] = []
            todo = [c.pairs for c in pl.candidates[: s.max_attempts]]
            expect = {c.pairs: c.pressure for c in pl.candidates}
            simulated: tuple[RollResult, ...] = ()
            look = bool(s.lookahead) and goal is not None
            uneven = not on_incline(terrain, face, obs.nodes, 0.0)
            incline = look and on_incline(terrain, face, obs.nodes, s.lookahead_tilt)
            if incline:
                todo, simulated = lookahead.choose(
                    workspace, params, terrain, s, obs, face, pl, set(), aim, brk, target, visited[:-1], incline=True
                )
            while todo:
                act = todo.pop(0)
                res, obs = yield from roll_controller(
                    params, s, obs, act, workspace.max_pressure, brk, expect.get(act, float("nan"))
                )
                tries.append(res)
                if res.face_after is None or res.rolled:
                    break
                if look and uneven and not simulated:
                    # on uneven ground the planned roll failed: foresee the others
                    todo, simulated = lookahead.choose(
                        workspace, params, terrain, s, obs, face, pl, {r.pairs for r in tries}, aim, brk, target
                    )
                elif (
                    not todo
                    and not simulated
                    and len(tries) == min(s.max_attempts, len(pl.candidates))
                    and s.escape_attempts
                ):
                    # stuck: other actions, those predicted to roll toward the target first
                    todo = escape(workspace, face, obs.nodes, {r.pairs for r in tries}, **target)[: s.escape_attempts]
            if not tries:  # nothing tried: no step
                outcome, message = (
                    "stuck",
                    (
                        f"every one of the {len(simulated)} actions simulated on face "
                        f"{topo.face_label(face)} (lookahead) tumbles the robot"
                        + (f" or slides it more than {lookahead.SLIDE} m" if incline else "")
                    ),
                )
                break
            after = tries[-1].face_after
            steps.append(Step(face, pl, tuple(tries), after, simulated))
            if after is not None and not tries[-1].rolled:
                outcome = "stuck"
                message = (
                    f"no candidate rolled the robot off face {topo.face_label(face)}: tried "
                    + ", ".join(f"{'+'.join(f'#{q}' for q in r.pairs)} up to {r.peak_pressure:.2f} MPa" for r in tries)
                    + ("" if pl.predicted else "; the workspace predicted no roll here (e.g. a slope too steep for it)")
                )
                break
            face = after
    except d.SimulationError as e:
        outcome = "off_terrain" if "no terrain" in str(e) else "sim_error"
        message = str(e)
    if edges is None and turn is not None:
        message += (
            f"; by a switchback: straight uphill toward ({turn[0]:.2f}, {turn[1]:.2f}) m first, then toward the goal"
        )
    return outcome, message, steps


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
    if dist < size:
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
) -> list[Run]:
    """`roll_to` for several goals (G, 2) m at once, one robot each, simulated as one batch
    (same parameters and terrain); each run equals its single run."""
    params = params or Params()
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
        lambda b, o: _drive(workspace, params, terrain, s, o, goal=checked[b], direction=direction),
        s,
        progress,
    )
    wall = _time.perf_counter() - t0
    return [
        Run(res[0], res[1], checked[b], start[b], tuple(res[2]), rec, wall, st) for b, (res, st, rec) in enumerate(out)
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
) -> Run:
    """Roll toward the world point `goal` (x, y) m: settle, then plan, roll, repeat (paper
    III.C) until the CoG is within arrive_tolerance of the goal ("arrived"), after max_rolls
    rolls ("step_limit"), when no candidate rolls the robot ("stuck"), it rests on no face
    ("no_contact"), leaves the terrain ("off_terrain") or the simulation fails ("sim_error").
    Starts from `state` (one robot), or stands the robot on `face` at `position` (m) turned by
    yaw_deg (deg). `direction` (a world vector) replaces the goal's direction for planning.
    `params` default: `Params()`; `settings` default: `RollSettings()`, the pipeline's defaults
    (the struts damped by settings.strut_damping in every roll). progress(seconds) receives
    the simulated time as it passes.

    Raises ValueError for bad input: a goal closer than the robot's size (the strut length),
    a non-finite goal or state, a terrain with nothing under the robot or the goal."""
    gl = np.asarray(goal, dtype=float).ravel()
    if gl.size not in (2, 3):
        raise ValueError(f"goal must be a finite world point (x, y) m, got {goal!r}")
    return roll_many(
        workspace, gl[None, :2], params, terrain, state, face, settings, position, yaw_deg, direction, progress
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
        params, terrain, state, lambda b, o: _drive(workspace, params, terrain, s, o, edges=edges), s
    )
    return Run(res[0], res[1], np.full(3, np.nan), start[0], tuple(res[2]), rec, _time.perf_counter() - t0, st)
