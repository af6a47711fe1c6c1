"""Local minima of the fit (`calibration.minima`, docs/design.md §9): a fit stopped in a valley
of the cost above another restarts from the lower point its profile finds and ends in the lower
valley (main's fit kept the upper one); a fit in the lower valley makes no restart; the extra
starts are drawn the same on every run, within their box and the bounds, and the fit of lowest
cost is kept."""

from types import SimpleNamespace

import numpy as np
import pytest

from tensegrity.calibration import calibrate, minima, profile
from tensegrity.calibration.fit import _bounds, solve
from tensegrity.calibration.linearity import margin
from tensegrity.io.formats.calibration import calibration_dataset
from tensegrity.physics.dynamics import SimulationError

t = np.linspace(0, 1, 400)
NOISE = 0.1
y = np.random.default_rng(3).normal(0.0, NOISE, (2, t.size))


def _runs(X):
    """Residuals (B, T, 2) of unknowns X (B, 2): a enters as (a - 1)^2, so two valleys (a near
    0.9 and 1.1) fit the first column equally; the second column (0.05 a t) tells them apart by
    ~3 s^2 under the noise (seed 3: the valley near 0.87 the lower), less than the threshold
    q^2 s^2 = 3.84 s^2 above the upper one, so its profile walks into the lower one; b, seen by
    the second column only, is refitted at each held a."""
    X = np.atleast_2d(X)
    a, b = X[:, :1], X[:, 1:2]
    return np.stack([((a - 1) ** 2 - 0.01) * t - y[0], 0.05 * (a - 1.1) * t + 0.3 * (b - 1) * (1 - t) - y[1]], axis=-1)


def _problem():
    """The attributes of a `model.Problem` that the fit and `minima.settle` read."""
    prob = SimpleNamespace(n_params=2, names=("a", "b"), fit=("a", "b"), units=np.ones(2), x0=np.ones(2))
    prob.__dict__.update(valid=np.ones((t.size, 2), bool), mode="free", motors=None, simulate=_runs)
    prob.__dict__.update(per_sample=lambda S, X: S, values=lambda x: np.asarray(x, float))
    prob.residuals = lambda X: _runs(X).reshape(len(np.atleast_2d(X)), -1)
    prob.constants = lambda theta: np.asarray(theta, float)
    return prob


def test_a_fit_in_the_upper_valley_restarts_from_the_lower_point_its_profile_finds():
    prob = _problem()
    lo, hi = _bounds(prob)
    x, J, res = solve(prob, np.array([1.15, 1.0]))  # main's fit: it stops in the upper valley
    assert 1.05 < x[0] < 1.2
    st = minima.settle(prob, x, J, res, solve, lo, hi)
    assert len(st.restarts) == 1 and st.restarts[0].startswith("the profile of a (")  # its check failed
    assert 0.8 < st.x[0] < 0.95  # the lower valley's minimum
    low = float(st.res.fun @ st.res.fun)
    assert low < float(res.fun @ res.fun) - 2.0 * NOISE**2  # ~3 s^2 lower, well beyond the margin
    assert low == pytest.approx(float(st.r @ st.r), rel=1e-12)  # what it knows is of the new fit
    assert st.unc.lower[0] < st.x[0] < st.unc.upper[0] and st.nfev > 0
    # from the lower valley: the same minimum, no restart (it costs nothing where the fit is it)
    x2, J2, res2 = solve(prob, np.array([0.85, 1.0]))
    again = minima.settle(prob, x2, J2, res2, solve, lo, hi)
    assert again.restarts == () and np.array_equal(again.x, x2) and again.nfev == 0
    assert abs(x2[0] - st.x[0]) < 0.01 and margin(J2, res2.fun) > 0


def test_no_restart_past_the_limit():
    """With RESTARTS exhausted a lower point no longer restarts the fit (tol inf)."""
    prob = _problem()
    x, J, res = solve(prob, np.array([1.15, 1.0]))
    old, minima.RESTARTS = minima.RESTARTS, 0
    try:
        st = minima.settle(prob, x, J, res, solve, *_bounds(prob))
    finally:
        minima.RESTARTS = old
    assert st.restarts == () and np.array_equal(st.x, x)


def test_extra_starts_are_seeded_within_their_box_and_the_bounds():
    prob = SimpleNamespace(n_params=2, x0=np.array([1.0, 1.0, 0.0]))
    lo, hi = np.array([0.01, 0.6, -1.0]), np.array([100.0, 100.0, 1.0])
    X = minima.draws(prob, 4, lo, hi, spread=2.0)
    assert X.shape == (4, 3) and np.array_equal(X, minima.draws(prob, 4, lo, hi, spread=2.0))
    assert np.all((X[:, 0] >= 0.5) & (X[:, 0] <= 2.0)) and np.all(X[:, 1] >= 0.6) and np.all(X[:, 2] == 0.0)
    assert len(np.unique(np.floor(np.log(X[:, 0]) / np.log(2.0) * 2 + 2))) == 4  # one per quarter (log)
    assert minima.draws(prob, 0, lo, hi).shape == (0, 3)
    with pytest.raises(ValueError, match="starts"):
        minima.draws(prob, -1, lo, hi)


def test_the_lowest_of_the_starts_is_kept():
    """costs (configured start first); an extra start the simulator cannot run is left out; one
    lower by less than the margin (~2e-4 of the cost here: 400 residuals, nothing left to gain)
    does not replace the one kept; the evaluations are summed over every start."""

    def staged(x0):
        if x0 is not None and x0[0] > 9:
            raise SimulationError("blew up")
        v = 2.0 if x0 is None else float(x0[0])
        return v, np.zeros((400, 1)), SimpleNamespace(fun=np.full(400, np.sqrt(v / 400))), 1, 1, {}

    best, costs = minima.lowest(staged, np.array([[3.0], [99.0], [1.0], [1.0 - 1e-6]]))
    assert np.allclose(costs, [2.0, 3.0, 1.0, 1.0 - 1e-6], rtol=1e-12) and best[0] == 1.0 and best[3:5] == (4, 4)


def test_calibrate_with_an_extra_start_reports_its_costs(free_run, truth):
    """The fit of one parameter from 10 % off and one more start: both fits reach the same
    minimum (costs equal to 1e-6), the configured one kept; the report holds the costs."""
    c = calibrate(
        free_run.head(40), truth.replace(cable_stiffness=1100.0), ("cable_stiffness",), "free", 1e-4, False, check=0.0,
        starts=1,
    )  # fmt: skip
    assert c.costs.shape == (2,) and c.restarts == () and abs(c.estimate[0] / 1000.0 - 1) < 1e-6
    ds = calibration_dataset(c)
    assert ds.attrs["restarts"] == 0 and ds.attrs["restarted_by"] == "none"
    assert np.array_equal(ds.attrs["start_costs_m2"], c.costs)


def _bumped(tol):
    """profile.interval of one unknown (no refit) whose cost above the fit's is g(u) s^2 (s = 1)
    at u = x - 1: below the threshold q^2 = 3.84 to u = 1.04, a barrier up to 6 at 1.3, down to
    4.5 at 2 (the bracket's far end) and -6 at 4, up again to 20 at 8; on the other side 30.72 |u|."""
    knots = ([-8, 0, 1, 1.1, 1.3, 2, 4, 8], [3.84 * 64, 0, 3.38, 4.5, 6, 4.5, -6, 20])
    prob = SimpleNamespace(n_params=1, names=("b",), units=np.ones(1))
    prob.residuals = lambda X: np.sqrt(np.interp(np.atleast_2d(X)[:, :1] - 1.0, *knots) + 10.0)
    return profile.interval(prob, None, np.ones(1), np.ones(1), 0, 10.0, 1.0, 1.96, tol=tol)


def test_a_profile_that_falls_again_past_its_end_is_followed_into_the_lower_valley():
    """The profile's end (u ~ 1.04) is before a barrier; the bracket's far end (u = 2) is below a
    point brentq refitted between them, so the profile is followed outward (u = 4): a point 6 s^2
    below the fit's cost, Lower; without restarts (tol inf) the stretch below the threshold
    beyond the barrier is part of the interval, its far end where g crosses 3.84 between u = 4 and 8."""
    with pytest.raises(profile.Lower) as low:
        _bumped(0.08)
    assert low.value.x[0] == pytest.approx(5.0) and low.value.below == pytest.approx(6.0)
    (lower, upper), shut, _ = _bumped(np.inf)
    assert lower == pytest.approx(1 - 3.84 / 30.72, abs=0.02) and upper == pytest.approx(
        1 + 4 + 4 * 9.84 / 26, abs=0.02
    )
    assert shut == (False, False)
