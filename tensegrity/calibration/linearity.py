"""Whether a calibration's linearised intervals hold (docs/design.md §9).

The linearised interval of a parameter (`uncertainty`) assumes the model linear over it.
Along the direction in which the covariance moves every unknown with that parameter's +- q
standard errors (q = t_0.975), the cost should rise by q^2 s^2; the fit
evaluates it at both ends (one batched simulation, 2 robots per parameter), and a parameter whose
rise is off by more than a factor LINEAR (1.25) at either end gets the interval of its profile
likelihood instead (`profile`: the other unknowns refitted; given a refit, as `fit` does), or,
without one or if the profile fails, none, and is named as too weakly determined. A rise 1/1.25
of the prediction puts the likelihood interval's end sqrt(1.25) = 1.12 times further out, so an
interval that passes covers at least ~92 % instead of 95 % (2 Phi(1.96 / 1.12) - 1); a rise faster
than predicted says the model curves
over the interval (the valley of the cost may bend away from the line). 1.5 (~89 %) let a
stiffness 10 standard errors off through at rises 1.09 and 1.45 (run in volts, seed 161082 of
the coverage test). Measured (0.5 mm of noise): the free mode with the muscles, 0.98-1.02 (two
seeds); runs in volts twisted up and back for 3 s each (`synthetic.twisting`, 20 seeds), the
strings' stiffness and pretension 0.88-4.1, their stall torque 0.92-1.09; with the damping
fitted too (three seeds) 0.9-24 (the slow twisting sees the damping
to 30-200 % of its value). The rise is not a profile (the other unknowns are moved along the
line, not refitted): a valley that curves away from that line passes it (docs/design.md §9).
Below a residual of FLOOR m (a noise-free check) the intervals are round-off wide and the check
is not made.

An end whose cost is below the fit's by more than `margin` (the fit was not the minimum) raises
`profile.Lower` with that point, as a refit of the profile that ends there does: the fit restarts
from it (`minima.settle`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np
from scipy import stats

from ..physics.dynamics import SimulationError
from . import model as mdl
from . import profile
from .uncertainty import Uncertainty, normal_inverse

__all__ = ["LINEAR", "FLOOR", "rises", "linear", "margin"]

LINEAR = 1.25  # an interval holds if the cost at its ends rises by q^2 s^2 within this factor
FLOOR = 1e-8  # m: a residual standard deviation below this is a noise-free fit (no check)


def steps(J: np.ndarray, unc: Uncertainty, n: int) -> tuple[np.ndarray, np.ndarray]:
    """The parameters with a linearised interval (k,) and the step (n, p) in scaled unknowns to
    the + end of each one's interval, every unknown moved with it along its covariance column
    (the linearised conditional optimum; rows of the others NaN); J (N, p) scaled, at x^."""
    keep = np.flatnonzero(np.isfinite(unc.se))
    V = np.full((n, J.shape[1]), np.nan)
    if keep.size:
        cols = np.concatenate([keep, np.arange(n, J.shape[1])])
        C = normal_inverse(J[:, cols])
        V[keep] = 0.0
        V[np.ix_(keep, cols)] = _q(unc) * unc.s * (C[:, : keep.size] / np.sqrt(np.diag(C)[: keep.size])).T
    return keep, V


def _q(unc: Uncertainty) -> float:
    """t_{0.975, N-p}, the quantile of `uncertainty`."""
    return float(stats.t.ppf(0.975, unc.dof))


def margin(J: np.ndarray, r: np.ndarray) -> float:
    """How far (m^2) below the fit's cost |r|^2 a point must be to say the fit was not the
    minimum: the larger of what the fit's own linear model says is still to gain at its optimum,
    |J (J^T J)^-1 J^T r|^2 (a fit stopped by `fit.STOP` or a tolerance: a point that far below is
    the same minimum, polished), and the least change of the minimum that moves an interval's end
    by more than its tolerance: the threshold q^2 s^2 moved by d, z = sqrt(.) - q by d / (2 q s^2),
    an end by `profile.XTOL` of a half-width for d = 2 q^2 XTOL s^2 (~0.08 s^2). J (N, p) at the
    optimum, r (N,) its residuals (m); s^2 = |r|^2 / (N - p) and q = t_{0.975, N-p} as in
    `uncertainty`."""
    dof = max(J.shape[0] - J.shape[1], 1)
    g = J.T @ r
    left = float(g @ normal_inverse(J) @ g) if np.all(np.isfinite(J)) else 0.0
    return max(left, 2 * float(stats.t.ppf(0.975, dof)) ** 2 * profile.XTOL * float(r @ r) / dof)


def rises(
    prob: mdl.Problem,
    x: np.ndarray,
    J: np.ndarray,
    r: np.ndarray,
    unc: Uncertainty,
    lo: np.ndarray | float = -np.inf,
    hi: np.ndarray | float = np.inf,
) -> np.ndarray:
    """The rise of the cost (n, 2) at x +- q se_j along parameter j's covariance direction (every
    unknown with it; J (N, p) in scaled unknowns at the optimum x, r (N,) m its residuals), in
    units of the linear prediction q^2 s^2; NaN for a parameter without an interval, inf for an
    end outside the bounds lo, hi (scaled) or whose simulation fails."""
    n = prob.n_params
    out = np.full((n, 2), np.nan)
    keep, V = steps(J, unc, n)
    if not keep.size:
        return out
    V = V[keep]
    X = np.concatenate([x + V, x - V])  # (2k, p): every + end, then every - end
    rise = np.full(len(X), np.inf)
    rows = np.flatnonzero(np.all((X >= lo) & (X <= hi), axis=1))
    if rows.size:
        try:
            R = prob.residuals(X[rows])
        except (SimulationError, ValueError):  # one robot at a time: find the one that fails
            R = np.array([_or_nan(prob, X[i]) for i in rows])
        rise[rows] = (np.sum(R**2, axis=1) - r @ r) / (_q(unc) * unc.s) ** 2
    out[keep] = np.nan_to_num(rise.reshape(2, keep.size).T, nan=np.inf)
    return out


def linear(
    prob: mdl.Problem,
    x: np.ndarray,
    J: np.ndarray,
    r: np.ndarray,
    unc: Uncertainty,
    lo: np.ndarray | float = -np.inf,
    hi: np.ndarray | float = np.inf,
    refit: Callable | None = None,
    tol: float | None = None,
) -> Uncertainty:
    """`unc` with the parameters whose interval does not hold (module docstring, LINEAR: their
    `rises` off the prediction by more than that factor at either end) given the profile's
    interval instead (`profile.interval`, with `refit` the least squares of the other unknowns;
    their se and correlations NaN), or, without `refit` or if the profile fails, none, and named.
    Not made below a residual of FLOOR m. Raises `profile.Lower` at an end of an interval, or a
    refit of a profile, whose cost is below |r|^2 by more than `tol` m^2 (None: `margin`; inf:
    never)."""
    if not np.isfinite(unc.se).any() or unc.s < FLOOR:
        return unc
    rise, tol = rises(prob, x, J, r, unc, lo, hi), margin(J, r) if tol is None else tol
    drop = np.where(np.isnan(rise), np.inf, rise) * (_q(unc) * unc.s) ** 2  # m^2 above |r|^2
    if drop.min() < -tol:
        j, end = np.unravel_index(np.argmin(drop), drop.shape)
        point = x + (1 - 2 * end) * steps(J, unc, prob.n_params)[1][j]
        below = -float(drop.min()) / unc.s**2
        raise profile.Lower(point, float(r @ r + drop.min()), below, f"the linearity check of {prob.fit[j]}")
    lost = np.flatnonzero(np.isfinite(unc.se) & ~np.all((rise >= 1 / LINEAR) & (rise <= LINEAR), axis=1))
    if not lost.size:
        return unc
    se, lower, upper, corr = unc.se.copy(), unc.lower.copy(), unc.upper.copy(), unc.corr.copy()
    se[lost] = lower[lost] = upper[lost] = np.nan
    corr[lost, :] = corr[:, lost] = np.nan
    method, said, refits, V = list(unc.method), [], unc.refits, steps(J, unc, prob.n_params)[1]
    lo, hi = np.broadcast_to(lo, x.shape), np.broadcast_to(hi, x.shape)
    for j, (a, b) in zip(lost, rise[lost], strict=True):
        method[j] = "none"
        why = f"the cost at its ends rises {a:.3g} and {b:.3g} times the linear prediction"
        if refit is not None:
            try:
                ends, shut, n = profile.interval(prob, refit, x, V[j], j, float(r @ r), unc.s, _q(unc), lo, hi, tol=tol)
            except (profile.OutOfBudget, SimulationError, ValueError) as e:
                why += f"; its profile failed: {e}"
            else:
                refits += n
                lower[j], upper[j] = np.array(ends) * prob.units[j]
                side = [w for w, o in zip(("below", "above"), shut, strict=True) if o]
                method[j] = "profile" + "".join(f", open {w}" for w in side)
                continue
        said.append(f"{prob.fit[j]} (too weakly determined for a linearised interval: {why})")
    return replace(
        unc,
        se=se,
        lower=lower,
        upper=upper,
        corr=corr,
        undetermined=unc.undetermined + tuple(said),
        method=tuple(method),
        refits=refits,
    )


def _or_nan(prob: mdl.Problem, x: np.ndarray) -> np.ndarray:
    """The residuals of one vector x, or NaN (its cost then fails the check) if it fails."""
    try:
        return prob.residuals(x[None])[0]
    except (SimulationError, ValueError):
        return np.full(int(prob.valid.sum()), np.nan)
