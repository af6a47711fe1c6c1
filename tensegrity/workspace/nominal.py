"""Nominal CoG: the average of the CoG over the samples of each pressure level (paper III.A), and
the nominal CoG of one contact case as a typed value: `Nominal` (one pair at a time, the file
results/nominal/{contact}.nc) and `TwoPairNominal` (two pairs, results/two_pair/{contact}.nc)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..physics import frames
from ..physics import topology as topo
from .mapping import all_pairs

MODES = ("free", "grounded")
METHODS = ("averaging", "statics")  # how a nominal CoG is made (nominal.method)


@dataclass(frozen=True)
class Nominal:
    """The nominal CoG of one contact case over all N_PAIRS pairs: contact ('equilateral' or
    'isosceles'), the face (1..20) the robot stands on, the sweep's mode ('free' or 'grounded'),
    levels (P,) MPa, pairs (n,) the 1-based pairs swept; cog (12, P, 3) m and support
    (12, P, 3, 3) m (mean deformed triangle) in the face's support frame, margin (12, P) m
    (positive inside), all NaN for the pairs not swept (and, in the grounded mode, from the
    level the robot rolled off its face on); averaging_error (12, P) m the estimated error of
    each average (`averaging_error`), None if the file predates it; method how the nominal was
    made, 'averaging' (the sweeps' means) or 'statics' (the static equilibria, nominal.method).
    Build it from the swept pairs with `of_pairs`."""

    contact: str
    face: int
    mode: str
    levels: np.ndarray
    pairs: np.ndarray
    cog: np.ndarray
    support: np.ndarray
    margin: np.ndarray
    averaging_error: np.ndarray | None = None
    method: str = "averaging"

    def __post_init__(self):
        if self.mode not in MODES:
            raise ValueError(f"nominal mode must be one of {MODES}, got {self.mode!r}")
        if self.method not in METHODS:
            raise ValueError(f"nominal method must be one of {METHODS}, got {self.method!r}")
        topo.face_number(self.face)  # ValueError unless 1..20
        P = np.shape(self.levels)[0]
        for name, shape in (
            ("cog", (topo.N_PAIRS, P, 3)),
            ("support", (topo.N_PAIRS, P, 3, 3)),
            ("margin", (topo.N_PAIRS, P)),
            ("averaging_error", (topo.N_PAIRS, P)),
        ):
            if getattr(self, name) is None:
                continue
            got = np.shape(getattr(self, name))
            if got != shape:
                raise ValueError(f"nominal {name} must have shape {shape}, got {got}")

    @classmethod
    def of_pairs(
        cls,
        contact: str,
        face: int,
        mode: str,
        levels: ArrayLike,
        pairs: ArrayLike,
        cog: ArrayLike,
        support: ArrayLike,
        margin: ArrayLike,
        averaging_error: ArrayLike | None = None,
        method: str = "averaging",
    ) -> Nominal:
        """From the swept 1-based `pairs` (n,): cog (n, P, 3) m, support (n, P, 3, 3) m,
        margin (n, P) m and averaging_error (n, P) m (or None) at `levels` (P,) MPa, spread over
        all pairs (`mapping.all_pairs`); `method` as the field."""
        pairs = np.asarray(pairs)
        return cls(
            str(contact),
            int(face),
            str(mode),
            np.asarray(levels, float),
            pairs,
            *(all_pairs(pairs, a) for a in (cog, support, margin)),
            None if averaging_error is None else all_pairs(pairs, averaging_error),
            str(method),
        )


@dataclass(frozen=True)
class TwoPairNominal:
    """The nominal CoG of one contact case with two pairs driven at once: contact, the face
    (1..20) it stands on, levels (P,) MPa of both pairs; per combination (66, the rows of
    `workspace.two_pair.COMBOS`) and grid point (P, P) (the first pair at levels[i], the second
    at levels[j]) cog (66, P, P, 3) m in the face's support frame (NaN: not available), and the
    least equal pressure of both pairs at which the CoG projection leaves the triangle,
    tip_pressure (66,) MPa (NaN: never); averaging_error (66, P, P) m the estimated error of
    each swept grid point's average (`averaging_error`; NaN: mapped), None if the file predates
    it."""

    contact: str
    face: int
    levels: np.ndarray
    cog: np.ndarray
    tip_pressure: np.ndarray
    averaging_error: np.ndarray | None = None


def nominal(
    t: ArrayLike,
    level: ArrayLike,
    cog: np.ndarray,
    support: np.ndarray,
    n_levels: int,
    hold: float,
    discard: float = 0.0,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Average one sweep per level.

    t (T,) s; level (T,) index of the level held at each sample (-1 while settling);
    cog (T, 3) m and support (T, 3, 3) m in the support frame; the first `discard` s of
    each level (the rise after the pressure step) are left out.
    Returns cog (n, 3) m, cog_std (n, 3) m (the oscillation spread), support (n, 3, 3) m
    (the mean deformed triangle) and margin (n,) m (signed distance of the CoG projection to
    that triangle's boundary, positive inside)."""
    t, level = np.asarray(t), np.asarray(level)
    out_c, out_s, out_t = (np.empty((n_levels, 3)), np.empty((n_levels, 3)), np.empty((n_levels, 3, 3)))
    for k in range(n_levels):
        sel = window(t, level, k, hold, discard)
        out_c[k], out_s[k], out_t[k] = cog[sel].mean(0), cog[sel].std(0), support[sel].mean(0)
    margin = frames.margin_2d(out_c[:, :2], out_t[:, :, :2])
    return out_c, out_s, out_t, margin


def window(t: np.ndarray, level: np.ndarray, k: int, hold: float, discard: float) -> np.ndarray:
    """Mask (T,) of the samples level k is averaged over: those of the level (`level` (T,)
    index per sample at times t (T,) s) after its first `discard` s. ValueError if none."""
    sel = level == k
    if not sel.any():
        raise ValueError(f"no samples for pressure level {k}")
    start = t[sel].min() - (t[1] - t[0] if t.size > 1 else 0.0)
    sel &= t > start + discard
    if not sel.any():
        raise ValueError(f"discard = {discard} s leaves no samples of level {k} (hold {hold} s)")
    return sel


def averaging_error(
    t: ArrayLike, level: ArrayLike, cog: np.ndarray, n_levels: int, hold: float, discard: float = 0.0
) -> np.ndarray:
    """Estimated error (n_levels,) m of each level's nominal CoG (`nominal`, same arguments) from
    the oscillation left in its window: a quarter of the range of the means of all half-length
    sub-windows (per axis, then the length of that vector).

    A sinusoid A sin(w t + phi) shifts the mean of a window of length W by up to
    (2A / wW) |sin(wW / 2)|, depending on phi; the means of the half windows, sliding through the
    phases, range over twice (4A / wW) |sin(wW / 4)|: the estimate (2A / wW) |sin(wW / 4)| is at
    least half that worst case, and on average over periods equal to it (~ A T / (pi W), T the
    period). A drift of rate r reads r W / 8 (the mean is off by up to r W / 2 from the end value).
    Measured on the default robot (both contact cases, 12 pairs, holds 0.5-2 s, 0.4 and 1.2 MPa
    steps; issue 34), estimate / distance to the static equilibrium: 10th percentile 0.84-1.6,
    median 1.4-4.6 (that distance holds ~0.01-0.02 mm that is not averaging). NaN for a window
    of fewer than 2 samples. Not included: motion after the window (volts at 3 V held 120 s: about
    0.4 mm, `benchmarks/bench_creep.py`, docs/benchmarks.md)."""
    t, level, cog = np.asarray(t), np.asarray(level), np.asarray(cog, float)
    out = np.full(n_levels, np.nan)
    for k in range(n_levels):
        x = cog[window(t, level, k, hold, discard)]  # a level's samples are consecutive
        h = x.shape[0] // 2
        if h:
            cs = np.cumsum(np.concatenate([np.zeros((1, 3)), x]), axis=0)
            means = (cs[h:] - cs[:-h]) / h  # every window of h consecutive samples
            out[k] = 0.25 * float(np.linalg.norm(np.ptp(means, axis=0)))
    return out


def first_roll(level: ArrayLike, on_face: ArrayLike, n_levels: int) -> int:
    """Index of the first level at whose end the robot no longer stands on its contact face
    (on_face False at the level's last sample: a pressure step can make the feet hop, which
    is not a roll), or n_levels if it never left it (always so in the free mode)."""
    level, on_face = np.asarray(level), np.asarray(on_face, bool)
    for k in range(n_levels):
        idx = np.flatnonzero(level == k)
        if idx.size and not on_face[idx[-1]]:
            return k
    return n_levels


def mask_after_roll(levels: Sequence[float] | np.ndarray, k: int, tip: float, *arrays: np.ndarray) -> float:
    """A grounded robot that rolled off its face at level index `k` (first_roll): from that
    level on the numbers are not of this face any more, so `arrays` (P, ...) become NaN in
    place, and the roll counts as the tip. Returns the tipping pressure (MPa): `tip` if the
    margin already crossed zero at or below levels[k], else levels[k]."""
    if k >= len(levels):
        return tip
    for a in arrays:
        a[k:] = np.nan
    return float(tip) if tip <= levels[k] else float(levels[k])


def levels_stood(cog: np.ndarray, rolled: ArrayLike | None = None) -> int:
    """Number of levels before a grounded robot rolled off its face: the leading levels whose
    nominal CoG (P, 3) m is finite and, if given, whose `rolled` (P,) flag is 0 (all P in the
    free mode)."""
    stood = np.isfinite(cog).all(axis=-1)
    if rolled is not None:
        stood &= np.asarray(rolled) == 0
    return int(np.argmin(stood)) if not stood.all() else len(stood)
