"""The model a calibration fits (docs/design.md §9): the measured node positions against the
simulated ones, as a function of one vector of unknowns in scaled units, evaluated for many
vectors at once as one batched simulation (one robot per vector).

The unknowns, in order: the named `Params` fields (scaled by their starting values: 1 is the
start), the initial state (`initial.INITIAL_NAMES`, if fitted) and the frame's tilt and height
(`initial.FRAME_NAMES`, grounded mode, if fitted). The residual is simulated minus measured node
coordinate (m, world frame) of every sample and every node that was measured (a node with a NaN
coordinate left out of that sample); sample 0 is the initial state's own nodes.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from ..physics import dynamics as d
from ..physics.params import Params
from ..physics.schedule import Schedule, whole_steps
from ..physics.terrain import Terrain
from . import initial
from .measurement import Grid, Measurement, grid, schedule

__all__ = ["Problem", "problem", "FITTABLE", "UNIT"]

MODES = ("free", "grounded")
# Params fields a calibration may fit, and those that do nothing in the free mode (no ground)
FITTABLE = tuple(f.name for f in fields(Params) if f.name not in ("cable_rest_length", "max_speed"))
_GROUND_ONLY = ("gravity", "ground_stiffness", "ground_damping", "friction", "friction_stiffness", "friction_damping")
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
    centroid `centre` (m, world); `mask` (T, 12, 3): which coordinates were measured."""

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

    def state(self, X: np.ndarray) -> d.State:
        """The initial states of vectors X (B, p): the first sample in each one's frame, fitted
        strut by strut, then changed by its initial-state unknowns."""
        n, k = self.n_params, len(initial.INITIAL_NAMES)
        fitted = len(self.names) >= n + k and self.names[n] == initial.INITIAL_NAMES[0]
        out = []
        for x in np.atleast_2d(X):
            R, o = self.frame(x)
            p = self.m.nodes[:3] @ R.T + o
            u = initial.node_velocities(p, self.g.index[:3], self.g.h)
            s = initial.state_from(p[0], u)
            out.append(initial.perturbed(s, self.values(x)[n : n + k] if fitted else np.zeros(k)))
        return d.State.concat(out)

    def params_of(self, X: np.ndarray) -> Params:
        """The Params of vectors X (B, p): the fitted fields as arrays (B,)."""
        V = self.values(np.atleast_2d(X))
        return self.params.replace(**{name: V[:, j].copy() for j, name in enumerate(self.fit)})

    def simulate(self, X: np.ndarray) -> np.ndarray:
        """Simulated nodes (B, T, 12, 3) m (world) at the measured samples, vectors X (B, p), in
        one batched simulation. Raises SimulationError or ValueError (invalid parameters)."""
        X = np.atleast_2d(X)
        prm, s0 = self.params_of(X), self.state(X)
        _, tr = d.simulate(prm, s0, self.sched, self.terrain, self.dt, self.every)
        S = np.broadcast_to(np.asarray(prm.strut_length, float), (len(X),))
        first = np.stack([d.nodes(s0.x[b], s0.q[b], S[b]) for b in range(len(X))])[:, None]
        rec = tr.nodes(S)[:, self.g.index[1:] - 1]
        return np.concatenate([first, rec], axis=1)

    def residuals(self, X: np.ndarray) -> np.ndarray:
        """Simulated minus measured coordinates (B, N) m, N the measured coordinates."""
        X = np.atleast_2d(X)
        sim = self.simulate(X)
        return np.stack([(sim[b] - self.measured(x))[self.mask] for b, x in enumerate(X)])


def problem(
    m: Measurement,
    params: Params,
    fit: tuple[str, ...],
    mode: str,
    dt: float,
    fit_initial: bool = True,
    fit_frame: bool = True,
) -> Problem:
    """The calibration problem of measurement m: fit the Params fields `fit` (start: `params`)
    in `mode` ('free': no gravity, no ground; 'grounded': flat ground at z = 0), simulating with
    time step dt s; with the initial state (`fit_initial`) and, grounded, the frame (`fit_frame`)
    fitted too. ValueError naming a bad field, mode or time step before any simulation."""
    if mode not in MODES:
        raise ValueError(f"mode {mode!r}: use one of {MODES}")
    if not fit:
        raise ValueError("fit: name at least one parameter")
    for name in fit:
        if name not in FITTABLE:
            raise ValueError(f"fit: {name!r} is not a parameter that can be fitted; use some of {', '.join(FITTABLE)}")
        if mode == "free" and name in _GROUND_ONLY:
            raise ValueError(f"fit: {name} has no effect in the free mode (no gravity, no ground)")
        if float(getattr(params, name)) == 0.0:
            raise ValueError(f"fit: {name} starts at 0; give it a non-zero starting value (--set params.{name}=...)")
    if len(set(fit)) != len(fit):
        raise ValueError(f"fit: a parameter is named twice in {', '.join(fit)}")
    g = grid(m.t)
    if not whole_steps(g.h, dt):
        raise ValueError(f"sim.dt = {dt} s does not divide the sampling interval {g.h!r} s")
    every = int(round(g.h / dt))
    g = Grid(every * dt, g.index)
    prm, terrain = (params.replace(gravity=0.0), Terrain.none()) if mode == "free" else (params, Terrain.flat())
    names = tuple(fit) + (initial.INITIAL_NAMES if fit_initial else ())
    units = [float(getattr(params, k)) for k in fit] + [UNIT[n.split("_", 1)[1]] for n in names[len(fit) :]]
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
    return Problem(
        m, g, schedule(m, g), dt, every, mode, terrain, prm, tuple(fit), names, np.array(units), x0, R, o, centre, mask
    )
