"""Measurements made by our own simulator, for tests, benchmarks and examples: a robot standing
on a face, driven by pressure steps (or voltage steps of the twisted strings), sampled at a rate
with Gaussian noise on every coordinate, in a frame that may be turned and shifted."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ..physics import dynamics as d
from ..physics import topology as topo
from ..physics.params import Params
from ..physics.schedule import Schedule
from ..physics.terrain import Terrain
from ..physics.twisted import TwistedString, Voltages
from .measurement import Measurement

__all__ = ["excitation", "twisting", "measure"]


def excitation(duration: float, hold: float = 0.5, pairs: ArrayLike = (1, 5, 10), level: float = 2.0) -> np.ndarray:
    """Pressure steps (K, 12) MPa, one per `hold` s over `duration` s: at rest (so that a robot
    standing still stays still over the first samples), then each pair of `pairs` in turn at
    `level`, then at half of it with the next, and again."""
    pairs = [topo.check_pair(p) for p in np.atleast_1d(pairs)]
    K = max(1, int(round(duration / hold)))
    out = np.zeros((K, topo.N_PAIRS))
    for k in range(K):
        j, phase = (k // 3) % len(pairs), k % 3
        if phase == 1:
            out[k, pairs[j] - 1] = level
        elif phase == 2:
            out[k, pairs[j] - 1] = 0.5 * level
            out[k, pairs[(j + 1) % len(pairs)] - 1] = level
    return out


def twisting(
    duration: float,
    up: float = 3.0,
    pairs: ArrayLike = (1, 5, 10),
    level: float = 24.0,
    rest: float = 0.2,
    hold: float = 0.1,
) -> np.ndarray:
    """Voltage steps (K, 12) V for the twisted strings, one per `hold` s over `duration` s: at rest
    for `rest` s, then `pairs` at +level for `up` s, at -level for `up` s, and again. A string
    contracts as the square of its twist (c ~ (theta r)^2 / 2 L0), which takes seconds to build
    (24 V: 3 s to ~27 mm of node motion; 0.2 s steps move the nodes by under 1 mm), and the
    reversal untwists it through zero to the other side."""
    pairs = np.array([topo.check_pair(p) for p in np.atleast_1d(pairs)]) - 1
    K = max(1, int(round(duration / hold)))
    out = np.zeros((K, topo.N_PAIRS))
    t = np.arange(K) * hold - rest  # the start of each step after the rest
    on = t >= -1e-9
    sign = np.where((np.floor(t / up + 1e-9).astype(int) % 2) == 0, 1.0, -1.0)
    out[np.ix_(on, pairs)] = level * sign[on, None]
    return out


def measure(
    params: Params,
    steps: np.ndarray,
    hold: float,
    mode: str = "free",
    rate: float = 100.0,
    dt: float = 1e-4,
    face: int = 8,
    noise: float = 0.0,
    seed: int = 0,
    rotation: np.ndarray | None = None,
    offset: ArrayLike = (0.0, 0.0, 0.0),
    motors: TwistedString | None = None,
) -> Measurement:
    """The robot standing on `face`, driven by `steps` (K, 12) MPa each held `hold` s, in `mode`
    ('free' or 'grounded' on flat ground), simulated with time step dt s and sampled at `rate` Hz
    from t = 0 (the state at rest) with Gaussian noise of `noise` m on every coordinate (seeded),
    seen in a frame where measured = rotation^T (world - offset). With `motors` the robot has the
    twisted strings (untwisted at t = 0) and `steps` are pair voltages in V."""
    prm, terrain = (params.replace(gravity=0.0), Terrain.none()) if mode == "free" else (params, Terrain.flat())
    every = int(round(1 / (rate * dt)))
    state = d.stand_on(prm, face, terrain)
    kind = Schedule if motors is None else Voltages
    sched = kind(np.full(len(steps), hold), np.asarray(steps, float)[None])
    _, tr = d.simulate(prm, state, sched, terrain, dt, every, motors=motors)
    p = np.concatenate([d.nodes(state.x, state.q, prm.strut_length), tr.nodes(prm.strut_length)[0]])
    u = np.concatenate([np.zeros((1, topo.N_PAIRS)), tr.pressure[0]])
    t = np.concatenate([[0.0], tr.t])
    R = np.eye(3) if rotation is None else np.asarray(rotation, float)
    p = (p - np.asarray(offset, float)) @ R
    p = p + np.random.default_rng(seed).normal(0.0, noise, p.shape) if noise > 0 else p
    source = f"simulated ({mode}, {rate:g} Hz, noise {noise * 1e3:g} mm, seed {seed})"
    return Measurement(t, p, u, mode, source, "pressure" if motors is None else "voltage")
