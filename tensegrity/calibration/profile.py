"""Profile-likelihood intervals where the linearised one does not hold (docs/design.md §9).

A parameter j whose cost at the ends of its linearised interval is off the prediction
(`linearity`) gets instead the interval of its profile: the cost with x_j held at v and every
other unknown refitted,

    S_j(v) = min_{x : x_j = v} |r(x)|^2,    95 % interval: S_j(v) - S(x^) <= q^2 s^2      (P1)

with q = t_{0.975, N-p} and s^2 = |r(x^)|^2 / (N - p) as in `uncertainty`. For a model linear in
the unknowns S_j(v) - S(x^) = (v - x^_j)^2 s^2 / se_j^2, and (P1) is the linearised interval; (P1)
is the same for any monotone reparametrisation of x_j (b or b^3), which the linearised one is not.
Each end is the root of the signed root z(t) = sqrt((S_j(x^_j +- t) - S(x^)) / s^2) - q (linear
in t for a linear model, so brentq converges in a step or two), to XTOL of the linearised
half-width, in a bracket that starts at that half-width and grows by GROW; a profile still below
q^2 s^2 at the parameter's bound gives an interval open at that bound (its end: the bound). Each
refit (`fit.solve` with x_j held, to a relative cost decrease FTOL: ~2e-4 s^2 for N ~ 2e4, against
q^2 s^2 = 3.84 s^2) starts from the nearest point refitted so far, moved along the linearised
conditional optimum (the covariance's column of j). At most BUDGET refits per parameter (both
ends); past it, or if a refit fails near the optimum, the parameter gets no interval (named).

A refit that ends below the fit's cost by more than `tol` (S_j(v) < S(x^) - tol: the fit was not
the minimum) stops the profile with `Lower`, the point it found; the fit restarts from there
(`minima.settle`). Past an end, a profile that falls again (the bracket's far end below a refit
between it and the end: a barrier, another valley beyond) is followed outward by GROW while it
falls (`_beyond`): into a point below the fit's cost (Lower), or below the threshold (a second
stretch of (P1): the interval's end is then that stretch's far end), or until it rises again.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from ..physics.dynamics import SimulationError

__all__ = ["BUDGET", "GROW", "XTOL", "FTOL", "NFEV", "Held", "OutOfBudget", "Lower", "interval"]

BUDGET = 30  # refits per parameter, both ends
GROW = 2.0  # the bracket's growth per step, in units of its last width
XTOL = 0.01  # an end's tolerance, in linearised half-widths
FTOL = 1e-8  # a refit stops when a step lowers the cost by less than this, relatively
NFEV = 30  # evaluations per refit
_FAILED = 1e6  # z of a held value whose refit fails: outside the interval


class OutOfBudget(RuntimeError):
    """The profile took more than BUDGET refits."""


class Lower(Exception):
    """A point x (p,) scaled whose cost |r|^2 (m^2) is below the fit's by more than the
    tolerance, by `below` times the fit's s^2: the fit stopped short of the minimum (found by a
    refit of the profile or by the linearity check, `where`)."""

    def __init__(self, x: np.ndarray, cost: float, below: float, where: str):
        super().__init__(f"{where} found a point {below:.3g} s^2 below the fit's cost")
        self.x, self.cost, self.below, self.where = np.asarray(x, float), float(cost), float(below), where


@dataclass(frozen=True)
class Held:
    """`prob` (a `model.Problem`) with its unknown j (a parameter) held at v (scaled), as the
    problem of the other unknowns (the attributes `fit.solve` reads)."""

    prob: object
    j: int
    v: float

    @property
    def names(self) -> tuple[str, ...]:
        return self.prob.names[: self.j] + self.prob.names[self.j + 1 :]

    @property
    def n_params(self) -> int:
        return self.prob.n_params - 1

    def __getattr__(self, name: str):  # mode, motors, valid: the problem's
        return getattr(self.prob, name)

    def residuals(self, Y: np.ndarray) -> np.ndarray:
        """Residuals (B, N) of the other unknowns Y (B, p - 1), x_j = v."""
        return self.prob.residuals(np.insert(np.atleast_2d(Y), self.j, self.v, axis=1))


def interval(
    prob: object,
    refit: Callable[[Held, np.ndarray], tuple[np.ndarray, np.ndarray, object]],
    x: np.ndarray,
    step: np.ndarray,
    j: int,
    cost: float,
    s: float,
    q: float,
    lo: np.ndarray | float = -np.inf,
    hi: np.ndarray | float = np.inf,
    budget: int | None = None,
    tol: float = np.inf,
) -> tuple[tuple[float, float], tuple[bool, bool], int]:
    """The 95 % profile interval (P1) of unknown j: its lower and upper end (scaled, a bound if
    open), whether each is open, and the refits made. x (p,) the optimum (scaled), cost its
    |r|^2 (m^2), step (p,) the
    linearised interval's step of every unknown with x_j (`linearity.steps`: step[j] the
    linearised half-width), s the residual standard deviation (m), q the quantile, lo, hi the
    bounds (scaled); `refit(held, y0)` -> (y, J, scipy result) the least-squares optimum of the
    other unknowns from y0 (`fit.solve`). Raises OutOfBudget past `budget` (None: BUDGET) refits,
    and Lower at a refit whose cost is below `cost` by more than `tol` (m^2)."""
    budget = BUDGET if budget is None else budget
    lo, hi = np.broadcast_to(lo, x.shape), np.broadcast_to(hi, x.shape)
    width, slope = float(step[j]), step / step[j]
    done: dict[float, tuple[float, np.ndarray]] = {0.0: (-q, x)}  # signed offset -> z, refitted x

    def z(u: float) -> float:
        if u in done:
            return done[u][0]
        if len(done) - 1 >= budget:
            raise OutOfBudget(f"the profile of {prob.names[j]} took more than {budget} refits")
        near = min(done, key=lambda w: abs(w - u))
        y0 = np.clip(done[near][1] + (u - near) * slope, lo, hi)
        held = Held(prob, j, float(x[j] + u))
        try:
            if x.size > 1:
                y, _, res = refit(held, np.delete(y0, j))
                fun = res.fun
            else:  # nothing else to refit
                y, fun = np.zeros(0), held.residuals(np.zeros((1, 0)))[0]
            rise = float(fun @ fun) - cost
            if rise < -tol:
                raise Lower(np.insert(y, j, x[j] + u), cost + rise, -rise / s**2, f"the profile of {prob.names[j]}")
            done[u] = (float(np.sign(rise) * np.sqrt(abs(rise)) / s - q), np.insert(y, j, x[j] + u))
        except (SimulationError, ValueError):
            done[u] = (_FAILED, y0)
        return done[u][0]

    ends, open_ = [], []
    for side in (-1.0, 1.0):
        limit = float(hi[j] - x[j] if side > 0 else x[j] - lo[j])
        a, b = 0.0, min(width, limit)
        while True:
            while z(side * b) < 0 and b < limit:
                a, b = b, min(GROW * b, limit)
            if z(side * b) < 0:  # still below the threshold at the bound
                end, shut = limit, True
                break
            end, shut = brentq(lambda t, side=side: z(side * t), a, b, xtol=XTOL * width), False
            c = _beyond(z, done, side, end, b, limit)
            if c is None:
                break
            a, b = c, min(GROW * c, limit)  # a second stretch below the threshold: its far end
        ends.append(x[j] + side * end)
        open_.append(shut)
    return (float(ends[0]), float(ends[1])), (open_[0], open_[1]), len(done) - 1


def _beyond(z: Callable[[float], float], done: dict, side: float, end: float, b: float, limit: float) -> float | None:
    """Past an end found at `end` (bracket's far end b): if the profile falls again towards b
    (z(b) below a refit between end and b), follow it outward by GROW while it falls: the
    offset (> 0) of a point below the threshold (a second stretch of (P1), whose far end is then
    the interval's), else None (it rises again, the bound, or the budget; a point below the
    fit's cost raises Lower on the way)."""
    seen = [v[0] for u, v in done.items() if end < side * u <= b]
    c, zc = b, z(side * b)
    if not seen or zc >= max(seen):
        return None
    try:
        while zc >= 0 and c < limit:
            c2 = min(GROW * c, limit)
            z2 = z(side * c2)
            if z2 >= zc:
                return None
            c, zc = c2, z2
    except OutOfBudget:
        return None
    return c if zc < 0 else None
