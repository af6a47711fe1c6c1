"""A measured trajectory (`Measurement`) and how the simulator replays its commands: the sample
grid, the gaps, and the pressure schedule (docs/design.md §9).

Conventions (the same as `tensegrity simulate --out` records): node positions (T, 12, 3) m in
the measurement's own frame, pair pressures (T, 12) MPa, where the pressure of sample k is the
one applied over the interval (t[k-1], t[k]] that ends at it (a zero-order hold; the pressure of
the first sample is not used). A run of the prototype's twisted strings (docs/design.md §10) is
driven in volts instead: the same array holds pair voltages (T, 12) V (`command` 'voltage'), and
the replay is a `twisted.Voltages` schedule.

Gaps: time must increase strictly and lie on one grid t0 + k h, h the smallest interval (within
1e-6 h); rows missing from the grid are allowed (the pressure of the next row is held over the
whole gap); a NaN node coordinate is an occluded marker: that node is left out of the sample's
residual; a NaN pressure is refused (the simulator must know what was commanded). The first
sample must be complete (it fixes the initial pose).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..physics import topology as topo
from ..physics.schedule import Schedule, check_pressures
from ..physics.twisted import Voltages, check_voltages

__all__ = ["Measurement", "Grid", "grid", "schedule", "COMMANDS"]

# what the robot was driven by: its unit and its check
COMMANDS = {"pressure": ("MPa", check_pressures), "voltage": ("V", check_voltages)}

GRID_TOLERANCE = 1e-6  # of a sampling interval: a time off the grid by more is refused


@dataclass(frozen=True)
class Measurement:
    """t (T,) s; nodes (T, 12, 3) m (NaN: an occluded marker); pressure (T, 12) the command:
    pair pressures in MPa, or pair voltages in V if `command` is 'voltage'; mode 'free' or
    'grounded' if the source says so, else ''; source: what it was read from."""

    t: np.ndarray
    nodes: np.ndarray
    pressure: np.ndarray
    mode: str = ""
    source: str = ""
    command: str = "pressure"

    def __post_init__(self):
        t = np.asarray(self.t, dtype=float).reshape(-1)
        p = np.asarray(self.nodes, dtype=float)
        u = np.asarray(self.pressure, dtype=float)
        where = f" of {self.source}" if self.source else ""
        if p.shape != (t.size, topo.N_NODES, 3):
            raise ValueError(f"nodes{where}: expected shape ({t.size}, 12, 3), got {p.shape}")
        if u.shape != (t.size, topo.N_PAIRS):
            raise ValueError(f"pressure{where}: expected shape ({t.size}, 12), got {u.shape}")
        if t.size < 3:
            raise ValueError(f"measurement{where}: {t.size} samples; at least 3 are needed")
        if not np.all(np.isfinite(t)):
            raise ValueError(f"time{where}: sample {int(np.argmin(np.isfinite(t))) + 1} is not finite")
        bad = np.flatnonzero(np.diff(t) <= 0)
        if bad.size:
            k = int(bad[0])
            raise ValueError(f"time{where} does not increase: sample {k + 2} at {t[k + 1]!r} s follows {t[k]!r} s")
        if np.isinf(p).any():
            raise ValueError(f"nodes{where}: infinite coordinate at sample {int(np.argwhere(np.isinf(p))[0, 0]) + 1}")
        if not np.isfinite(p[0]).all():
            n = int(np.argwhere(~np.isfinite(p[0]))[0, 0]) + 1
            raise ValueError(f"nodes{where}: the first sample lacks node {n} (NaN); it fixes the initial pose")
        if self.command not in COMMANDS:
            raise ValueError(f"command{where}: {self.command!r} is not one of {', '.join(COMMANDS)}")
        if not np.isfinite(u).all():
            k, j = np.argwhere(~np.isfinite(u))[0]
            raise ValueError(
                f"{self.command}{where}: sample {k + 1} (t = {t[k]!r} s) has no {self.command} for pair {j + 1} (NaN)"
            )
        COMMANDS[self.command][1](u, f"{self.command}{where}")
        if self.mode not in ("", "free", "grounded"):
            raise ValueError(f"mode{where}: {self.mode!r} is not 'free' or 'grounded'")
        for name, val in (("t", t), ("nodes", p), ("pressure", u)):
            object.__setattr__(self, name, val)

    def head(self, n: int) -> Measurement:
        """The first n samples."""
        return Measurement(self.t[:n], self.nodes[:n], self.pressure[:n], self.mode, self.source, self.command)


@dataclass(frozen=True)
class Grid:
    """The sample grid: interval h s, and index (T,) of each sample on it (index[0] = 0)."""

    h: float
    index: np.ndarray


def grid(t: np.ndarray) -> Grid:
    """The grid t0 + k h of increasing times t (T,) s, h the smallest interval; ValueError naming
    the first sample off it (by more than GRID_TOLERANCE h)."""
    h = float(np.min(np.diff(t)))
    k = (t - t[0]) / h
    idx = np.rint(k).astype(np.int64)
    off = np.flatnonzero(np.abs(k - idx) > GRID_TOLERANCE)
    if off.size:
        i = int(off[0])
        raise ValueError(f"time: sample {i + 1} at {t[i]!r} s is not on the sampling grid t0 + k * {h!r} s")
    return Grid(h, idx)


def schedule(m: Measurement, g: Grid) -> Schedule:
    """The pressures of m as a `Schedule` (its voltages as `Voltages`) starting at t[0], in
    segments of whole sampling intervals: sample k's command over (t[k-1], t[k]], consecutive
    equal commands merged."""
    steps = np.diff(g.index)
    durations, levels = [], []
    for k in range(1, m.t.size):
        if levels and np.array_equal(levels[-1], m.pressure[k]):
            durations[-1] += steps[k - 1]
        else:
            durations.append(int(steps[k - 1]))
            levels.append(m.pressure[k])
    kind = Voltages if m.command == "voltage" else Schedule
    return kind(np.array(durations, float) * g.h, np.array(levels)[None])
