"""Pressure sweeps of the actuator pairs on a contact face (paper III.A)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..physics import dynamics as d
from ..physics import frames
from ..physics import topology as topo
from ..physics.contact import clearance, resting_face
from ..physics.params import Params
from ..physics.schedule import Schedule
from ..physics.terrain import Terrain
from ..physics.twisted import TwistedString, Voltages

MODES = ("free", "grounded")


@dataclass(frozen=True)
class SweepSetup:
    """The staircase of a sweep: levels (P,) MPa, each held `hold` s after `settle` s at zero
    pressure, in `mode` ('free' or 'grounded', `setup`), simulated with time step dt s and
    recorded every record_every steps. The defaults are the schema's `sweep` and `sim` defaults
    (pinned by tests/io/test_settings.py)."""

    levels: tuple[float, ...] = (0.4, 0.8, 1.2, 1.6, 2.0, 2.4, 2.8, 3.2, 3.6, 4.0, 4.4, 4.8)
    hold: float = 1.0
    settle: float = 0.0
    mode: str = "free"
    dt: float = 1e-4
    record_every: int = 10


@dataclass(frozen=True)
class Sweep:
    """One staircase per pair. t (T,) s; pressure_cmd (B, T) MPa; cog (B, T, 3) m and
    support (B, T, 3, 3) m in the support frame of the deformed contact face; nodes (B, T, 12, 3)
    m world positions; level (T,) index of the level held (-1 while settling); on_face (B, T)
    whether the robot rests on `face`; resting_face (B, T) the face it rests on, 0 for none
    (contact.resting_face; `face` throughout in the free mode); locked (B, P) with the
    twisted-string actuator, whether a motor had twisted its strands past their lock by the end
    of each level (`TwistedString.locked`: the model (T1) does not hold there), else None."""

    pairs: np.ndarray
    levels: np.ndarray
    face: int
    t: np.ndarray
    pressure_cmd: np.ndarray
    cog: np.ndarray
    support: np.ndarray
    nodes: np.ndarray
    level: np.ndarray
    on_face: np.ndarray
    resting_face: np.ndarray
    locked: np.ndarray | None = None


def setup(params: Params, mode: str) -> tuple[Params, Terrain]:
    """Parameters and terrain of a sweep mode: 'free' (no gravity, no ground: the paper's
    assumption, docs/design.md §3) or 'grounded' (gravity, flat ground, friction)."""
    if mode not in MODES:
        raise ValueError(f"unknown sweep mode {mode!r}: use one of {MODES}")
    return (params.replace(gravity=0.0), Terrain.none()) if mode == "free" else (params, Terrain.flat())


def run(
    params: Params,
    face: int | Sequence[int],
    pairs: ArrayLike,
    sweep: SweepSetup,
    motors: TwistedString | None = None,
) -> Sweep:
    """Stand the robot on `face`, apply the staircase of `sweep` to each pair in `pairs` (one
    robot each, batched). With `motors` (the twisted-string actuator, docs/design.md §10) the
    levels and `pressure_cmd` are motor voltages, V."""
    face = topo.face_number(face)
    pairs = np.array([topo.check_pair(p) for p in np.atleast_1d(pairs)])
    levels = np.asarray(sweep.levels, dtype=float)
    hold, settle, dt, record_every = sweep.hold, sweep.settle, sweep.dt, sweep.record_every
    prm, terrain = setup(params, sweep.mode)
    state = d.stand_on(prm, face, terrain, batch=len(pairs))
    if motors is None:
        sched = Schedule.staircase(pairs, levels, hold, settle)
        _, tr = d.simulate(prm, state, sched, terrain, dt, record_every)
        locked = None
    else:
        sched = Voltages.staircase(pairs, levels, hold, settle)
        tr, locked = run_levels(prm, state, sched, terrain, dt, record_every, motors)
        locked = locked[:, 1:] if settle > 0 else locked
    nodes = tr.nodes(prm.strut_length)
    cog, support = frames.in_support_frame(nodes, face)
    seg = np.searchsorted(np.cumsum(sched.durations), tr.t - 0.5 * dt * record_every)
    level = seg - (1 if settle > 0 else 0)
    if terrain.kind == "none":
        resting = np.full((len(pairs), tr.t.size), face, np.int64)
    else:
        resting = resting_faces(nodes, terrain, prm.strut_radius)
    return Sweep(
        pairs,
        levels,
        face,
        tr.t,
        tr.pressure[np.arange(len(pairs)), :, pairs - 1],
        cog,
        support,
        nodes,
        level,
        resting == face,
        resting,
        locked,
    )


def run_levels(
    params: Params,
    state: d.State,
    sched: Voltages,
    terrain: Terrain,
    dt: float,
    record_every: int,
    motors: TwistedString,
) -> tuple[d.Trajectory, np.ndarray]:
    """`dynamics.simulate` of a staircase of voltages one segment at a time (the same run: each
    continues from the last one's state), and whether a motor of each robot is past its strands'
    lock at the end of each segment, (B, K)."""
    parts, locked = [], []
    for k, duration in enumerate(sched.durations):
        segment = Voltages(np.array([duration]), sched.pressure[:, k : k + 1])
        state, tr = d.simulate(params, state, segment, terrain, dt, record_every, motors=motors)
        parts.append(tr)
        locked.append(motors.locked(state.motor_angle).any(axis=1))

    def joined(field: str, axis: int) -> np.ndarray:
        return np.concatenate([getattr(p, field) for p in parts], axis=axis)

    tr = d.Trajectory(joined("t", 0), joined("x", 1), joined("q", 1), joined("pressure", 1))
    return tr, np.stack(locked, axis=1)


def resting_faces(nodes: np.ndarray, terrain: Terrain, radius: float | np.ndarray) -> np.ndarray:
    """Face (B, T) each robot rests on, 0 for none, for node positions (B, T, 12, 3) m: the
    contact rule `contact.resting_face` with a tolerance of one contact radius (m, scalar or
    (B,))."""
    r = np.reshape(np.asarray(radius, float), (-1, 1, 1))
    return resting_face(clearance(nodes, terrain, 0.0) - r, r[..., 0])
