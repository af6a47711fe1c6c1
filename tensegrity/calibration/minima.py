"""Local minima of the fit (docs/design.md §9, issue 32): restarts from a lower point that the
intervals' own checks find, and extra starts.

A fit that stops in a valley of the cost other than the deepest keeps intervals that follow that
valley (a run in volts, seed 972259 of the coverage test: the fit 13.9 s^2 above the truth's
valley, its profile interval 1.3 % wide, 9.8 % off). Two remedies:

- **Restart from a lower point** (always; it costs nothing where the fit is the minimum). The
  linearity check evaluates the cost at each interval's ends, and a profile refits every other
  unknown at held values of one (`linearity`, `profile`): if any of those points has a cost below
  the fit's by more than `linearity.margin` (the larger of what the fit's linear model still
  expects to gain and the least change of the minimum that moves an interval's end by its
  tolerance), the fit was not the minimum (a profile that falls again past its end is followed
  outward to look for such a point: `profile._beyond`). The full fit then restarts from that point
  (`fit.solve`, to the last stage's tolerance), and the uncertainty, the check and the profiles
  are redone from the new optimum; at most RESTARTS times (each restart lowers the cost by more
  than the margin), after which a lower point no longer restarts the fit. The report counts the
  restarts and names what found each.
- **Extra starts** (`calibrate(starts=k)`, `tensegrity calibrate --starts k`; default 0): k more
  fits, each on the same growing horizon, from parameters drawn by a seeded Latin hypercube
  (scipy.stats.qmc, seed SEED: the same starts every run) log-uniformly within a factor `spread`
  (default SPREAD) of the configured start on each side, inside the fit's bounds (1/100 to 100
  times the start); the initial state and frame start from the data, as the first fit. The fit
  of lowest cost is kept, with its prediction check; a start replaces the one kept so far only if
  lower by more than that one's margin (the same minimum reached twice: the first is kept).
  Off by default: on the volts seeds that still missed after the restarts, two extra starts
  reached no lower minimum, at 1.6-2.4 times the CPU (docs/benchmarks.md, "Local minima").
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import partial

import numpy as np
from scipy.stats import qmc

from ..physics.dynamics import SimulationError
from . import profile
from .linearity import linear, margin
from .misfit import misfit
from .uncertainty import Uncertainty, structural, uncertainty

__all__ = ["RESTARTS", "SEED", "SPREAD", "Settled", "draws", "lowest", "settle"]

RESTARTS = 5  # restarts from a lower point at most (each lowers the cost by more than the margin)
SEED = 32  # the Latin hypercube's seed (issue 32): the same extra starts on every run
SPREAD = 2.0  # extra starts within this factor of the configured start, each way, log-uniformly


@dataclass(frozen=True)
class Settled:
    """The fit's optimum x (p,) scaled, its Jacobian J (N, p) and scipy result `res`; what it
    knows `unc`; its simulated nodes (T, 12, 3) m and residuals r (N,) m; `restarts` what found
    each lower point the fit restarted from and how far below the fit's cost it was (in the fit's
    s^2); nfev, njev of the restarts' fits."""

    x: np.ndarray
    J: np.ndarray
    res: object
    unc: Uncertainty
    simulated: np.ndarray
    r: np.ndarray
    restarts: tuple[str, ...]
    nfev: int
    njev: int


def draws(prob: object, k: int, lo: np.ndarray, hi: np.ndarray, spread: float = SPREAD) -> np.ndarray:
    """k extra starts (k, p) scaled of problem `prob` (a `model.Problem`): its parameters drawn
    by a Latin hypercube (seed SEED) log-uniformly in [x0 / spread, x0 * spread], clipped to the
    bounds lo, hi (p,); its other unknowns (initial state, frame) at x0."""
    if k < 0 or not spread >= 1.0:
        raise ValueError(f"starts {k!r} must be >= 0 and spread {spread!r} >= 1")
    n, X = prob.n_params, np.tile(np.asarray(prob.x0, float), (k, 1))
    if k:
        u = qmc.LatinHypercube(d=n, rng=SEED).random(k)
        X[:, :n] *= spread ** (2 * u - 1)
    return np.clip(X, lo, hi)


def lowest(staged: Callable[[np.ndarray | None], tuple], X0: np.ndarray) -> tuple[tuple, np.ndarray]:
    """The fit of lowest cost among staged(None) (the configured start; its errors raised) and
    staged(x0) for each extra start x0 in X0 (k, p) (one the simulator cannot run left out): its
    (x, J, res, nfev, njev, ...) with nfev, njev summed over every start, and the costs |r|^2
    (m^2) of the fits made, the configured start's first. A start replaces the one kept so far
    only if its cost is lower by more than that one's `linearity.margin` (the same minimum
    reached twice differs in round-off and the fit's stopping rule: the first is kept)."""
    fits = [staged(None)]
    for x0 in X0:
        try:
            fits.append(staged(x0))
        except (SimulationError, ValueError):
            continue
    costs = np.array([float(f[2].fun @ f[2].fun) for f in fits])
    k = 0  # a later start replaces the kept one only below it by more than its margin
    for i in range(1, len(fits)):
        if costs[i] < costs[k] - margin(fits[k][1], fits[k][2].fun):
            k = i
    best = list(fits[k])
    best[3:5] = sum(f[3] for f in fits), sum(f[4] for f in fits)
    return tuple(best), costs


def settle(
    prob: object,
    x: np.ndarray,
    J: np.ndarray,
    res: object,
    solve: Callable[..., tuple[np.ndarray, np.ndarray, object]],
    lo: np.ndarray,
    hi: np.ndarray,
) -> Settled:
    """What the fit x (J its Jacobian, scipy result res) of problem `prob` knows (`uncertainty`,
    `misfit`, `linearity.linear` with the profile's refits by `solve`), restarting the full fit
    (`solve(prob, x0)`) from any point the checks find below its cost (module docstring), at most
    RESTARTS times; lo, hi the bounds (p,) scaled."""
    n, said, nfev, njev = prob.n_params, [], 0, 0
    refit = partial(solve, max_nfev=profile.NFEV, ftol=profile.FTOL)
    while True:
        simulated = prob.simulate(x[None])[0]
        R = prob.per_sample(simulated[None], x)[0]
        r, theta = R[prob.valid], prob.values(x)[:n]
        unc = uncertainty(J / prob.units, r, n, theta, prob.fit, structural(prob.constants, theta))
        unc = misfit(R, unc, prob.fit)
        try:
            tol = None if len(said) < RESTARTS else np.inf  # past RESTARTS: no more restarts
            unc = linear(prob, x, J, r, unc, lo, hi, refit=refit, tol=tol)
        except profile.Lower as low:
            said.append(f"{low.where} ({low.below:.3g} s^2 below)")
            x, J, res = solve(prob, low.x)
            nfev, njev = nfev + res.nfev, njev + res.njev
            continue
        return Settled(x, J, res, unc, simulated, r, tuple(said), nfev, njev)
