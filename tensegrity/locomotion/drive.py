"""The controller of one run (paper III.C, repeated; docs/design.md §6), one robot of a `lockstep`
batch: `drive` settles the robot, then finds its contact face, plans from the workspace (`plan`),
rolls in the simulator (`control.roll_controller`) and repeats, toward a goal or over given edges,
until the run ends with one of `outcome.OUTCOMES`; it returns the outcome, its message and the
`Step`s. A candidate that does not roll the robot is followed by the next; rolls are foreseen in
simulation (`lookahead`) on an incline before the first try and on uneven ground after a failed
one, a switchback leads up a steep slope, and the escape actions (`brake.escape`) come once the
candidates are spent. `runs` checks the arguments and runs it.
"""

from __future__ import annotations

import time

import numpy as np
from numpy.typing import ArrayLike

from ..physics import contact as ct
from ..physics import dynamics as d
from ..physics import topology as topo
from ..physics.params import Params
from ..physics.terrain import Terrain
from ..workspace.lookup import Workspace
from . import lookahead
from .brake import Brake, escape, on_incline
from .control import RollResult, roll_controller, settle_controller
from .lockstep import Controller, Obs
from .outcome import Step
from .plan import plan
from .settings import RollSettings

_TABU = 4  # a run avoids rolling back onto the faces of its last four steps


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
            cpu = time.process_time()  # planning CPU: the plan and every roll simulated ahead
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
            cpu = time.process_time() - cpu
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
                    c0 = time.process_time()
                    todo, simulated = lookahead.choose(
                        workspace, params, terrain, s, obs, face, pl, {r.pairs for r in tries}, aim, brk, target
                    )
                    cpu += time.process_time() - c0
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
            steps.append(Step(face, pl, tuple(tries), after, simulated, cpu))
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
