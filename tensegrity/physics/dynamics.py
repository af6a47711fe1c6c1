"""The step function and the simulation driver (docs/design.md §3), the recorded `Trajectory`, and
the cable tensions and energy of a state. The time loop itself is compiled in `kernel/`; the
state, its geometry and the initial states (`stand_on`) are `state`'s, offered here too."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike

from . import actuator, kernel
from . import topology as topo
from .params import Params
from .schedule import Schedule, check_pressures
from .state import State, axes, cog, from_nodes, node_velocities, nodes, stand_on
from .terrain import Terrain
from .twisted import TwistedString, Voltages

__all__ = [
    "SimulationError",
    "Trajectory",
    "simulate",
    "step",
    "tensions",
    "energy",
    "warm",
    # physics.state's, offered here: the public API and the callers take them from dynamics
    "State",
    "stand_on",
    "from_nodes",
    "nodes",
    "node_velocities",
    "axes",
    "cog",
]


class SimulationError(RuntimeError):
    """A simulation went non-finite, too fast, or off the terrain."""


@dataclass(frozen=True)
class Trajectory:
    """Recorded samples: t (T,) s, x (B, T, 6, 3) m, q (B, T, 6, 4), pressure (B, T, 12) MPa
    per pair, or (B, T, 24) per cable, as the schedule gave them (V with motors)."""

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
    motors: TwistedString | None = None,
) -> tuple[State, Trajectory]:
    """Advance the batch through the schedule with time step dt (s), recording every
    `record_every` steps. Returns the final state and the trajectory; the input is unchanged.
    Raises SimulationError naming the robot, the time and the quantity if a run blows up.
    The schedule's levels are per pair (12) or per cable (24): a pair's level is lifted to both
    its cables here (`topology.cable_levels`), the kernel reads one per cable.
    With `motors` (twisted-string actuators, docs/design.md §10) the schedule's levels are
    voltages in V, and the state carries the motors' angles and speeds (0 if it has none)."""
    if not (np.isfinite(dt) and 0 < dt <= 1e-3):
        raise ValueError(f"time step dt = {np.asarray(dt).tolist()!r} s must be in (0, 1e-3]")
    if int(record_every) < 1:
        raise ValueError(f"record_every must be a positive number of steps, got {np.asarray(record_every).tolist()!r}")
    state.check()
    if isinstance(schedule, Voltages) != (motors is not None):
        raise ValueError(
            "motors=TwistedString(...) and a schedule of voltages (twisted.Voltages) go together: got "
            f"motors {'given' if motors is not None else 'None'} and a {type(schedule).__name__}"
        )
    B = state.batch
    if schedule.pressure.shape[0] not in (1, B):
        raise ValueError(f"schedule has {schedule.pressure.shape[0]} robots, the state {B}")
    prm = params.pack(B)
    terrain = terrain or Terrain.flat()
    kind, meta, hz = terrain.packed()
    s = state.copy()
    if motors is not None:
        from .kernel import motors as km  # compiled on first use only

        mprm = motors.pack(params, B, dt)
        zero = np.zeros((B, topo.N_CABLES))
        s = replace(
            s,
            motor_angle=zero if s.motor_angle is None else s.motor_angle,
            motor_speed=zero.copy() if s.motor_speed is None else s.motor_speed,
        )
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
        level = np.broadcast_to(schedule.pressure[:, k], (B, schedule.pressure.shape[-1]))
        # per cable, a writeable C-ordered copy (as the state's): one compiled signature of the kernel
        pres = np.array(topo.cable_levels(level), dtype=float, order="C")
        out_x = np.empty((B, n_rec, topo.N_STRUTS, 3))
        out_q = np.empty((B, n_rec, topo.N_STRUTS, 4))
        if motors is None:
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
        else:
            km.advance(
                *(s.x, s.v, s.q, s.w, s.anchor, s.stuck, s.motor_angle, s.motor_speed, prm, mprm, pres),
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
        ps.append(np.repeat(level[:, None], n_rec, axis=1))
        t0 += n * dt
    s = replace(s, t=t0)
    return s, Trajectory(np.concatenate(ts), np.concatenate(xs, 1), np.concatenate(qs, 1), np.concatenate(ps, 1))


def step(params: Params, state: State, pressure: ArrayLike, dt: float = 1e-4, terrain: Terrain | None = None) -> State:
    """One time step of dt (s) with pressures (B, 12) or (12,) MPa per pair, or (B, 24) or (24,)
    per cable: the pure step function."""
    return simulate(params, state, Schedule.constant(pressure, dt), terrain, dt, 1)[0]


def tensions(params: Params, state: State, pressure: ArrayLike) -> np.ndarray:
    """Cable tensions (B, 24) N (eq. 2 with eq. 1, never negative) under pressures (B, 12) or
    (12,) MPa per pair, or (B, 24) or (24,) per cable."""
    B = state.batch
    p = _per_cable(pressure, B)
    P = nodes(state.x, state.q, params.strut_length)
    U = node_velocities(state, params.strut_length)
    return kernel.tensions(P, U, params.pack(B), p)[0]


def energy(params: Params, state: State, pressure: ArrayLike) -> np.ndarray:
    """Total mechanical energy (B,) J: kinetic + cable (a = 1) + gravity, under pressures per
    pair or per cable (as `tensions`). Ground contact and damping are not conservative and are
    not included."""
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
    pres = _per_cable(pressure, B)
    # the law at rest (S1): a spring k whose clamped tension starts at l* (eq. 1-2); U by (S2)
    act = actuator.activations(prm["muscle_gain"], pres)
    k, lstar = actuator.spring(prm["cable_stiffness"], prm["cable_rest_length"], prm["muscle_min_length"], act)
    cable = 0.5 * (k * np.maximum(0.0, ln - lstar) ** 2).sum(-1)
    grav = (m * prm["gravity"] * state.x[..., 2]).sum(-1)
    return kin + cable + grav


def _per_cable(pressure: ArrayLike, batch: int) -> np.ndarray:
    """Checked pressures (batch, 24) MPa, C-ordered, of pressures per pair or per cable, (12,)
    or (24,) for the whole batch or (batch, 12 or 24) (`topology.cable_levels`)."""
    p = topo.cable_levels(check_pressures(pressure))
    return np.ascontiguousarray(np.broadcast_to(p, (batch, topo.N_CABLES)))


def warm() -> None:
    """Compile the kernels, or load them from numba's cache (`__pycache__` beside the source):
    the set-up (workflow/setup.sh) calls this once, so that the pipeline's first jobs do not
    each compile the same code at the same time."""
    params = Params()
    for batch in (1, kernel.LANES):  # one robot, and the groups of lanes (kernel.advance)
        state = stand_on(params, 8, batch=batch)
        simulate(params, state, Schedule.constant(np.zeros((batch, 12)), 1e-3), Terrain.flat())
    tensions(params, state, np.zeros((batch, 12)))
    # the twisted-string kernel (kernel.motors): groups of lanes for every batch
    simulate(params, state, Voltages.constant(np.zeros((batch, 12)), 1e-3), Terrain.flat(), motors=TwistedString())
