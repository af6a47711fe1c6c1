"""Intervals with model discrepancy (`calibration.discrepancy`, docs/design.md §9): a fit whose
residuals say the model misfits gets the interval of refits on disjoint time windows (W1), which
widens with the model error and holds the truth where the classical one does not; a right model
with independent noise keeps its classical interval bit for bit, no window fitted."""

import numpy as np
import pytest
from scipy import stats
from scipy.optimize import least_squares

from tensegrity.calibration import calibrate, discrepancy
from tensegrity.calibration import synthetic as syn
from tensegrity.calibration.measurement import Measurement
from tensegrity.calibration.misfit import misfit
from tensegrity.calibration.uncertainty import uncertainty

NAMES = ("a", "b")
T, M = 200, 3  # samples, entries per sample
TRUE = np.array([1.0, 2.0])


def _line(y: np.ndarray, t: np.ndarray) -> tuple:
    """The straight line a + b t fitted to y (k * M,) at times t (k * M,): estimate, Jacobian,
    residuals."""
    res = least_squares(lambda x: x[0] + x[1] * t - y, np.ones(2))
    return res.x, res.jac, res.fun


def _run(error: float, seed: int = 5) -> tuple:
    """A measurement of the line 1 + 2 t over 2 s with 10 mm of noise and a slow sine of `error`
    (m) the model lacks, as a `Measurement` whose node 1's x holds y (the rest zero), the
    classical uncertainty after `misfit`, and the estimate."""
    s = np.linspace(0, 2, T)
    y = TRUE[0] + TRUE[1] * s[:, None] + error * np.sin(np.pi * s[:, None])
    y = y + np.random.default_rng(seed).normal(0.0, 0.01, (T, M))
    nodes = np.zeros((T, 12, 3))
    nodes[:, 0, :] = y
    m = Measurement(s, nodes, np.zeros((T, 12)))
    x, J, r = _line(y.reshape(-1), np.repeat(s, M))
    unc = uncertainty(J, r, 2, x, NAMES)
    return m, misfit(r.reshape(T, M), unc, NAMES), unc, x


def _widen(m: Measurement, unc, x: np.ndarray, k: int = 4):
    calls = []

    def refit(w: Measurement) -> np.ndarray:
        calls.append(w)
        a = int(w.source.rsplit("[", 1)[1].split(":")[0])
        fitted, _, _ = _line(w.nodes[:, 0, :].reshape(-1), np.repeat(w.t + m.t[a], M))
        return fitted

    out, W = discrepancy.widen(unc, NAMES, x, np.ones(2), m, k, refit, 100.0)
    return out, W, calls


def test_independent_residuals_keep_the_classical_interval_and_fit_no_window():
    m, unc, before, x = _run(0.0)
    out, W, calls = _widen(m, unc, x)
    assert out is unc and unc is before and not calls and W.shape == (0, 2)
    assert out.method == ("linearised", "linearised") and out.lower[1] < TRUE[1] < out.upper[1]


@pytest.mark.parametrize("error", [0.03, 0.1])
def test_a_model_error_gets_a_window_interval_that_holds_the_truth(error):
    """A sine the line lacks biases the slope by many classical standard errors; misfit drops
    the interval, the windows' gives one, wider than the classical, holding the truth."""
    m, unc, before, x = _run(error)
    assert abs(x[1] - TRUE[1]) > 3 * before.se[1]  # the classical interval misses
    assert np.isnan(unc.lower).all()
    out, W, calls = _widen(m, unc, x)
    assert len(calls) == 4 and W.shape == (4, 2) and out.method == ("windows", "windows")
    assert out.lower[1] < TRUE[1] < out.upper[1] and out.upper[1] - out.lower[1] > before.upper[1] - before.lower[1]
    assert out.undetermined == () and np.isfinite(out.se).all() and out.refits == 4


def test_the_interval_widens_with_the_model_error():
    widths = []
    for error in (0.03, 0.1, 0.3):
        m, unc, _, x = _run(error)
        out, _, _ = _widen(m, unc, x)
        widths.append(np.log(out.upper / out.lower))
    assert np.all(np.diff(np.array(widths), axis=0) > 0)


def test_the_interval_is_W1():
    """(W1) by hand: windows e^{+-0.1} about the estimate, K = 2: s = 0.1 sqrt(2)."""
    est = np.array([2.0])
    lo, hi, s = discrepancy.interval(est, np.array([[2.0 * np.exp(0.1)], [2.0 * np.exp(-0.1)]]))
    q = stats.t.ppf(0.975, 1)
    assert s[0] == pytest.approx(0.1 * np.sqrt(2)) and hi[0] == pytest.approx(2.0 * np.exp(q * s[0]))
    assert lo[0] * hi[0] == pytest.approx(4.0)
    # a failed window (NaN) is left out; fewer than 2 left: no interval
    lo, hi, s = discrepancy.interval(est, np.array([[np.nan], [2.2]]))
    assert np.isnan(lo).all() and np.isnan(hi).all() and np.isnan(s).all()


def test_a_window_interval_beyond_the_bounds_is_open_there():
    m, unc, _, x = _run(0.1)
    out, _ = discrepancy.widen(unc, NAMES, x, x, m, 4, lambda w: x * np.array([1.0, 1e4]), 10.0)
    assert out.method[1] == "windows, open below, open above" and out.upper[1] == pytest.approx(10 * x[1])
    assert [u for u in out.undetermined if discrepancy.UNBOUNDED in u] == [f"{NAMES[1]} {discrepancy.UNBOUNDED}"]


def test_split_and_its_errors():
    m, _, _, _ = _run(0.0)
    parts = discrepancy.split(m, 4)
    assert [p.t.size for p in parts] == [50] * 4 and all(p.t[0] == 0.0 for p in parts)
    assert np.array_equal(np.concatenate([p.nodes for p in parts]), m.nodes)
    with pytest.raises(ValueError, match="windows"):
        discrepancy.split(m, 1)
    with pytest.raises(ValueError, match="windows"):
        discrepancy.split(m, 20)
    # the default: WINDOWS grounded if each gets LEAST samples (a shorter run: none), none free
    k, least = discrepancy.WINDOWS, discrepancy.LEAST
    assert discrepancy.count(None, "grounded", k * least) == k and discrepancy.count(None, "grounded", 31) == 0
    assert discrepancy.count(None, "free", 1000) == 0 and discrepancy.count(6, "free", 1000) == 6


def test_a_free_run_of_a_right_model_is_unchanged_with_windows(truth, hold):
    """The free mode's default fits no window; asked for windows, a run our model reproduces to
    its noise fits none either: estimates and intervals bit for bit."""
    m = syn.measure(truth, syn.excitation(0.6, hold), hold, "free", rate=100.0, noise=5e-4, seed=3)
    start = truth.replace(muscle_gain=560.0)
    a = calibrate(m, start, ("muscle_gain",), "free", 1e-4, check=0.0)
    b = calibrate(m, start, ("muscle_gain",), "free", 1e-4, check=0.0, windows=4)
    assert a.unc.method == ("linearised",) and np.array_equal(a.estimate, b.estimate)
    assert np.array_equal(a.unc.lower, b.unc.lower) and np.array_equal(a.unc.upper, b.unc.upper)
    assert a.problem.residual == "positions" and b.unc.refits == a.unc.refits


def test_the_grounded_default_residual_is_the_shape(truth, hold):
    """The grounded mode fits the cable lengths unless told otherwise; the free mode the node
    positions (model.DEFAULT_RESIDUAL)."""
    m = syn.measure(truth, syn.excitation(0.05, 0.01), 0.01, "grounded", rate=100.0)
    c = calibrate(m, truth, ("muscle_gain",), "grounded", 1e-4, fit_initial=False, check=0.0, windows=0)
    p = calibrate(m, truth, ("muscle_gain",), "grounded", 1e-4, False, check=0.0, residual="positions", windows=0)
    assert c.problem.residual == "shape" and p.problem.residual == "positions"


def test_a_window_interval_is_clipped_to_a_damper_s_own_upper_bound():
    """`upper` (a damper's stability limit, `stability`) clips the interval where `bound` would not;
    nothing is said of the contact or stick constants any more (their window fits converge)."""
    m, unc, _, x = _run(0.1)
    out, _ = discrepancy.widen(unc, NAMES, x, x, m, 4, lambda w: x * np.array([1.0, 1.5]), 10.0, np.array([10.0, 1.2]))
    assert out.method == ("windows", "windows, open above") and out.upper[1] == pytest.approx(1.2 * x[1])
    assert not [u for u in out.undetermined if "not validated" in u]
