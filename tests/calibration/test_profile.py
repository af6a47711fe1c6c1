"""Profile-likelihood intervals (`calibration.profile`, docs/design.md §9, (P1)), through the fit's
own refit (`fit.solve` with the parameter held): on a model linear in its unknowns the profile
interval is the linearised one; it is the same for any monotone reparametrisation (b, or b^3), so
on a model linear in b^3 it is the cube root of the linearised interval of c = b^3, where the
linearised interval of b fails `linearity`'s check; a profile that stays below the threshold up to
a bound gives an interval open at that bound."""

from dataclasses import replace
from functools import partial
from types import SimpleNamespace

import numpy as np
from scipy.optimize import least_squares

from tensegrity.calibration import calibrate, profile
from tensegrity.calibration.fit import solve
from tensegrity.calibration.linearity import linear, steps
from tensegrity.calibration.uncertainty import uncertainty
from tensegrity.io.formats.calibration import calibrated_yaml, calibration_dataset

NAMES = ("a", "b")
t = np.linspace(0, 1, 200)
REFIT = partial(solve, max_nfev=profile.NFEV, ftol=profile.FTOL)


def _fit(f, x_true, noise):
    """The least-squares fit of f(x) (N,) to f(x_true) + noise (seed 3): the problem as the fit
    sees it (two parameters, scaled units 1), scipy's result and the linearised uncertainty."""
    y = f(x_true) + np.random.default_rng(3).normal(0.0, noise, f(x_true).shape)
    res = least_squares(lambda x: f(x) - y, np.ones(2), xtol=1e-15, ftol=1e-15, gtol=1e-15)
    residuals = lambda X: np.array([f(x) - y for x in np.atleast_2d(X)])  # noqa: E731
    prob = SimpleNamespace(n_params=2, names=NAMES, fit=NAMES, units=np.ones(2), valid=np.ones(y.size, bool))
    prob.__dict__.update(mode="free", motors=None, residuals=residuals)
    return prob, res, uncertainty(res.jac, res.fun, 2, res.x, NAMES)


def _profile(prob, res, unc, j, lo=-np.inf, hi=np.inf):
    q = (unc.upper[j] - res.x[j]) / unc.se[j]  # the quantile uncertainty used
    return profile.interval(prob, REFIT, res.x, steps(res.jac, unc, 2)[1][j], j, res.fun @ res.fun, unc.s, q, lo, hi)


def test_on_a_linear_model_the_profile_interval_is_the_linearised_one():
    """Correlated unknowns (the refit moves the other one): z(t) is exactly linear, brentq's
    interpolation step lands on the root, and the refits of a linear model are exact to the
    finite differences' round-off: the ends agree to 1e-6 of a standard error."""
    A = np.random.default_rng(1).normal(size=(200, 2)) @ np.array([[1.0, 0.6], [0.0, 0.8]])
    prob, res, unc = _fit(lambda x: A @ x, np.array([1.0, 2.0]), 0.1)
    assert abs(unc.corr[0, 1]) > 0.3
    for j in range(2):
        ends, shut, n = _profile(prob, res, unc, j)
        assert np.allclose(ends, (unc.lower[j], unc.upper[j]), rtol=0, atol=1e-6 * unc.se[j]), (j, ends)
        assert shut == (False, False) and n <= 10


def test_profile_of_a_cubed_unknown_is_the_cube_root_of_the_linear_interval_and_holds_the_truth():
    """b enters as b^3, b = 0.5 with a standard error ~40 % of it: its linearised interval fails
    the check (`test_linearity`); `linear` with a refit gives the profile's instead, which is the
    cube root of the linearised interval of c = b^3 in the same data (to brentq's tolerance, XTOL
    of b's linearised half-width) and holds the truth; a keeps its linearised interval."""
    prob, res, unc = _fit(lambda x: np.concatenate([x[0] * t, 0.01 * x[1] ** 3 * t]), np.array([1.0, 0.5]), 0.01)
    after = linear(prob, res.x, res.jac, res.fun, unc, refit=REFIT)
    assert after.method == ("linearised", "profile") and not after.undetermined and 0 < after.refits <= 30
    assert after.lower[0] == unc.lower[0] and np.isnan(after.se[1])
    _, _, c = _fit(lambda x: np.concatenate([x[0] * t, 0.01 * x[1] * t]), np.array([1.0, 0.125]), 0.01)
    tol = profile.XTOL * (unc.upper[1] - unc.lower[1]) / 2
    assert np.allclose([after.lower[1], after.upper[1]], np.cbrt([c.lower[1], c.upper[1]]), rtol=0, atol=tol)
    assert after.lower[1] < 0.5 < after.upper[1]
    assert not np.isclose(after.upper[1], unc.upper[1], rtol=0.05)  # the linearised end was not it


def test_a_profile_below_the_threshold_up_to_a_bound_is_open_there():
    """b / (1 + b) seen under noise 0.02 with b = 3: towards b = 100 the signal changes by only
    ~1 noise RMS over the run (the cost rises ~1 s^2 < q^2 s^2), towards 0.01 by ~3: the interval
    is open above (its end the bound) and closed below."""
    prob, res, unc = _fit(
        lambda x: np.concatenate([x[0] * t, 0.01 * x[1] / (1 + x[1]) * t]), np.array([1.0, 3.0]), 0.02
    )
    (lower, upper), shut, _ = _profile(prob, res, unc, 1, np.array([0.01, 0.01]), np.array([100.0, 100.0]))
    assert shut == (False, True) and upper == 100.0 and 0.01 < lower < 3.0


def test_the_report_and_calibrated_yaml_say_what_gave_each_interval(free_run, truth):
    """A fit whose intervals are linearised says so in the report and adds no comment to
    calibrated.yaml; one with a profile interval (here put in by hand) names it in both."""
    c = calibrate(
        free_run.head(40), truth.replace(cable_stiffness=1100.0), ("cable_stiffness",), "free", 1e-4, False, check=0.0
    )
    ds = calibration_dataset(c)
    assert c.unc.method == ("linearised",) and ds.attrs["interval_methods"] == "cable_stiffness: linearised"
    assert "profile" not in calibrated_yaml(c, "run")
    c = replace(
        c, unc=replace(c.unc, lower=np.array([990.0]), upper=np.array([1.1e5]), method=("profile, open above",))
    )
    assert calibration_dataset(c)["cable_stiffness_upper_95"].attrs["interval_method"] == "profile, open above"
    line = "# 95 % interval of cable_stiffness by its profile likelihood, open above: [990, 110000]"
    assert line in calibrated_yaml(c, "run").splitlines()


def test_a_single_unknown_is_profiled_without_a_refit():
    """With nothing else to refit the profile is the cost itself: for y = b t, the linearised
    interval (to round-off)."""
    y = 2.0 * t + np.random.default_rng(3).normal(0.0, 0.1, t.size)
    res = least_squares(lambda x: x[0] * t - y, np.ones(1))
    prob = SimpleNamespace(n_params=1, names=("b",), units=np.ones(1), residuals=lambda X: X[:, :1] * t - y)
    unc = uncertainty(res.jac, res.fun, 1, res.x, ("b",))
    q = (unc.upper[0] - res.x[0]) / unc.se[0]
    ends, _, n = profile.interval(prob, None, res.x, np.array([q * unc.se[0]]), 0, res.fun @ res.fun, unc.s, q)
    assert np.allclose(ends, (unc.lower[0], unc.upper[0]), rtol=0, atol=1e-6 * unc.se[0]) and n <= 10
