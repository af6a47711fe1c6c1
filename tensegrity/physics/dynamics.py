"""State of a batch of robots, initial states, the step function and the simulation driver
(docs/design.md §3). The time loop itself is compiled in `kernel/`."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike

from . import actuator, frames, kernel
from . import topology as topo
from .params import Params
from .schedule import Schedule, check_pressures
from .terrain import Terrain


class SimulationError(RuntimeError):
    """A simulation went non-finite, too fast, or off the terrain."""


@dataclass(frozen=True)
class State:
    """Batch of B robots. x, v: strut centres (m) and velocities (m/s), (B, 6, 3) world;
    q: unit quaternions (w, x, y, z) taking body to world components, (B, 6, 4), body axis 3
    along the strut; w: body angular velocities (rad/s), (B, 6, 3); anchor, stuck: friction
    stick points (B, 12, 3) m and flags (B, 12); t: time, s."""

    x: np.ndarray
    v: np.ndarray
    q: np.ndarray
    w: np.ndarray
    anchor: np.ndarray
    stuck: np.ndarray
    t: float = 0.0

    @property
    def batch(self) -> int:
        return self.x.shape[0]

    def copy(self) -> State:
        return State(
            *(np.array(a, copy=True, order="C") for a in (self.x, self.v, self.q, self.w, self.anchor, self.stuck)),
            t=self.t,
        )

    def check(self) -> None:
        for name in ("x", "v", "q", "w"):
            a = getattr(self, name)
            if np.isfinite(a).all():  # the usual case: one test per array
                continue
            bad = ~np.isfinite(a).reshape(a.shape[0], -1).all(axis=1)
            if bad.any():
                raise ValueError(f"state {name} is not finite for robot {int(np.argmax(bad))}")

    def take(self, idx: ArrayLike | slice) -> State:
        """The sub-batch of robots idx."""
        return State(*(a[idx] for a in (self.x, self.v, self.q, self.w, self.anchor, self.stuck)), t=self.t)

    @staticmethod
    def concat(states: Sequence[State], t: float | None = None) -> State:
        """One batch of the robots of `states`, in order, at time `t` s (default: the first's)."""
        return State(
            *(np.concatenate([getattr(s, k) for s in states]) for k in ("x", "v", "q", "w", "anchor", "stuck")),
            t=states[0].t if t is None else t,
        )


def axes(q: np.ndarray, column: int | None = None) -> np.ndarray:
    """Rotation matrices (..., 3, 3) of quaternions (..., 4) (w, x, y, z; normalised here);
    columns are the body axes in world components. With `column` (0..2): that axis (..., 3)."""
    q = q / np.sqrt((q * q).sum(axis=-1))[..., None]
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    cols = (
        lambda: (1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)),
        lambda: (2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)),
        lambda: (2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)),
    )
    if column is not None:
        return np.stack(cols[column](), axis=-1)
    return np.stack([np.stack(c(), axis=-1) for c in cols], axis=-1)


def nodes(x: np.ndarray, q: np.ndarray, strut_length: float | np.ndarray) -> np.ndarray:
    """Node positions (..., 12, 3) m from strut centres x (..., 6, 3) and quaternions (..., 6, 4)
    (strut end = x + L c for the first node of a strut, x - L c for the second; eq. 4)."""
    half = 0.5 * np.asarray(strut_length, dtype=float)
    half = half.reshape(half.shape + (1,) * (x.ndim - half.ndim))[..., None, :] if half.ndim else half
    c = axes(q, 2) * (half if np.ndim(half) == 0 else half[..., 0, :][..., None, :])
    p = np.empty(x.shape[:-2] + (topo.N_NODES, 3))
    p[..., topo.STRUTS[:, 0], :] = x + c
    p[..., topo.STRUTS[:, 1], :] = x - c
    return p


def node_velocities(state: State, strut_length: float | np.ndarray) -> np.ndarray:
    """Node velocities (B, 12, 3) m/s."""
    half = 0.5 * np.asarray(strut_length, dtype=float).reshape(-1, 1, 1)
    R = axes(state.q)
    w = state.w
    cdot = R[..., :, 0] * w[..., 1:2] - R[..., :, 1] * w[..., 0:1]  # R (w x e3)
    u = np.empty(state.x.shape[:-2] + (topo.N_NODES, 3))
    u[..., topo.STRUTS[:, 0], :] = state.v + half * cdot
    u[..., topo.STRUTS[:, 1], :] = state.v - half * cdot
    return u


def cog(x: np.ndarray) -> np.ndarray:
    """Centre of gravity (..., 3) m: the mean of the strut centres (..., 6, 3) (equal masses)."""
    return x.mean(axis=-2)


def from_nodes(p: np.ndarray) -> State:
    """A state at rest from node positions (B, 12, 3) or (12, 3) m (strut lengths as given)."""
    p = np.asarray(p, dtype=float).reshape(-1, topo.N_NODES, 3)
    a, b = p[:, topo.STRUTS[:, 0]], p[:, topo.STRUTS[:, 1]]
    c = ((a - b) / np.linalg.norm(a - b, axis=-1, keepdims=True)).reshape(-1, 3)
    # the rotation taking e3 onto c about the axis e3 x c (quaternion w, x, y, z)
    half = 0.5 * np.arccos(np.clip(c[:, 2], -1.0, 1.0))
    ax = np.stack([-c[:, 1], c[:, 0], np.zeros(len(c))], axis=1)
    n = np.linalg.norm(ax, axis=1, keepdims=True)
    ax = np.where(n > 1e-12, ax / np.where(n > 1e-12, n, 1.0), [1.0, 0.0, 0.0])
    q = np.concatenate([np.cos(half)[:, None], np.sin(half)[:, None] * ax], axis=1)
    B = p.shape[0]
    z3 = np.zeros((B, topo.N_STRUTS, 3))
    return State(
        0.5 * (a + b),
        z3,
        q.reshape(B, topo.N_STRUTS, 4),
        z3.copy(),
        np.zeros((B, topo.N_NODES, 3)),
        np.zeros((B, topo.N_NODES), dtype=np.bool_),
    )


def stand_on(
    params: Params,
    face: int | Sequence[int],
    terrain: Terrain | None = None,
    batch: int = 1,
    position: ArrayLike = (0.0, 0.0),
    yaw_deg: float = 0.0,
) -> State:
    """The symmetric robot at rest with `face` (1..20 or three node numbers) on the terrain
    under `position` (m), turned by yaw_deg about the terrain normal. With no terrain (free
    mode) it is placed as if on flat ground at z = 0."""
    f = topo.face_number(face) - 1
    S = float(np.max(params.strut_length)) if np.ndim(params.strut_length) else params.strut_length
    r = float(np.max(params.strut_radius))
    p = topo.reference_nodes(S)
    tri = p[topo.FACES[f]]
    outward = np.cross(tri[1] - tri[0], tri[2] - tri[0])
    outward *= np.sign(np.dot(outward, tri.mean(0)))  # the centre is at the origin
    outward /= np.linalg.norm(outward)
    terrain = terrain or Terrain.flat()
    px, py = map(float, position)
    if terrain.kind == "heightfield" and np.isnan(terrain.height(px, py)):
        raise ValueError(f"terrain has nothing under the robot at position {position}")
    up = terrain.normal_at(px, py) if terrain.kind != "none" else np.array([0.0, 0.0, 1.0])
    p = p @ (frames.turn(up, np.radians(yaw_deg)) @ frames.align(outward, -up)).T
    p[:, :2] += [px, py]
    if terrain.kind == "none":
        p[:, 2] += r - p[:, 2].min()
    else:
        h = terrain.height(p[:, 0], p[:, 1])
        if np.any(np.isnan(h)):
            raise ValueError(f"terrain has nothing under the robot at position {position}")
        p[:, 2] += np.max(h + r / terrain.normal_at(p[:, 0], p[:, 1])[:, 2] - p[:, 2])
    return from_nodes(np.repeat(p[None], batch, axis=0))


@dataclass(frozen=True)
class Trajectory:
    """Recorded samples: t (T,) s, x (B, T, 6, 3) m, q (B, T, 6, 4), pressure (B, T, 12) MPa."""

    t: np.ndarray
    x: np.ndarray
    q: np.ndarray
    pressure: np.ndarray

    def nodes(self, strut_length: float | np.ndarray) -> np.ndarray:
        """Node positions (B, T, 12, 3) m."""
        L = np.asarray(strut_length, float)
        if L.ndim:
            return np.stack([nodes(self.x[b], self.q[b], L[b]) for b in range(L.size)])
        return nodes(self.x, self.q, L)

    def cog(self) -> np.ndarray:
        """CoG (B, T, 3) m, world frame."""
        return cog(self.x)


_QUANTITY = {
    1: "a non-finite (NaN or inf) strut state",
    2: "a node faster than max_speed",
    3: "a node with no terrain under it",
}


def simulate(
    params: Params,
    state: State,
    schedule: Schedule,
    terrain: Terrain | None = None,
    dt: float = 1e-4,
    record_every: int = 10,
) -> tuple[State, Trajectory]:
    """Advance the batch through the schedule with time step dt (s), recording every
    `record_every` steps. Returns the final state and the trajectory; the input is unchanged.
    Raises SimulationError naming the robot, the time and the quantity if a run blows up."""
    if not (np.isfinite(dt) and 0 < dt <= 1e-3):
        raise ValueError(f"time step dt = {np.asarray(dt).tolist()!r} s must be in (0, 1e-3]")
    if int(record_every) < 1:
        raise ValueError(f"record_every must be a positive number of steps, got {np.asarray(record_every).tolist()!r}")
    state.check()
    B = state.batch
    if schedule.pressure.shape[0] not in (1, B):
        raise ValueError(f"schedule has {schedule.pressure.shape[0]} robots, the state {B}")
    prm = params.pack(B)
    terrain = terrain or Terrain.flat()
    kind, meta, hz = terrain.packed()
    s = state.copy()
    status = np.zeros(B, np.int64)
    fail = np.zeros(B, np.int64)
    every = int(record_every)
    ts, xs, qs, ps = [], [], [], []
    t0 = state.t
    for k, dur in enumerate(schedule.durations):
        n = int(round(dur / dt))
        if abs(n * dt - dur) > 1e-9 * max(1.0, dur) or n % every:
            raise ValueError(
                f"segment {k} of {dur} s is not a whole number of recording intervals ({every} steps of {dt} s)"
            )
        n_rec = n // every
        # a writeable C-ordered copy (as the state's): one compiled signature of the kernel
        pres = np.array(np.broadcast_to(schedule.pressure[:, k], (B, topo.N_PAIRS)), dtype=float, order="C")
        out_x = np.empty((B, n_rec, topo.N_STRUTS, 3))
        out_q = np.empty((B, n_rec, topo.N_STRUTS, 4))
        kernel.advance(
            s.x,
            s.v,
            s.q,
            s.w,
            s.anchor,
            s.stuck,
            prm,
            pres,
            kind,
            meta,
            hz,
            n_rec,
            every,
            dt,
            out_x,
            out_q,
            status,
            fail,
        )
        if status.any():
            b = int(np.flatnonzero(status)[0])
            raise SimulationError(
                f"robot {b} of the batch: {_QUANTITY[int(status[b])]} at t = {t0 + fail[b] * dt:.4f} s (dt = {dt} s)"
            )
        ts.append(t0 + dt * every * np.arange(1, n_rec + 1))
        xs.append(out_x)
        qs.append(out_q)
        ps.append(np.repeat(pres[:, None], n_rec, axis=1))
        t0 += n * dt
    s = replace(s, t=t0)
    return s, Trajectory(np.concatenate(ts), np.concatenate(xs, 1), np.concatenate(qs, 1), np.concatenate(ps, 1))


def step(params: Params, state: State, pressure: ArrayLike, dt: float = 1e-4, terrain: Terrain | None = None) -> State:
    """One time step of dt (s) with pair pressures (B, 12) or (12,) MPa: the pure step function."""
    p = check_pressures(pressure)
    return simulate(params, state, Schedule.constant(p.reshape(-1, topo.N_PAIRS), dt), terrain, dt, 1)[0]


def tensions(params: Params, state: State, pressure: ArrayLike) -> np.ndarray:
    """Cable tensions (B, 24) N (eq. 2 with eq. 1, never negative)."""
    B = state.batch
    p = np.ascontiguousarray(np.broadcast_to(check_pressures(pressure), (B, topo.N_PAIRS)))
    P = nodes(state.x, state.q, params.strut_length)
    U = node_velocities(state, params.strut_length)
    return kernel.tensions(P, U, params.pack(B), p)[0]


def energy(params: Params, state: State, pressure: ArrayLike) -> np.ndarray:
    """Total mechanical energy (B,) J: kinetic + cable (a = 1) + gravity. Ground contact and
    damping are not conservative and are not included."""
    if np.any(np.asarray(params.cable_exponent) != 1.0):
        raise NotImplementedError("cable energy is implemented for cable_exponent = 1 only")
    B = state.batch
    prm = {
        k: np.broadcast_to(np.asarray(getattr(params, k), float), (B,))[:, None]
        for k in (
            "strut_mass",
            "strut_length",
            "strut_radius",
            "cable_stiffness",
            "cable_rest_length",
            "muscle_min_length",
            "muscle_gain",
            "gravity",
        )
    }
    m, S, r = prm["strut_mass"], prm["strut_length"], prm["strut_radius"]
    It, Ia = m * (S**2 / 12 + r**2 / 4), m * r**2 / 2
    kin = (
        0.5 * m * np.sum(state.v**2, -1)
        + 0.5 * It * np.sum(state.w[..., :2] ** 2, -1)
        + 0.5 * Ia * state.w[..., 2] ** 2
    ).sum(-1)
    P = nodes(state.x, state.q, params.strut_length)
    ln = np.linalg.norm(P[:, topo.CABLES[:, 1]] - P[:, topo.CABLES[:, 0]], axis=-1)
    pres = np.broadcast_to(check_pressures(pressure), (B, topo.N_PAIRS))
    # the law at rest (S1): a spring k whose clamped tension starts at l* (eq. 1-2); U by (S2)
    act = actuator.activations(prm["muscle_gain"], pres)
    k, lstar = actuator.spring(prm["cable_stiffness"], prm["cable_rest_length"], prm["muscle_min_length"], act)
    cable = 0.5 * (k * np.maximum(0.0, ln - lstar) ** 2).sum(-1)
    grav = (m * prm["gravity"] * state.x[..., 2]).sum(-1)
    return kin + cable + grav


def warm() -> None:
    """Compile the kernels, or load them from numba's cache (`__pycache__` beside the source):
    the set-up (workflow/setup.sh) calls this once, so that the pipeline's first jobs do not
    each compile the same code at the same time."""
    params = Params()
    for batch in (1, kernel.LANES):  # one robot, and the groups of lanes (kernel.advance)
        state = stand_on(params, 8, batch=batch)
        simulate(params, state, Schedule.constant(np.zeros((batch, 12)), 1e-3), Terrain.flat())
    tensions(params, state, np.zeros((batch, 12)))
