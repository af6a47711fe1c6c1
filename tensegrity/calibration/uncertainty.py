"""What a least-squares fit knows (docs/design.md §9): standard errors, 95 % intervals and
correlations from the Jacobian J at the optimum, and the combinations of parameters the data
cannot determine.

The linearised covariance is s^2 (J^T J)^-1 with s^2 = |r|^2 / (N - p), the residual variance
(N measured coordinates, p unknowns, the nuisance ones included), and the interval the estimate
+- t_{0.975, N-p} standard errors. Both hold to first order in the noise: they assume the
residuals independent with equal variance and the model right (exact for a linear model with
Gaussian noise; the coverage test, tests/calibration, checks them on our own trajectories).

Identifiability: the nuisance unknowns (initial state, frame) are projected out of the
parameters' columns, the columns taken in log-parameters (d r / d ln theta) and scaled to unit
length, and a right singular vector whose singular value is below IDENTIFIABLE times the largest
is a direction the data cannot see (e.g. in the free mode a common scale of the mass and every
force leaves the motion unchanged). It is named; the parameters in it get no interval (NaN).
The finite-difference Jacobian is good to about 1e-5 of a column, so a true null direction shows
a ratio near that; a ratio below 1e-4 is taken as none.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import stats

__all__ = ["IDENTIFIABLE", "Uncertainty", "uncertainty", "describe"]

IDENTIFIABLE = 1e-4  # smallest singular value ratio of a direction the data determine
_PART = 0.1  # a parameter takes part in a null direction if its component exceeds this


@dataclass(frozen=True)
class Uncertainty:
    """se, lower, upper (n,) in the parameters' units (NaN: not determined); corr (n, n);
    s the residual standard deviation (m); dof N - p; undetermined: each direction the data
    cannot see, in words; singular (n,) the singular value ratios of the parameters' columns."""

    se: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    corr: np.ndarray
    s: float
    dof: int
    undetermined: tuple[str, ...]
    singular: np.ndarray


def describe(names: tuple[str, ...], v: np.ndarray) -> str:
    """A null direction v (n,) of log-parameters in words."""
    part = [(n, c) for n, c in zip(names, v / np.max(np.abs(v)), strict=True) if abs(c) > _PART]
    if len(part) > 1 and all(abs(c - part[0][1]) < 0.05 for _, c in part):
        return f"a common scale of {', '.join(n for n, _ in part)} (scaling them together leaves the motion unchanged)"
    if len(part) == 1:
        return f"{part[0][0]} (it does not change the motion)"
    expo = " * ".join(f"{n}^{c:+.2f}" for n, c in part)
    return f"the product {expo} can change without changing the motion; only the other combinations are determined"


def uncertainty(J: np.ndarray, r: np.ndarray, n: int, theta: np.ndarray, names: tuple[str, ...]) -> Uncertainty:
    """Uncertainty of the first n unknowns (values theta (n,), their columns of J in their own
    units) from the Jacobian J (N, p) in the unknowns' own units and the residuals r (N,) m."""
    N, p = J.shape
    dof = N - p
    if dof <= 0:
        raise ValueError(f"{N} measured coordinates cannot determine {p} unknowns")
    s2 = float(r @ r) / dof
    # parameters' columns with the nuisance ones projected out, in log-parameters, unit length
    A, Q = J[:, :n] * theta, np.linalg.qr(J[:, n:])[0] if p > n else None
    if Q is not None:
        A = A - Q @ (Q.T @ A)
    norm = np.linalg.norm(A, axis=0)
    norm = np.where(norm > 0, norm, 1.0)
    _, sv, Vt = np.linalg.svd(A / norm, full_matrices=False)
    ratio = sv / sv[0] if sv[0] > 0 else np.zeros_like(sv)
    null = [Vt[i] / norm for i in range(len(sv)) if ratio[i] < IDENTIFIABLE]
    null = [v / np.linalg.norm(v) for v in null]
    lost = np.zeros(n, bool)
    for v in null:
        lost |= np.abs(v) / np.max(np.abs(v)) > _PART
    # the covariance of what is determined: the reduced normal matrix, lost parameters left out
    keep = np.flatnonzero(~lost)
    se = np.full(n, np.nan)
    corr = np.full((n, n), np.nan)
    if keep.size:
        Ak = A[:, keep] / theta[keep]  # back to the parameters' own units
        cov = s2 * np.linalg.pinv(Ak.T @ Ak)
        se[keep] = np.sqrt(np.diag(cov))
        corr[np.ix_(keep, keep)] = cov / np.outer(se[keep], se[keep])
    q = float(stats.t.ppf(0.975, dof))
    return Uncertainty(
        se,
        theta - q * se,
        theta + q * se,
        corr,
        float(np.sqrt(s2)),
        dof,
        tuple(describe(names, v) for v in null),
        ratio,
    )
