"""The model a calibration fits (docs/design.md §9): the measured node positions against the
simulated ones, as a function of one vector of unknowns in scaled units, evaluated for many
vectors at once as one batched simulation (one robot per vector).

The unknowns, in order: the named `Params` fields (scaled by their starting values: 1 is the
start), the initial state (`initial.INITIAL_NAMES`, if fitted) and the frame's tilt and height
(`initial.FRAME_NAMES`, grounded mode, if fitted). The residual (`RESIDUALS`) is, per sample
(sample 0 the initial state's own nodes), simulated minus measured: 'positions', every measured
node's coordinates (m, world frame; a node with a NaN coordinate left out of that sample);
'shape', the 24 cable lengths (m; with the struts rigid they fix the structure's shape up to a
rigid motion; a cable with an end not measured left out; grounded, the default). The shape does not see where the robot
is or how it is turned, which the ground contact decides: a contact law not ours (MuJoCo's) moves
the whole robot tens of mm away from ours but its shape ~1 mm (docs/benchmarks.md).

A run driven in volts (`Measurement.command` 'voltage') is replayed with the twisted strings
(`twisted.TwistedString`, docs/design.md §10), whose fields are fitted by their configuration
keys `actuator.twisted_string.<field>` (`ACTUATOR_FITTABLE`); the muscles' fields (eq. 1-2) then
have no effect. Its motors start untwisted and at rest (theta = omega = 0): the motor angles are
not measured, and a run must start from the strings' zero twist (where every cable carries T0).
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from ..physics import actuator
from ..physics import dynamics as d
from ..physics import topology as topo
from ..physics.params import Params
from ..physics.schedule import Schedule, whole_steps
from ..physics.terrain import Terrain
from ..physics.twisted import TwistedString
from . import initial
from .measurement import Grid, Measurement, grid, schedule

__all__ = ["Problem", "problem", "FITTABLE", "ACTUATOR", "ACTUATOR_FITTABLE", "UNIT", "RESIDUALS", "lengths"]
MODES = ("free", "grounded")
RESIDUALS = ("positions", "shape")
DEFAULT_RESIDUAL = {"free": "positions", "grounded": "shape"}  # per mode (docs/design.md §9)
__all__ += ["DEFAULT_RESIDUAL"]
# Params fields a calibration may fit, and those that do nothing in the free mode (no ground)
FITTABLE = tuple(f.name for f in fields(Params) if f.name not in ("cable_rest_length", "max_speed"))
_GROUND_ONLY = ("gravity", "ground_stiffness", "ground_damping", "friction", "friction_stiffness", "friction_damping")
# the twisted strings' fields by their configuration keys, and the muscles' Params fields, which
# a run in volts does not use (the strings' law replaces eq. 1-2)
ACTUATOR = "actuator.twisted_string."
ACTUATOR_FITTABLE = tuple(ACTUATOR + f.name for f in fields(TwistedString))
_MUSCLE_ONLY = (*actuator.NAMES, "cable_pretension")
# scaled unit of each unknown of the initial state and the frame: m, rad, m/s, rad/s per unit
UNIT = {"x": 1e-2, "y": 1e-2, "z": 1e-2, "tilt_a": 1e-2, "tilt_b": 1e-2}
UNIT |= {"vx": 1e-2, "vy": 1e-2, "vz": 1e-2, "wa": 1e-1, "wb": 1e-1}
UNIT |= {"frame_tilt_x": 1e-2, "frame_tilt_y": 1e-2, "frame_z": 1e-2}


@dataclass(frozen=True)
class Problem:
    """A calibration problem: the measurement m on grid g, replayed by `sched` from the first
    sample with time step dt s recorded every `every` steps, in `mode` on `terrain`; the start
    parameters `params` (gravity 0 in the free mode); the unknowns `names` with scaled units
    `units` (value = x * unit) and start x0; the first-guess frame (R, o) and the robot's first
    centroid `centre` (m, world); `mask` (T, 12, 3): which coordinates were measured; `motors`
    the twisted strings a run in volts is replayed with (None: the pneumatic muscles);
    `residual` its kind (`RESIDUALS`), `valid` (T, M) which of a sample's M entries are measured."""

    m: Measurement
    g: Grid
    sched: Schedule
    dt: float
    every: int
    mode: str
    terrain: Terrain
    params: Params
    fit: tuple[str, ...]
    names: tuple[str, ...]
    units: np.ndarray
    x0: np.ndarray
    R: np.ndarray
    o: np.ndarray
    centre: np.ndarray
    mask: np.ndarray
    motors: TwistedString | None = None
    residual: str = "positions"
    valid: np.ndarray | None = None

    @property
    def n_params(self) -> int:
        return len(self.fit)

    def values(self, x: np.ndarray) -> np.ndarray:
        """The unknowns (..., p) in their own units (Params' units, m, rad, m/s, rad/s)."""
        return np.asarray(x, float) * self.units

    def frame(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The frame (R (3, 3), o (3,) m) of one vector x: world = R measured + o."""
        if self.names[-1] != initial.FRAME_NAMES[-1]:
            return self.R, self.o
        return initial.tilted(self.R, self.o, self.centre, self.values(x)[-3:])

    def measured(self, x: np.ndarray) -> np.ndarray:
        """The measured nodes (T, 12, 3) m in the world frame of vector x (NaN where missing)."""
        R, o = self.frame(x)
        return self.m.nodes @ R.T + o

    def _frames(self, X: np.ndarray) -> list[np.ndarray]:
        """The rows of X (B, p) grouped by their frame (most vectors share one: the frame's
        unknowns are 3 of them), as index arrays."""
        F = np.atleast_2d(X)[:, len(self.names) - 3 :] if self.names[-1] == initial.FRAME_NAMES[-1] else None
        if F is None:
            return [np.arange(len(np.atleast_2d(X)))]
        _, inv = np.unique(F, axis=0, return_inverse=True)
        return [np.flatnonzero(inv.ravel() == j) for j in range(int(inv.max()) + 1)]

    def state(self, X: np.ndarray) -> d.State:
        """The initial states of vectors X (B, p): the first sample in each one's frame, fitted
        strut by strut, then changed by its initial-state unknowns."""
        X = np.atleast_2d(X)
        n, k = self.n_params, len(initial.INITIAL_NAMES)
        fitted = len(self.names) >= n + k and self.names[n] == initial.INITIAL_NAMES[0]
        D = self.values(X)[:, n : n + k] if fitted else np.zeros((len(X), k))
        groups, out = self._frames(X), []
        for rows in groups:
            R, o = self.frame(X[rows[0]])
            p = self.m.nodes[:3] @ R.T + o
            u = initial.node_velocities(p, self.g.index[:3], self.g.h)
            out.append(initial.perturbed(initial.state_from(p[0], u), D[rows]))
        s = d.State.concat(out)
        return s if len(groups) == 1 else s.take(np.argsort(np.concatenate(groups), kind="stable"))

    def params_of(self, X: np.ndarray) -> Params:
        """The Params of vectors X (B, p): the fitted fields as arrays (B,)."""
        V = self.values(np.atleast_2d(X))
        own = {name: V[:, j].copy() for j, name in enumerate(self.fit) if not name.startswith(ACTUATOR)}
        return self.params.replace(**own)

    def motors_of(self, X: np.ndarray) -> TwistedString | None:
        """The twisted strings of vectors X (B, p): their fitted fields as arrays (B,)."""
        if self.motors is None:
            return None
        V = self.values(np.atleast_2d(X))
        own = {name[len(ACTUATOR) :]: V[:, j].copy() for j, name in enumerate(self.fit) if name.startswith(ACTUATOR)}
        return self.motors.replace(**own)

    def constants(self, theta: np.ndarray) -> np.ndarray:
        """Every number the simulator reads that the fitted parameters theta (n,) (their own
        units) set: the packed Params and, for a run in volts, the strings' (T1)-(T5) constants."""
        n = self.n_params
        x = np.concatenate([np.asarray(theta, float) / self.units[:n], self.x0[n:]])[None]
        prm, motors = self.params_of(x), self.motors_of(x)
        packed = prm.pack(1)[0]
        return packed if motors is None else np.concatenate([packed, motors.pack(prm, 1, self.dt)[0]])

    def simulate(self, X: np.ndarray) -> np.ndarray:
        """Simulated nodes (B, T, 12, 3) m (world) at the measured samples, vectors X (B, p), in
        one batched simulation. Raises SimulationError or ValueError (invalid parameters)."""
        X = np.atleast_2d(X)
        prm, s0 = self.params_of(X), self.state(X)
        _, tr = d.simulate(prm, s0, self.sched, self.terrain, self.dt, self.every, motors=self.motors_of(X))
        S = np.asarray(prm.strut_length, float)  # (B,) only if fitted
        if S.ndim:
            first = np.stack([d.nodes(s0.x[b], s0.q[b], S[b]) for b in range(len(X))])[:, None]
        else:
            first = d.nodes(s0.x, s0.q, S)[:, None]
        rec = tr.nodes(S)[:, self.g.index[1:] - 1]
        return np.concatenate([first, rec], axis=1)

    def per_sample(self, sim: np.ndarray, X: np.ndarray) -> np.ndarray:
        """The residual (B, T, M) m of simulated nodes sim (B, T, 12, 3) of vectors X (B, p),
        NaN where not measured (module docstring: M 36 coordinates or 24 cable lengths)."""
        X = np.atleast_2d(X)
        if self.residual == "shape":  # the measured lengths do not depend on the frame
            return lengths(sim) - lengths(self.m.nodes)
        out = np.empty((len(X), *self.mask.shape))
        for rows in self._frames(X):  # the measured nodes once per frame
            out[rows] = sim[rows] - self.measured(X[rows[0]])
        return out.reshape(len(X), len(self.mask), -1)

    def residuals(self, X: np.ndarray) -> np.ndarray:
        """Simulated minus measured (B, N) m, the N measured entries of `per_sample`."""
        X = np.atleast_2d(X)
        return self.per_sample(self.simulate(X), X)[:, self.valid]


def problem(
    m: Measurement,
    params: Params,
    fit: tuple[str, ...],
    mode: str,
    dt: float,
    fit_initial: bool = True,
    fit_frame: bool = True,
    motors: TwistedString | None = None,
    residual: str = "positions",
) -> Problem:
    """The calibration problem of measurement m: fit the Params fields `fit` (start: `params`;
    with `motors`, a run in volts, also `ACTUATOR_FITTABLE` keys, start: `motors`) in `mode`
    ('free': no gravity, no ground; 'grounded': flat ground at z = 0), simulating with time step
    dt s; with the initial state (`fit_initial`) and, grounded, the frame (`fit_frame`) fitted
    too; `residual` of `RESIDUALS`. ValueError naming a bad field, mode, actuator, residual or
    time step before any simulation."""
    if mode not in MODES:
        raise ValueError(f"mode {mode!r}: use one of {MODES}")
    if residual not in RESIDUALS:
        raise ValueError(f"residual {residual!r}: use one of {RESIDUALS}")
    _check_actuator(m, motors)
    if not fit:
        raise ValueError("fit: name at least one parameter")
    for name in fit:
        _check_name(name, mode, motors)
        if _start(name, params, motors) == 0.0:
            key = name if name.startswith(ACTUATOR) else f"params.{name}"
            raise ValueError(f"fit: {name} starts at 0; give it a non-zero starting value (--set {key}=...)")
    if len(set(fit)) != len(fit):
        raise ValueError(f"fit: a parameter is named twice in {', '.join(fit)}")
    g = grid(m.t)
    if not whole_steps(g.h, dt):
        raise ValueError(f"sim.dt = {dt} s does not divide the sampling interval {g.h!r} s")
    every = int(round(g.h / dt))
    g = Grid(every * dt, g.index)
    prm, terrain = (params.replace(gravity=0.0), Terrain.none()) if mode == "free" else (params, Terrain.flat())
    names = tuple(fit) + (initial.INITIAL_NAMES if fit_initial else ())
    units = [_start(k, params, motors) for k in fit] + [UNIT[n.split("_", 1)[1]] for n in names[len(fit) :]]
    if mode == "grounded":
        R, o = initial.level_frame(m.nodes[0], float(params.strut_radius))
        if fit_frame:
            names += initial.FRAME_NAMES
            units += [UNIT[n] for n in initial.FRAME_NAMES]
    else:
        R, o = np.eye(3), np.zeros(3)
    x0 = np.concatenate([np.ones(len(fit)), np.zeros(len(names) - len(fit))])
    # a node with a NaN coordinate is left out of its sample (the frame mixes the coordinates)
    mask = np.repeat(np.isfinite(m.nodes).all(axis=-1, keepdims=True), 3, axis=-1)
    centre = (m.nodes[0] @ R.T + o).mean(axis=0)
    valid = np.isfinite(lengths(m.nodes)) if residual == "shape" else mask.reshape(len(mask), -1)
    return Problem(
        m,
        g,
        schedule(m, g),
        dt,
        every,
        mode,
        terrain,
        prm,
        tuple(fit),
        names,
        np.array(units),
        x0,
        R,
        o,
        centre,
        mask,
        motors,
        residual,
        valid,
    )


def lengths(nodes: np.ndarray) -> np.ndarray:
    """The cable lengths (..., 24) m of node positions (..., 12, 3) m (NaN where an end is)."""
    a, b = topo.CABLES[:, 0], topo.CABLES[:, 1]
    return np.linalg.norm(nodes[..., a, :] - nodes[..., b, :], axis=-1)


def _start(name: str, params: Params, motors: TwistedString | None) -> float:
    """The starting value of the fitted `name` (a Params field or an actuator key)."""
    if name.startswith(ACTUATOR):
        return float(np.asarray(getattr(motors, name[len(ACTUATOR) :])))
    return float(np.asarray(getattr(params, name)))


def _check_actuator(m: Measurement, motors: TwistedString | None) -> None:
    """A run in volts is replayed with twisted strings, a run in MPa with the muscles."""
    if m.command == "voltage" and motors is None:
        raise ValueError(
            f"{m.source or 'the measurement'} is driven in volts: it is replayed with the prototype's twisted "
            "strings; give motors (the actuator.twisted_string section)"
        )
    if m.command == "pressure" and motors is not None:
        raise ValueError(
            f"{m.source or 'the measurement'} is driven by pressures (MPa): it is replayed with the pneumatic "
            "muscles, not the twisted strings; give no motors, or a run in volts (voltage_cmd, v1 .. v12)"
        )


def _check_name(name: str, mode: str, motors: TwistedString | None) -> None:
    """ValueError if `name` cannot be fitted, or has no effect, in this mode and actuator."""
    fittable = FITTABLE + (ACTUATOR_FITTABLE if motors is not None else ())
    if name not in fittable:
        hint = "" if motors is not None or name not in ACTUATOR_FITTABLE else " (a run driven by pressures)"
        raise ValueError(
            f"fit: {name!r} is not a parameter that can be fitted{hint}; use some of {', '.join(fittable)}"
        )
    if mode == "free" and name in _GROUND_ONLY:
        raise ValueError(f"fit: {name} has no effect in the free mode (no gravity, no ground)")
    if motors is not None and name in _MUSCLE_ONLY:
        raise ValueError(
            f"fit: {name} has no effect in a run driven in volts (the twisted strings replace the muscles' "
            f"eq. 1-2); fit their keys: {', '.join(ACTUATOR_FITTABLE)}"
        )
