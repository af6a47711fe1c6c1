"""The check that a linearised interval holds (`calibration.linearity.linear`, docs/design.md §9): on a
model linear in its unknowns the cost at an interval's ends rises by exactly q^2 s^2 and every
interval is kept; on one whose unknown enters cubically near zero, weakly seen under the noise,
it does not, and that unknown is named and left without an interval."""

from types import SimpleNamespace

import numpy as np
from scipy.optimize import least_squares

from tensegrity.calibration.linearity import linear
from tensegrity.calibration.uncertainty import uncertainty

NAMES = ("a", "b")


def _fit(f, x_true, noise):
    """The least-squares fit of f(x) (N,) to f(x_true) + noise, its uncertainty and `linear`."""
    y = f(x_true) + np.random.default_rng(3).normal(0.0, noise, f(x_true).shape)
    res = least_squares(lambda x: f(x) - y, np.ones(2), xtol=1e-15, ftol=1e-15, gtol=1e-15)
    prob = SimpleNamespace(n_params=2, names=NAMES, fit=NAMES, residuals=lambda X: np.array([f(x) - y for x in X]))
    unc = uncertainty(res.jac, res.fun, 2, res.x, NAMES)
    return unc, linear(prob, res.x, res.jac, res.fun, unc)


def test_a_linear_model_keeps_every_interval():
    A = np.random.default_rng(1).normal(size=(200, 2))
    before, after = _fit(lambda x: A @ x, np.array([1.0, 2.0]), 0.1)
    assert after is before  # unchanged: both rises within 1 +- 1e-9 of the prediction


def test_a_weakly_seen_cubic_unknown_is_named_and_loses_its_interval():
    """b enters as b^3 with b = 0.5, its standard error ~40 % of it: the cost along its
    interval is far from a parabola; a, seen linearly and uncorrelated, keeps its interval."""
    t = np.linspace(0, 1, 200)
    before, after = _fit(lambda x: np.concatenate([x[0] * t, 0.01 * x[1] ** 3 * t]), np.array([1.0, 0.5]), 0.01)
    assert np.isfinite(before.se).all() and 0.2 < before.se[1] / 0.5 < 1.0
    assert np.isfinite(after.se[0]) and after.lower[0] == before.lower[0]
    assert np.isnan([after.se[1], after.lower[1], after.upper[1]]).all()
    assert len(after.undetermined) == 1 and after.undetermined[0].startswith("b (too weakly determined")
