"""The controller of one run (paper III.C, repeated; docs/design.md §6), one robot of a `lockstep`
batch: `drive` settles the robot, then finds its contact face, plans from the workspace (`plan`),
simulates candidate rolls from the robot's state and picks the one with the best simulated outcome
(`lookahead.choose`, on every ground), rolls in the simulator (`control.roll_controller`) and
repeats, toward a goal or over given edges, until the run ends with one of `outcome.OUTCOMES`; it
returns the outcome, its message and the `Step`s. With lookahead 0 the plan's candidates are tried
in the world instead, then the escape actions (`brake.escape`). `runs` checks the arguments and
runs it. Where no roll simulated ahead is acceptable, the run goes back to a state where it found an
acceptable roll it did not take (a backtrack, `memory.Memory.opens`); where none returns to one, it makes
no roll and ends `stuck`. A roll the world does not make as its model foresaw (a model error, `runs.roll_to`
`model=`) is planned again from where the robot stands, without the actions the world refused there.
"""

from __future__ import annotations

import copy
import functools
import time
from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike

from ..physics import contact as ct
from ..physics import dynamics as d
from ..physics import topology as topo
from ..physics.params import Params
from ..physics.terrain import Terrain
from ..workspace.lookup import Workspace
from . import lookahead, progress
from .brake import Brake, escape
from .control import RollResult, roll_controller, settle_controller
from .foreseen import Foreseen
from .lockstep import Controller, Obs, observe
from .outcome import Step
from .plan import Plan, plan
from .settings import RollSettings

_TABU = 4  # the plan ranks rolls back onto the faces of the last four steps after the others


def step_ahead(
    workspace: Workspace,
    params: Params,
    terrain: Terrain,
    s: RollSettings,
    obs: Obs,
    face: int,
    pl: Plan,
    target: dict,
    brk: Brake | None,
    cost: Callable[[RollResult], float],
    memory: lookahead.Memory,
    now: float,
    onward: Callable[[RollResult], bool] | None = None,
    known: Foreseen | None = None,
    refused: tuple = (),
) -> tuple[list, tuple[RollResult, ...]]:
    """A run's step simulated ahead from `obs` on `face` (`lookahead.choose`): the plan `pl`'s
    actions toward `target`, the lazy ones (`lookahead.acts`: the optimised ones if s.optimised_actions,
    per cable if s.cable_actions, neither in volts; the brake kept) next after its first where that one is
    not acceptable; `onward` (`lookahead.choose`) judges a landing; `known` (`foreseen.Foreseen`) keeps the
    rolls simulated; the actions `refused` (the world did not roll the robot with them where it stands,
    as the model foresaw) are left out. Returns the acceptable actions best first and every roll
    simulated (`drive`, `start.first_roll` and `onward`)."""
    muscles = s.motors is None  # the optimised actions are solved on the muscles' statics (eq. 1-2)
    world = lookahead.World(
        params,
        terrain,
        obs.state,
        workspace.max_pressure,
        s.optimised_actions and muscles,
        cables=s.cable_actions and muscles,
    )
    args = (workspace, face, obs.nodes, pl, target, brk, world)
    expect = {c.pairs: c.pressure for c in pl.candidates}
    more = lambda: [a for a in lookahead.acts(*args, lazy=True) if a not in refused]  # noqa: E731 (optimised, kept)
    return lookahead.choose(
        params,
        terrain,
        s,
        obs,
        [a for a in lookahead.acts(*args) if a not in refused],
        workspace.max_pressure,
        brk,
        expect,
        cost,
        memory,
        now,
        more,
        onward,
        known,
    )


def _plan(workspace: Workspace, s: RollSettings, face: int, nodes: np.ndarray, avoid: list[int], target: dict) -> Plan:
    """A step's plan on `face` toward `target`, the faces `avoid` ranked last (`plan.plan`, the run's settings)."""
    return plan(
        workspace, face, nodes, avoid=avoid, combine=s.combine, min_alignment=s.min_alignment, unit=s.unit, **target
    )


def onward(
    workspace: Workspace,
    params: Params,
    terrain: Terrain,
    s: RollSettings,
    target: dict,
    brk: Brake | None,
    memory: lookahead.Memory,
    visited: list[int],
    known: Foreseen | None,
    r: RollResult,
) -> bool:
    """Whether the robot, landed as the roll `r` simulated ahead leaves it (`lookahead.foresee`: its
    final state and levels), has an acceptable roll from there toward `target` (`step_ahead`, the
    memory with that state added, the faces `visited` with the landing's, the brake braced anew):
    False for a dead end, where every roll tumbles, slides, does not roll or returns (a slope's face
    that only the brake holds). The verdict does not depend on the candidates' order: they are
    simulated until one is acceptable, or all of them; `known` keeps their rolls for the next step."""
    goal = target.get("goal")
    if goal is not None and np.linalg.norm(np.subtract(r.cog_after[:2], goal[:2])) <= s.arrive_tolerance:
        return True  # arrived there: no roll follows
    if r.state is None or r.record is None or r.face_after is None or not len(workspace.pairs(r.face_after)):
        return True  # nothing to look from (or no curve for that face in the workspace): not judged
    (obs,) = observe(params, terrain, r.state, s, pressure=[r.record.pressure[-1]])
    if obs.face is None:
        return False
    mem = copy.deepcopy(memory)
    mem.add(obs.face, obs.cog)
    b = None if brk is None else copy.deepcopy(brk, {id(brk.workspace): brk.workspace})
    if b is not None:
        b.forget()
    avoid = (visited + [obs.face])[-_TABU - 1 : -1]  # as the next step's plan avoids them
    pl = _plan(workspace, s, obs.face, obs.nodes, avoid, target)
    ok, _ = step_ahead(
        workspace, params, terrain, s, obs, obs.face, pl, target, b, lambda x: 0.0, mem, np.inf, None, known
    )
    return bool(ok)


def drive(
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
    each edge of `edges` in turn. Returns (outcome, message, steps, start_face, stuck_cpu): the
    face the robot settled on first (None: none) and the planning CPU s of a last step that made
    no roll, none of its simulated rolls acceptable (recorded as no `Step`; else 0)."""
    steps: list[Step] = []
    visited: list[int] = []
    outcome, message = "step_limit", f"step limit of {s.max_rolls} rolls reached"
    brk = Brake(workspace, s.brake_margin) if s.brake else None
    memory: lookahead.Memory | None = None
    known = Foreseen()  # the rolls `onward` simulated from the landing, for the next step
    start_face, stuck_cpu = None, 0.0
    refused: tuple = ()  # the actions the world did not roll the robot with on this face (a model error)
    try:
        face, obs = yield from settle_controller(s, obs, brk)
        start_face = face
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
            target = dict(goal=goal) if direction is None else dict(direction=direction)
            travel, lift = progress.stride(obs.nodes, face)
            # the memory forgets when the CoG comes closer to the goal than ever (not along a direction or over edges)
            memory = memory or lookahead.Memory(travel / 2, goal if edges is None and direction is None else None)
            if edges is not None:
                e = tuple(sorted(int(n) for n in edges[k]))
                corners = [topo.edge_nodes(face, j) for j in range(3)]
                if e not in corners:
                    outcome, message = "stuck", (f"edge {e[0]}-{e[1]} is not an edge of face {topo.face_label(face)}")
                    break
                target = dict(direction=ct.edge_outward(obs.nodes[topo.FACES[face - 1]])[corners.index(e)])
                cost, now = progress.over_edge(face, e), 1.0
            elif direction is None:
                cost = lambda r, t=travel, h=lift: progress.rolls_to_goal(r.cog_after, goal, terrain, t, h)  # noqa: E731
                now = progress.rolls_to_goal(obs.nodes.mean(axis=0), goal, terrain, travel, lift)
            else:
                cost, now = progress.along(target["direction"], travel), 0.0
            memory.add(face, obs.nodes.mean(axis=0))
            visited = (visited + [face])[-_TABU - 1 :]
            cpu = time.process_time()  # planning CPU: the plan and every roll simulated ahead
            pl = _plan(workspace, s, face, obs.nodes, visited[:-1], target)
            tries: list[RollResult] = []
            expect = {c.pairs: c.pressure for c in pl.candidates}
            simulated: tuple[RollResult, ...] = ()
            braked = brk is not None
            if s.lookahead:
                # none acceptable: no roll (a roll the planner judged unacceptable was foreseen only
                # until its ramp gave up, and can tumble the robot); the run ends stuck below
                look = (
                    None
                    if edges
                    else functools.partial(onward, workspace, params, terrain, s, target, brk, memory, visited, known)
                )
                known.keep(obs)
                todo, simulated = step_ahead(
                    workspace, params, terrain, s, obs, face, pl, target, brk, cost, memory, now, look, known, refused
                )
            else:  # the workspace's order, tried in the world
                todo = [(c.pairs, braked) for c in pl.candidates[: s.max_attempts]]
            cpu = time.process_time() - cpu
            while todo:
                refused += (todo[0],) if s.lookahead else ()
                act, with_brake, w = todo[0][0], todo[0][1], lookahead.weights_of(todo.pop(0))
                res, obs = yield from roll_controller(
                    params,
                    s,
                    obs,
                    act,
                    workspace.max_pressure,
                    brk if with_brake else None,
                    expect.get(act, float("nan")) if w is None else float("nan"),
                    weights=w,
                )
                if brk is not None and not with_brake:
                    brk.forget()
                tries.append(res)
                if res.face_after is None or res.rolled:
                    break
                if (
                    not todo
                    and not s.lookahead
                    and len(tries) == min(s.max_attempts, len(pl.candidates))
                    and s.escape_attempts
                ):
                    # stuck: other actions, those predicted to roll toward the target first
                    todo = [
                        (a, braked)
                        for a in escape(workspace, face, obs.nodes, {r.pairs for r in tries}, **target)[
                            : s.escape_attempts
                        ]
                    ]
            if not tries:  # nothing tried: no step (its planning CPU kept as the run's stuck_cpu)
                stuck_cpu = cpu
                outcome, message = (
                    "stuck",
                    (
                        f"every one of the {len(simulated)} candidate rolls simulated on face "
                        f"{topo.face_label(face)} tumbles the robot, slides it more than "
                        f"{lookahead.SLIDE} m, does not roll it, or returns it to where it was, with no acceptable "
                        f"roll left untaken ({lookahead.verdicts(simulated, memory)})"
                    ),
                )
                break
            after = tries[-1].face_after
            steps.append(Step(face, pl, tuple(tries), after, simulated, cpu))
            if tries[-1].rolled:
                refused = ()
            elif after is not None and s.lookahead:  # the model foresaw rolls the world refused: plan again here
                face = after
                continue
            if after is not None and not tries[-1].rolled:
                outcome = "stuck"
                message = (
                    f"no candidate rolled the robot off face {topo.face_label(face)}: tried "
                    + ", ".join(
                        f"{'+'.join(f'#{q}' for q in r.pairs)} up to {r.peak_pressure:.2f} {s.unit}" for r in tries
                    )
                    + ("" if pl.predicted else "; the workspace predicted no roll here (e.g. a slope too steep for it)")
                    + (
                        f"; none of the {len(simulated)} candidate rolls simulated here rolls it without a tumble, "
                        f"a slide over {lookahead.SLIDE} m or a return ({lookahead.verdicts(simulated, memory)})"
                        if simulated
                        else ""
                    )
                )
                break
            face = after
    except d.SimulationError as e:
        outcome = "off_terrain" if "no terrain" in str(e) else "sim_error"
        message = str(e)
    return outcome, message, steps, start_face, stuck_cpu
