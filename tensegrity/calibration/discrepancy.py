"""Intervals with model discrepancy (docs/design.md §9, issue 32): a grounded fit whose residuals
say the model does not reproduce the run (`misfit`) gets the interval of refits on WINDOWS
disjoint time windows instead of none.

A wrong model (MuJoCo's contact against ours) biases the estimates by an amount that does not
shrink with more samples: the classical intervals (`uncertainty`), and a sandwich with the
residuals' autocorrelation (Newey-West, 2-6 times wider), held no truth (docs/benchmarks.md). What
does reflect the bias is how much the estimate moves when the same model is fitted to another
stretch of the run: each window is calibrated on its own (its own initial state from its first
samples, started from the whole run's estimate), and the spread of the window estimates about the
whole run's stands for the error of the whole run's estimate. This is subsampling (Politis and
Romano, Ann. Statist. 22, 1994, 2031-2050; Politis, Romano and Wolf, "Subsampling", Springer
1999, ch. 3 and 8) with non-overlapping blocks and a rate of convergence of 1: a bias does not
average out, so the window spread is not scaled down by sqrt(window / run) as it would be for
independent noise (Bertail, Politis and Romano, JASA 94, 1999: the rate is what sets that
scaling). In log-parameters (positive, fitted as multiples of their start):

    d_w = ln(theta_w / theta^),  s^2 = sum_w d_w^2 / (K - 1),  95 %: theta^ exp(+- t_{0.975, K-1} s)   (W1)

(K the windows whose fit succeeded, Student's t for s estimated from K values). The interval is
clipped to the fit's bounds (1/100 to 100 times the start: 'windows, open below/above'). Where
the residuals are independent the classical interval stays (the windows are not fitted), so a
right model keeps its intervals bit for bit; the free mode refits none unless asked (`count`).
K = WINDOWS was chosen among 3, 4, 6 on the tuning seeds 0-5 of bench_calibration_intervals.py
(docs/benchmarks.md, "Grounded intervals with model discrepancy"); no constant of (W1) was tuned.
MuJoCo's grounded runs fitted to the shape: 24 of 24 truths inside on the tuning seeds, 20 of 20
on five evaluation seeds (the damping's intervals reach the bounds: not determined). Assumed: the
windows' biases spread as far as the whole run's; a bias common to every stretch can lie outside.
Cost: the K window fits, about as much again as the fit.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np
from scipy import stats

from ..physics.dynamics import SimulationError
from .measurement import Measurement
from .misfit import REASON
from .uncertainty import Uncertainty

__all__ = ["WINDOWS", "LEAST", "UNBOUNDED", "count", "split", "interval", "dropped", "widen", "given"]

WINDOWS = 4  # disjoint time windows refitted (tuning seeds 0-5)
LEAST = 20  # samples a window needs at least (the growing horizon's first stage: `fit.horizons`)
LEVEL = 0.95
UNBOUNDED = "not determined: its windows' interval (W1) reaches the fit's bounds on both sides"


def count(windows: int | None, mode: str, samples: int) -> int:
    """The windows to refit: `windows` as given; None (the default) WINDOWS in the grounded mode if
    each window gets LEAST samples, else 0 (the free mode, or a run too short: no interval)."""
    if windows is not None:
        return windows
    return WINDOWS if mode == "grounded" and samples // WINDOWS >= LEAST else 0


def split(m: Measurement, k: int) -> list[Measurement]:
    """k disjoint windows of consecutive samples of m (as equal as the samples allow), each a
    measurement of its own, its time from its first sample (s). ValueError naming `windows` if
    k < 2 or a window would have fewer than LEAST samples."""
    T = m.t.size
    if k < 2 or T // k < LEAST:  # (also k < 0)
        raise ValueError(f"windows: {k} windows of {T} samples; give at least 2, of {LEAST} samples or more each")
    edges = np.linspace(0, T, k + 1).round().astype(int)
    return [
        Measurement(m.t[a:b] - m.t[a], m.nodes[a:b], m.pressure[a:b], m.mode, f"{m.source}[{a}:{b}]", m.command)
        for a, b in zip(edges[:-1], edges[1:], strict=True)
    ]


def interval(estimate: np.ndarray, windows: np.ndarray, level: float = LEVEL) -> tuple[np.ndarray, ...]:
    """(W1): lower, upper (n,) of the estimates (n,) from the window estimates (K, n) (a NaN row:
    a window whose fit failed, left out), and the relative spread s (n,) (NaN: fewer than 2)."""
    estimate = np.asarray(estimate, float)
    W = np.asarray(windows, float).reshape(-1, estimate.size)
    W = W[np.all(np.isfinite(W) & (W > 0), axis=1)]
    if len(W) < 2 or np.any(estimate <= 0):
        nan = np.full(estimate.size, np.nan)
        return nan, nan.copy(), nan.copy()
    d = np.log(W / estimate)
    s = np.sqrt(np.sum(d**2, axis=0) / (len(W) - 1))
    q = float(stats.t.ppf(0.5 + level / 2, len(W) - 1))
    return estimate * np.exp(-q * s), estimate * np.exp(q * s), s


def dropped(unc: Uncertainty, names: tuple[str, ...]) -> np.ndarray:
    """Which parameters (n,) bool `misfit` left without an interval (named with its REASON)."""
    said = [u for u in unc.undetermined if REASON in u]
    return np.array([any(u.startswith(f"{k} {REASON}") for u in said) for k in names])


def widen(
    unc: Uncertainty,
    names: tuple[str, ...],
    estimate: np.ndarray,
    start: np.ndarray,
    m: Measurement,
    k: int,
    refit: Callable[[Measurement], np.ndarray],
    bound: float,
    upper: np.ndarray | None = None,
) -> tuple[Uncertainty, np.ndarray]:
    """`unc` with the intervals (W1) of the parameters `names` whose intervals `misfit` dropped
    (`dropped`; the others as they were), the window estimates (n,) `refit(window)` of each of
    the k windows of m (`split`), each interval clipped to [start / bound, start * upper] (n,;
    upper None: bound; a damper's may be its stability limit, `stability`); standard error
    estimate * s (an interval open on both sides: the parameter named UNBOUNDED in
    `undetermined`); and the window estimates (k, n) (NaN rows: fits that failed; no window is
    fitted if `misfit` dropped nothing)."""
    n, lost = estimate.size, dropped(unc, names)
    W = np.full((k, n), np.nan)
    if not lost.any():
        return unc, W[:0]
    for i, w in enumerate(split(m, k)):
        try:
            W[i] = refit(w)
        except (SimulationError, ValueError):  # a window the model cannot run: left out
            continue
    lo, hi, s = interval(estimate, W)
    give = lost & np.isfinite(s)
    if not give.any():
        return replace(unc, refits=unc.refits + k, windows=W), W
    lo_b, hi_b = start / bound, start * (bound if upper is None else upper)
    method = tuple(
        ("windows" + (", open below" if lo[j] < lo_b[j] else "") + (", open above" if hi[j] > hi_b[j] else ""))
        if give[j]
        else unc.method[j]
        for j in range(n)
    )
    keep = [u for u in unc.undetermined if not any(u.startswith(f"{names[j]} {REASON}") for j in np.flatnonzero(give))]
    keep += [f"{names[j]} {UNBOUNDED}" for j in np.flatnonzero(give & (lo < lo_b) & (hi > hi_b))]
    return (
        replace(
            unc,
            se=np.where(give, estimate * s, unc.se),
            lower=np.where(give, np.maximum(lo, lo_b), unc.lower),
            upper=np.where(give, np.minimum(hi, hi_b), unc.upper),
            undetermined=tuple(keep),
            method=method,
            refits=unc.refits + k,
            windows=W,
        ),
        W,
    )


def given(
    c: object,
    calibrate: Callable[..., object],
    k: int,
    fit_initial: bool,
    fit_frame: bool,
    bound: float,
    upper: np.ndarray | None = None,
) -> object:
    """Calibration c (`fit.Calibration`) with `widen`'s intervals: each of k windows fitted by
    `calibrate` (`fit.calibrate`, no windows of its own, no check) from c's estimates, with the
    initial state (`fit_initial`) and the frame (`fit_frame`) as the whole run's; parameters
    bounded to [start / bound, start * upper] (upper (n,) None: bound)."""
    p = c.problem

    def refit(w: Measurement) -> np.ndarray:
        return calibrate(
            w, c.params, c.names, p.mode, p.dt, fit_initial, fit_frame, 0.0, c.motors, p.residual, windows=0
        ).estimate

    unc, _ = widen(c.unc, c.names, c.estimate, c.start, p.m, k, refit, bound, upper)
    return replace(c, unc=unc)
