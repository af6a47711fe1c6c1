"""Whether the model fits the measurement to its noise (docs/design.md §9): the residuals of
consecutive samples are uncorrelated if it does.

The intervals (`uncertainty`) assume a right model and independent noise. A model that is wrong
(another contact law than the measured robot's, say) leaves a residual that is smooth in time,
and its estimates are off by a bias the intervals know nothing of: against MuJoCo's grounded
runs the four cable parameters came out 27-47 % off with intervals 0.002-7 % wide (docs/
benchmarks.md). A sandwich estimator with the residuals' autocorrelation (Newey-West, Bartlett
lags of 10 samples to a third of the run) widened them only 2-6 times, the bias still 4.6-4200
standard errors (tuning seeds 0 and 3, residual 'shape'): such a bias is no noise, and no
interval from one run holds it.
So the lag-one autocorrelation of the residuals, rho = sum r_t . r_t+1 / sum |r_t|^2 over the
consecutive samples, is compared with its spread under independent noise, 1 / sqrt(n) (n the
products summed): above MISFIT spreads every interval is dropped and named with the reason,
the estimates kept (the model that best reproduces the run, not the robot's true values); a
grounded fit then gets the intervals of refits on time windows instead (`discrepancy`).
Below a residual of `linearity.FLOOR` m (a noise-free check) it is not made. The test sees a
misfit as large as the noise; a smaller one can still bias an estimate by several standard
errors unseen (a line fitted to 600 points with a sine of 0.3-1 times the noise: slope 3-13
standard errors off, the lag-one autocorrelation 0-4 spreads from 0).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from .linearity import FLOOR
from .uncertainty import Uncertainty

__all__ = ["MISFIT", "REASON", "autocorrelation", "misfit"]

REASON = "(no interval: the model does not reproduce the measurement to its noise"  # how misfit names one
MISFIT = 4.0  # spreads of the lag-one autocorrelation under independent noise (3e-5 beyond by chance)


def autocorrelation(R: np.ndarray) -> tuple[float, int]:
    """The lag-one autocorrelation of residuals R (T, M) (NaN: not measured) over consecutive
    samples, and the number of products n it sums."""
    a, b = R[:-1], R[1:]
    both = np.isfinite(a) & np.isfinite(b)
    den = float(np.nansum(R**2))
    return (float(np.sum(a[both] * b[both])) / den if den > 0 else 0.0), int(both.sum())


def misfit(R: np.ndarray, unc: Uncertainty, names: tuple[str, ...]) -> Uncertainty:
    """`unc` without intervals, each parameter named with the reason, if the residuals R (T, M)
    m of the fit are correlated from one sample to the next by more than MISFIT spreads."""
    if not np.isfinite(unc.se).any() or unc.s < FLOOR:
        return unc
    rho, n = autocorrelation(R)
    if rho * np.sqrt(n) <= MISFIT:
        return unc
    lost = np.flatnonzero(np.isfinite(unc.se))
    nan = np.full(len(names), np.nan)
    said = tuple(
        f"{names[j]} {REASON}; the residuals of consecutive samples are correlated, {rho:.3g}, "
        f"{rho * np.sqrt(n):.0f} times the "
        "spread of independent noise; the estimate is the model's best, its bias unknown)"
        for j in lost
    )
    corr = unc.corr.copy()
    corr[lost, :] = corr[:, lost] = np.nan
    none = ("none",) * len(names)
    return replace(
        unc, se=nan, lower=nan.copy(), upper=nan.copy(), corr=corr, undetermined=unc.undetermined + said, method=none
    )
