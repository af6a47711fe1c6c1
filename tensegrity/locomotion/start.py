"""Start poses that stand and can roll (issue 30 item 3; docs/design.md §6).

A run placed on a face its CoG cannot stay on tumbles before its first roll (a 24 deg slope from
the paper's start face). `stands` asks the simulator: every candidate pose (face, yaw) is set
down on the terrain (`dynamics.stand_on`) and left for STAND_TIME s at rest, held by the run's
own brake (`brake.Brake`, as `drive` holds it), all in one batch; a pose stands if the robot then
rests on a face and its CoG has moved less than STAND_MOVE m (a robot that stands only sags, by
millimetres; on uneven ground it may settle onto a neighbouring triple of nodes). A pose may
stand where every roll from it tumbles or slides (24 deg: a dead end before the first roll);
`first_roll` simulates the run's first step from it (settled as `drive` settles it, the
candidates simulated by `lookahead.choose`, acceptance and cost as the run's). `choose` keeps
the pose a user gave if it stands (else ValueError naming one that does) and otherwise picks one
among the candidates: the face given (else the paper's start face) at the yaw given (else 0),
then the others, the CoG projection along gravity deepest inside the support triangle first
(rigid robot, `contact.judge`), those that stand found in that order (the first alone, then
BATCH at a time). Given a goal, it takes the first standing candidate whose first roll is
acceptable and gains toward the goal, else the first with an acceptable roll (a detour), else
the first that stands; without a goal, the first that stands. Where nothing was given and no
pose stands (ground rougher than the robot: on 0.07 m terrain some places), the paper's start
face at yaw 0, saying so: the robot settles first. `Start.message` says which and why.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .. import paper
from ..physics import contact as ct
from ..physics import dynamics as d
from ..physics import topology as topo
from ..physics.params import Params
from ..physics.terrain import Terrain
from ..workspace.lookup import Workspace
from . import lookahead, progress
from .brake import Brake
from .control import settle_controller
from .drive import step_ahead
from .lockstep import Obs, lockstep
from .plan import plan
from .settings import RollSettings

__all__ = ["Start", "stands", "first_roll", "choose", "STAND_TIME", "STAND_MOVE", "YAW_STEP"]

STAND_TIME = 2.0  # s at rest: a robot that cannot stand has tipped over an edge by then
STAND_MOVE = 0.05  # m of CoG travel (horizontal) that is no longer standing: a tip or a slide
YAW_STEP = 30.0  # deg between the yaws tried where none is given
BATCH = 8  # candidate poses simulated together


@dataclass(frozen=True)
class Start:
    """The start pose of a run: `face` (1-based) and `yaw_deg` (about the terrain normal, deg);
    `message`: which pose, and why, in words; `cpu`: the process time (s, all threads) the
    choice took."""

    face: int
    yaw_deg: float
    message: str
    cpu: float = 0.0  # s: process time spent choosing (the poses and rolls simulated)


def _brake(workspace: Workspace, terrain: Terrain, s: RollSettings) -> Brake | None:
    return Brake(workspace, s.brake_margin) if s.brake else None


def stands(
    workspace: Workspace,
    params: Params,
    terrain: Terrain,
    s: RollSettings,
    poses: Sequence[tuple[int, float]],
    position: Sequence[float] = (0.0, 0.0),
) -> np.ndarray:
    """(P,) bool: each pose (1-based face, yaw deg) at `position` (m) stands on `terrain`
    (module docstring), simulated as one batch with the struts damped as in every roll."""
    if not poses:
        return np.zeros(0, bool)
    state = d.State.concat([d.stand_on(params, f, terrain, position=position, yaw_deg=y) for f, y in poses])
    c0 = d.nodes(state.x, state.q, params.strut_length).mean(axis=1)

    def hold(b: int, obs: Obs):
        brake, t0 = _brake(workspace, terrain, s), obs.t
        while obs.t - t0 < STAND_TIME - 1e-9:
            _, obs = yield from settle_controller(s, obs, brake)
        return obs.face

    out = lockstep(params, terrain, state, hold, s)
    ok = []
    for b, (face, st, _) in enumerate(out):
        c1 = d.nodes(st.x, st.q, params.strut_length)[0].mean(axis=0)
        # on uneven ground a pose set down on one face may settle on the next triple of nodes
        # that touch; it stands if it rests on a face without travelling
        ok.append(face is not None and float(np.linalg.norm(c1[:2] - c0[b, :2])) < STAND_MOVE)
    return np.array(ok, bool)


def first_roll(
    workspace: Workspace,
    params: Params,
    terrain: Terrain,
    s: RollSettings,
    pose: tuple[int, float],
    goal: Sequence[float],
    position: Sequence[float] = (0.0, 0.0),
) -> tuple[float | None, str]:
    """The first step of a run toward `goal` (x, y) m from `pose` (1-based face, yaw deg) at
    `position` (m), as `drive` makes it: the robot set down and settled with the run's brake,
    its candidate rolls simulated from that state (`lookahead.choose`: the same candidates,
    horizons, acceptance and cost, `progress.rolls_to_goal`). Returns the progress (rolls: the
    cost of staying minus that of its best acceptable roll; <= 0 a detour) or None if no
    candidate is acceptable (a dead end), and the verdicts in words."""
    state = d.stand_on(params, pose[0], terrain, position=position, yaw_deg=pose[1])

    def settle(b: int, obs: Obs):
        brk = _brake(workspace, terrain, s)
        face, obs = yield from settle_controller(s, obs, brk)
        return face, obs, brk

    (((face, obs, brk), _, _),) = lockstep(params, terrain, state, settle, s)
    if face is None:
        return None, "it comes to rest on no face"
    gl = np.array([goal[0], goal[1], float(terrain.height(goal[0], goal[1]))])
    travel, lift = progress.stride(obs.nodes, face)
    memory = lookahead.Memory(travel / 2)
    memory.add(face, obs.cog)
    target = dict(goal=gl)
    pl = plan(workspace, face, obs.nodes, combine=s.combine, min_alignment=s.min_alignment, unit=s.unit, **target)

    def cost(r):
        return progress.rolls_to_goal(r.cog_after, gl, terrain, travel, lift)

    now = progress.rolls_to_goal(obs.cog, gl, terrain, travel, lift)
    _, simulated = step_ahead(workspace, params, terrain, s, obs, face, pl, target, brk, cost, memory, now)
    ok = [r for r in simulated if r.rolled and lookahead.lands(r) and not memory.seen(r.face_after, r.cog_after)]
    fine = [now - cost(r) for r in ok]  # the acceptable rolls, as `lookahead.choose` accepts them
    words = f"{len(simulated)} rolls simulated: {lookahead.verdicts(simulated, memory)}"
    return (max(fine) if fine else None), words


def _margin(params: Params, terrain: Terrain, face: int, yaw: float, position: Sequence[float]) -> float:
    """Margin (m) of the rigid robot's CoG projection along gravity in `face`'s triangle."""
    st = d.stand_on(params, face, terrain, position=position, yaw_deg=yaw)
    return float(ct.judge(d.nodes(st.x, st.q, params.strut_length)[0], face).margin)


def _standing(workspace, params, terrain, s, poses, position):
    """The poses of `poses` that stand, in order: the first alone (the preferred pose, which
    mostly stands), then `BATCH` at a time, simulated only as far as they are asked for."""
    for k0, k1 in [(0, 1)] + [(k, k + BATCH) for k in range(1, len(poses), BATCH)]:
        part = poses[k0:k1]
        yield from (p for p, ok in zip(part, stands(workspace, params, terrain, s, part, position)) if ok)


def _search(workspace, params, terrain, s, poses, position) -> tuple[int, float] | None:
    """The first pose of `poses` that stands; None if none does."""
    return next(_standing(workspace, params, terrain, s, poses, position), None)


def _rolling(workspace, params, terrain, s, poses, position, goal) -> tuple[tuple[int, float], str] | None:
    """The first standing pose of `poses` with an acceptable first roll toward `goal` that makes
    progress, else the first with one (a detour), else the first that stands, and why in words;
    None if none stands."""
    ground = terrain.describe()
    found: list[tuple[tuple[int, float], float | None, str]] = []  # (pose, progress, verdicts)
    for pose in _standing(workspace, params, terrain, s, poses, position):
        try:
            gain, words = first_roll(workspace, params, terrain, s, pose, goal, position)
        except d.SimulationError as e:
            gain, words = None, f"the simulation failed ({e})"
        found.append((pose, gain, words))
        if gain is not None and gain > 0:
            break
    if not found:
        return None
    pick = max(found, key=lambda f: (f[1] is not None and f[1] > 0, f[1] is not None))  # the first of the best kind
    pose, gain, words = pick
    if gain is not None and gain > 0:
        why = f"it stands on {ground} and its best first roll gains {gain:.2f} rolls toward the goal ({words})"
    elif gain is not None:
        why = f"it stands on {ground}; no first roll from it gains toward the goal, a detour does ({words})"
    else:
        why = f"it stands on {ground}, but no first roll from any standing pose is acceptable ({words})"
    for p, g, w in found:
        if p != pose:
            why += f"; {_label(p)} stands, but " + (
                f"no first roll from it is acceptable ({w})" if g is None else f"none from it gains ({w})"
            )
    return pose, why


def _ranked(params, terrain, faces, yaws, position, first=None) -> list[tuple[int, float]]:
    """Poses over `faces` x `yaws`, `first` (if given) then deepest CoG projection first."""
    poses = [(f, float(y)) for f in faces for y in yaws]
    m = {p: _margin(params, terrain, p[0], p[1], position) for p in poses}
    order = sorted(poses, key=lambda p: (p != first, -round(m[p], 9), p))
    return [p for p in order if m[p] > 0 or p == first]  # a rigid robot tipping cannot stand


def _label(pose: tuple[int, float]) -> str:
    face = topo.face_label(pose[0])
    return f"face {face} at yaw {pose[1]:g} deg (--face {face.strip('()')} --yaw {pose[1]:g})"


def choose(
    workspace: Workspace,
    params: Params,
    terrain: Terrain,
    s: RollSettings,
    face: int | Sequence[int] | None = None,
    yaw_deg: float | None = None,
    position: Sequence[float] = (0.0, 0.0),
    goal: Sequence[float] | None = None,
) -> Start:
    """The start pose of a run at `position` (m) toward `goal` (x, y) m: the one given (face
    1..20 or three nodes, yaw deg) if it stands, else ValueError naming one that does; where the
    face or the yaw is not given, a standing one, with a first roll toward `goal` if one has
    (module docstring; without a goal, the first that stands). ValueError if a face or yaw is
    given and no pose with it stands there."""
    cpu = time.process_time()
    params = s.rolling(params)
    yaws = np.arange(0.0, 360.0, YAW_STEP) if yaw_deg is None else [float(yaw_deg)]
    faces = range(1, topo.N_FACES + 1) if face is None else [topo.face_number(face)]
    every = np.arange(0.0, 360.0, YAW_STEP)
    other = None
    if face is not None and yaw_deg is not None:
        pose = (faces[0], float(yaw_deg))
        if stands(workspace, params, terrain, s, [pose], position)[0]:
            why = f"start on {_label(pose)}, as given: it stands on {terrain.describe()}"
            return Start(*pose, why, time.process_time() - cpu)
        what = (
            f"the start pose {_label(pose)} does not stand on {terrain.describe()}: the robot tips or slides "
            f"more than {STAND_MOVE} m within {STAND_TIME} s, before any roll"
        )
        other = _search(workspace, params, terrain, s, _ranked(params, terrain, faces, every, position), position)
    else:
        first = (faces[0] if face is not None else topo.face_number(paper.START_FACE), float(yaws[0]))
        ranked = _ranked(params, terrain, faces, yaws, position, first)
        if goal is None:
            pose = _search(workspace, params, terrain, s, ranked, position)
            pick = None if pose is None else (pose, f"it stands on {terrain.describe()}")
        else:
            pick = _rolling(workspace, params, terrain, s, ranked, position, goal)
        if pick is not None:
            return Start(*pick[0], f"start on {_label(pick[0])}, chosen: {pick[1]}", time.process_time() - cpu)
        what = (
            "no start pose"
            + (f" on face {topo.face_label(faces[0])}" if face is not None else "")
            + (f" at yaw {yaw_deg:g} deg" if yaw_deg is not None else "")
            + f" stands on "
            f"{terrain.describe()} at {tuple(position)} m"
        )
    if face is None and yaw_deg is None:  # nothing stands here (very rough ground): it settles first
        return Start(
            *first,
            f"start on {_label(first)}: {what} (the robot settles where it comes to rest before the first roll)",
            time.process_time() - cpu,
        )
    if other is None:
        other = _search(
            workspace,
            params,
            terrain,
            s,
            _ranked(params, terrain, range(1, topo.N_FACES + 1), every, position),
            position,
        )
    raise ValueError(what + (f"; {_label(other)} stands" if other else "; no pose stands there"))
