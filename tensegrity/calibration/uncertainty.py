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

Some combinations no trajectory can determine, because the simulator reads the parameters only
through fewer constants (`structural`): the twisted strings' 14 keys reach the kernel as 9
numbers (docs/design.md §10: the series stiffness K of spring and fibre, G = tau_s / V,
D = tau_s (1 - I0/I_s) / omega0 + b, TC = tau_s I0 / I_s, J = N^2 J_r, ...). Their null
directions are found from the Jacobian of those constants by central differences (exact to
~1e-8, ratio below STRUCTURAL), named with every parameter taking part (component above 1e-3),
and taken out before the data's own directions are sought (a weak column's finite-difference
error, ~1e-3 of it, would hide them among the data's).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy import linalg, stats

__all__ = ["IDENTIFIABLE", "STRUCTURAL", "Uncertainty", "uncertainty", "describe", "structural"]
__all__ += ["basis", "normal_inverse"]

IDENTIFIABLE = 1e-4  # smallest singular value ratio of a direction the data determine
STRUCTURAL = 1e-6  # smallest singular value ratio of a direction the simulator's constants see
_PART = 0.1  # a parameter takes part in a null direction if its component exceeds this
_PART_STRUCTURAL = 1e-3  # ... of a structural one (exact: every share counts)
_LOG_STEP = 1e-4  # central-difference step in log-parameters (error ~ step^2)


@dataclass(frozen=True)
class Uncertainty:
    """se, lower, upper (n,) in the parameters' units (NaN: not determined); corr (n, n);
    s the residual standard deviation (m); dof N - p; undetermined: each direction the data
    cannot see, in words; singular (n,) the singular value ratios of the parameters' columns;
    method (n,) what gave each interval: 'linearised', 'profile' (`profile`: ', open below',
    ', open above' where it reaches a bound), 'windows' (`discrepancy`) or 'none'; refits the
    profiles' and windows' refits; windows (k, n) the estimates of the time windows refitted
    (`discrepancy`; NaN rows: fits that failed; none refitted: (0, n))."""

    se: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    corr: np.ndarray
    s: float
    dof: int
    undetermined: tuple[str, ...]
    singular: np.ndarray
    method: tuple[str, ...] = ()
    refits: int = 0
    windows: np.ndarray | None = None


def _svd(M: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """U, sv, Vt of M (N, k) with its columns at unit length, the directions whose singular value
    is below IDENTIFIABLE of the largest left out, and the column norms (k,)."""
    norm = np.linalg.norm(M, axis=0)
    norm = np.where(norm > 0, norm, 1.0)
    U, sv, Vt = np.linalg.svd(M / norm, full_matrices=False)
    seen = sv > IDENTIFIABLE * sv[0] if sv.size and sv[0] > 0 else np.zeros(sv.size, bool)
    return U[:, seen], sv[seen], Vt[seen], norm


def basis(M: np.ndarray) -> np.ndarray:
    """An orthonormal basis (N, r) of the span of M's columns (N, k), the directions the data do
    not see left out (`_svd`: e.g. with the residual 'shape' on flat ground, the robot's
    horizontal position and heading, and the frame's tilt beside the struts' own)."""
    return _svd(M)[0]


def normal_inverse(J: np.ndarray) -> np.ndarray:
    """The pseudo-inverse (k, k) of J^T J, J (N, k), without the directions `basis` leaves out."""
    _, sv, Vt, norm = _svd(J)
    return (Vt.T / sv**2 @ Vt) / np.outer(norm, norm)


def structural(constants: Callable[[np.ndarray], np.ndarray], theta: np.ndarray) -> np.ndarray:
    """The directions (k, n) of log-parameters (unit length) that leave every constant the
    simulator reads unchanged: `constants(theta)` (m,) of the parameters theta (n,), its
    Jacobian in log-parameters by central differences, relative to each constant's size."""
    theta = np.asarray(theta, float)
    base = np.abs(np.asarray(constants(theta), float))
    scale = np.where(base > 0, base, 1.0)
    M = np.empty((base.size, theta.size))
    for j in range(theta.size):
        up, down = theta.copy(), theta.copy()
        up[j] *= np.exp(_LOG_STEP)
        down[j] *= np.exp(-_LOG_STEP)
        M[:, j] = (np.asarray(constants(up)) - np.asarray(constants(down))) / (2 * _LOG_STEP) / scale
    norm = np.linalg.norm(M, axis=0)
    if np.any(norm == 0):  # a parameter the simulator does not read at all
        return np.eye(theta.size)[norm == 0]
    _, sv, Vt = np.linalg.svd(M / norm, full_matrices=True)
    sv = np.concatenate([sv, np.zeros(theta.size - sv.size)])
    null = [Vt[i] / norm for i in range(theta.size) if sv[i] < STRUCTURAL * sv[0]]
    return np.array([v / np.linalg.norm(v) for v in null]).reshape(-1, theta.size)


def describe(names: tuple[str, ...], v: np.ndarray, share: float = _PART) -> str:
    """A null direction v (n,) of log-parameters in words (a parameter whose component is
    below `share` of the largest left out)."""
    part = [(n, c) for n, c in zip(names, v / np.max(np.abs(v)), strict=True) if abs(c) > share]
    if len(part) > 1 and all(abs(c - part[0][1]) < 0.05 for _, c in part):
        return f"a common scale of {', '.join(n for n, _ in part)} (scaling them together leaves the motion unchanged)"
    if len(part) == 1:
        return f"{part[0][0]} (it does not change the motion)"
    expo = " * ".join(f"{n}^{c:+.2g}" for n, c in part)
    return f"the product {expo} can change without changing the motion; only the other combinations are determined"


def uncertainty(
    J: np.ndarray,
    r: np.ndarray,
    n: int,
    theta: np.ndarray,
    names: tuple[str, ...],
    fixed: np.ndarray | None = None,
) -> Uncertainty:
    """Uncertainty of the first n unknowns (values theta (n,), their columns of J in their own
    units) from the Jacobian J (N, p) in the unknowns' own units and the residuals r (N,) m;
    `fixed` (k, n): the structural null directions (`structural`), named first."""
    N, p = J.shape
    dof = N - p
    if dof <= 0:
        raise ValueError(f"{N} measured coordinates cannot determine {p} unknowns")
    s2 = float(r @ r) / dof
    # parameters' columns with the nuisance ones projected out, in log-parameters, unit length
    A, Q = J[:, :n] * theta, basis(J[:, n:]) if p > n else None
    if Q is not None:
        A = A - Q @ (Q.T @ A)
    # the data's own directions, within those the simulator's constants see (V1: the rest)
    fixed = np.zeros((0, n)) if fixed is None else np.asarray(fixed, float).reshape(-1, n)
    V1 = linalg.null_space(fixed) if len(fixed) else np.eye(n)
    B = A @ V1
    norm = np.linalg.norm(B, axis=0)
    norm = np.where(norm > 0, norm, 1.0)
    _, sv, Vt = np.linalg.svd(B / norm, full_matrices=False) if B.shape[1] else (None, np.zeros(0), None)
    ratio = sv / sv[0] if sv.size and sv[0] > 0 else np.zeros_like(sv)
    null = [(v, _PART_STRUCTURAL) for v in fixed]
    null += [(V1 @ (Vt[i] / norm), _PART) for i in range(len(sv)) if ratio[i] < IDENTIFIABLE]
    null = [(v / np.linalg.norm(v), share) for v, share in null]
    lost = np.zeros(n, bool)
    for v, share in null:
        lost |= np.abs(v) / np.max(np.abs(v)) > share
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
        tuple(describe(names, v, share) for v, share in null),
        np.concatenate([ratio, np.zeros(len(fixed))]),
        tuple("linearised" if np.isfinite(e) else "none" for e in se),
    )
