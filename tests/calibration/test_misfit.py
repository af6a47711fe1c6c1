"""A wrong model gives no interval (`calibration.misfit`, docs/design.md §9): the residuals of a
right model under independent noise are uncorrelated from one sample to the next and keep every
interval; a model that misses a slow term leaves a smooth residual, and every interval is dropped
and named, the estimates kept."""

import numpy as np
from scipy.optimize import least_squares

from tensegrity.calibration.misfit import MISFIT, autocorrelation, misfit
from tensegrity.calibration.uncertainty import uncertainty

NAMES = ("a", "b")
T, M = 200, 3  # samples, entries per sample
t = np.repeat(np.linspace(0, 1, T), M)


def _fit(y):
    """The straight line a + b t fitted to y (T * M,): its uncertainty, residuals (T, M), estimate."""
    res = least_squares(lambda x: x[0] + x[1] * t - y, np.ones(2))
    return uncertainty(res.jac, res.fun, 2, res.x, NAMES), res.fun.reshape(T, M), res.x


def test_independent_noise_on_a_right_model_keeps_every_interval():
    noise = np.random.default_rng(5).normal(0.0, 0.01, t.shape)
    unc, R, _ = _fit(1.0 + 2.0 * t + noise)
    rho, n = autocorrelation(R)
    assert abs(rho) * np.sqrt(n) < 3 and n == (T - 1) * M
    assert misfit(R, unc, NAMES) is unc and unc.lower[1] < 2.0 < unc.upper[1]


def test_a_slow_term_the_model_lacks_drops_every_interval_and_names_it():
    """A sine of 20 mm beside 10 mm of noise: the line's slope comes out ~25 standard errors
    off inside a 'right-model' interval; the misfit is seen (lag-one autocorrelation above
    MISFIT spreads) and no interval is given."""
    noise = np.random.default_rng(5).normal(0.0, 0.01, t.shape)
    unc, R, x = _fit(1.0 + 2.0 * t + 0.02 * np.sin(2 * np.pi * t) + noise)
    assert abs(x[1] - 2.0) > 3 * unc.se[1]  # the bias the interval does not know
    rho, n = autocorrelation(R)
    assert rho * np.sqrt(n) > MISFIT
    out = misfit(R, unc, NAMES)
    assert np.isnan(out.se).all() and np.isnan(out.lower).all() and np.isnan(out.upper).all()
    assert [u.split(" ")[0] for u in out.undetermined] == list(NAMES)
    assert "does not reproduce the measurement" in out.undetermined[0]
