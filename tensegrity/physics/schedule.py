"""Pressure schedules: pressures (MPa) per pair or per cable held over time segments, and their
check (the law that turns a pressure into a cable force is `actuator`); the hold of a ramp
(`hold_step`)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from . import topology as topo

MAX_PRESSURE = 10.0  # MPa; a McKibben muscle is rated well below this


def check_pressures(p: ArrayLike, name: str = "pressure") -> np.ndarray:
    """Return p as float array; raise ValueError naming `name` if any value is NaN or outside
    [0, MAX_PRESSURE] MPa."""
    a = np.asarray(p, dtype=float)
    if (a >= 0).all() and (a <= MAX_PRESSURE).all():  # the usual case (NaN fails both)
        return a
    bad = ~np.isfinite(a) | (a < 0) | (a > MAX_PRESSURE)
    if np.any(bad):
        raise ValueError(f"{name}: {float(a[bad].ravel()[0])!r} MPa is outside 0..{MAX_PRESSURE} MPa")
    return a


def whole_steps(duration: float, step: float) -> bool:
    """Whether `duration` is a whole number of `step`s (within 1e-6 of a step): an interval of
    time steps (s), a hold of recording intervals (s), a grid of ramp increments (MPa)."""
    n = duration / step
    return abs(n - round(n)) <= 1e-6


def hold_step(
    holding: ArrayLike,
    held: ArrayLike,
    armed: ArrayLike,
    lifted: ArrayLike,
    interval: float,
    hold_time: float,
    rearm: bool,
    spent: ArrayLike = 0.0,
    budget: float = np.inf,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The hold of a pressure ramp (`locomotion.control.roll`, `workspace.gravity.ramp`), one
    check of robots (...) after an `interval` s: a support node lifted (`lifted`, bool) starts a
    hold of the pressure if `armed`; it ends hold_time s later, and the ramp goes on. holding
    (...) bool, the pressure was held over the interval; held (...) s, for how long before it;
    spent (...) s, all holds before it. A hold that ran out leaves the robot armed if `rearm`
    (held again while a node is up), else not until none is; none starts once `spent` reaches
    `budget` s. Returns holding, held, armed and spent after the check. One robot given as Python
    bools and floats (a roll's check) gets them back as such: the same numbers, without numpy."""
    if type(holding) is type(armed) is type(lifted) is bool and type(held) is type(spent) is float:
        held = held + interval if holding else held
        spent = spent + interval if holding else spent
        ends = holding and held >= hold_time - 1e-9
        armed = armed or not lifted
        begins = not holding and lifted and armed and spent < budget - 1e-9
        held, armed = 0.0 if begins else held, rearm if ends else armed
        return (holding and not ends) or begins, held, armed, spent
    holding, armed, lifted = (np.asarray(a, bool) for a in (holding, armed, lifted))
    held = np.where(holding, held + interval, held)
    spent = np.where(holding, spent + interval, spent)
    ends = holding & (held >= hold_time - 1e-9)
    armed = armed | ~lifted
    begins = ~holding & lifted & armed & (spent < budget - 1e-9)
    held, armed = np.where(begins, 0.0, held), np.where(ends, rearm, armed)
    return (holding & ~ends) | begins, held, armed, spent


@dataclass(frozen=True)
class Schedule:
    """Piecewise-constant pressures: segment k lasts durations[k] s with pressure
    pressure[:, k, :] MPa, shape (B, K, 12) per pair or (B, K, 24) per cable (the prototype's 24
    actuators; `topology.cable_levels`), B may be 1 for the whole batch. A subclass may hold
    another actuation level by its own `check` (`twisted.Voltages`: volts)."""

    durations: np.ndarray
    pressure: np.ndarray

    check = staticmethod(check_pressures)  # the levels' check: a class attribute, not a field

    def __post_init__(self):
        d = np.asarray(self.durations, dtype=float).reshape(-1)
        p = self.check(self.pressure)
        if p.ndim == 2:
            p = p[None]
        if p.ndim != 3 or p.shape[1] != d.size or p.shape[2] not in (topo.N_PAIRS, topo.N_CABLES):
            raise ValueError(f"schedule pressure must have shape (B, {d.size}, 12 or 24), got {p.shape}")
        if not np.all(np.isfinite(d)) or np.any(d <= 0):
            raise ValueError(f"schedule durations must be positive seconds, got {d.tolist()}")
        object.__setattr__(self, "durations", d)
        object.__setattr__(self, "pressure", p)

    @property
    def per_cable(self) -> bool:
        """Whether the levels are one per cable (24), not one per pair (12)."""
        return self.pressure.shape[-1] == topo.N_CABLES

    @property
    def duration(self) -> float:
        return float(self.durations.sum())

    @classmethod
    def constant(cls, pressure: ArrayLike, duration: float) -> Schedule:
        """Pressures (B, 12) or (12,) MPa per pair, or (B, 24) or (24,) per cable, held for
        `duration` s."""
        p = np.asarray(pressure, dtype=float)
        n = p.shape[-1] if p.ndim and p.shape[-1] in (topo.N_PAIRS, topo.N_CABLES) else topo.N_PAIRS
        if p.size % n:
            raise ValueError(f"pressures must be (B, 12 or 24) or (12 or 24,), got shape {p.shape}")
        return cls(np.array([duration]), p.reshape(-1, 1, n))

    @classmethod
    def staircase(cls, pairs: ArrayLike, levels: ArrayLike, hold: float, settle: float = 0.0) -> Schedule:
        """The paper's sweep (III.A): robot b drives pair pairs[b] (1-based) through `levels`
        MPa, each held `hold` s, after `settle` s at zero pressure."""
        pairs = [topo.check_pair(p) for p in np.atleast_1d(pairs)]
        levels = cls.check(levels, "pressure levels")
        segs = ([0.0] if settle > 0 else []) + list(levels)
        p = np.zeros((len(pairs), len(segs), topo.N_PAIRS))
        for b, pair in enumerate(pairs):
            p[b, :, pair - 1] = segs
        d = ([settle] if settle > 0 else []) + [hold] * len(levels)
        return cls(np.array(d), p)
