"""The contact dampers' stability limit (`calibration.stability`, (D1), docs/design.md §9): above
it the explicit step makes a grounded run chatter and the residual rough, and a fit started there
stalled where it started (docs/benchmarks.md, issue 32); the fit bounds the dampers to it."""

import numpy as np
import pytest

from tensegrity.calibration import calibrate, stability
from tensegrity.calibration import model as mdl
from tensegrity.calibration import synthetic as syn
from tensegrity.calibration.fit import PARAM_RANGE, _bounds

DT = 1e-4


@pytest.fixture(scope="module")
def limit(truth) -> float:
    return stability.limit(truth.strut_mass, truth.strut_length, truth.strut_radius, DT)


def test_the_limit_is_twice_a_strut_end_s_mass_over_the_step(truth, limit):
    """(D1): a force across a strut at its end moves it as m_e = m / (1 + (S/2)^2 m / I_t), about
    m / 4 (exactly m / 4 for a thin strut); c* = 2 m_e / dt."""
    m, S, r = truth.strut_mass, truth.strut_length, truth.strut_radius
    assert limit == pytest.approx(2 * m / (1 + (S / 2) ** 2 * m / (m * (S**2 / 12 + r**2 / 4))) / DT, rel=1e-12)
    assert stability.limit(m, S, 0.0, DT) == pytest.approx(m / (2 * DT), rel=1e-12)


def test_only_the_dampers_are_bounded_by_the_limit(truth, limit, four):
    """The four cable parameters keep the fit's range (a fit of them is bit for bit as before);
    a damper's upper bound is c* (a start beyond it moves to it); a start PARAM_RANGE times beyond
    is refused, naming the key."""
    m = syn.measure(truth, syn.excitation(0.05, 0.01), 0.01, "grounded", rate=100.0)
    prob = mdl.problem(m, truth, four, "grounded", DT, False, False)
    assert np.array_equal(_bounds(prob)[1], np.full(4, PARAM_RANGE))
    fit = (*four, "ground_damping", "friction_damping", "friction_stiffness")
    start = truth.replace(friction_damping=2 * limit)
    hi = _bounds(mdl.problem(m, start, fit, "grounded", DT, False, False))[1]
    expect = [PARAM_RANGE] * 4 + [limit / truth.ground_damping, 0.5, PARAM_RANGE]
    assert hi == pytest.approx(expect, rel=1e-12)
    # a damper that ends at c* is named: its value is the limit, not an estimate
    said = stability.pinned(
        fit[4:], np.array([limit, 0.5 * limit, 1e6]), np.array([100.0, 2 * limit, 2e4]), hi[4:], 1e2
    )
    assert len(said) == 1 and said[0].startswith("ground_damping at its upper bound")
    with pytest.raises(ValueError, match="friction_damping starts"):
        _bounds(mdl.problem(m, truth.replace(friction_damping=PARAM_RANGE * limit), fit, "grounded", DT, False, False))


@pytest.mark.parametrize("key", ["ground_damping", "friction_damping"])
def test_above_the_limit_the_grounded_residual_is_rough(truth, limit, key):
    """The cause of the stall, and the check that reports it (`stability.rough`): below c* the
    shape residual moves with the stiffness in proportion (its difference quotients at steps 1e-9
    and 1e-6 agree); at 1.1 c* a step of 1e-9 moves it by far more than the derivative says
    (chatter: the run depends on round-off)."""
    m = syn.measure(truth, syn.excitation(0.6, 0.2, level=1.0), 0.2, "grounded", rate=100.0)
    prob = mdl.problem(m, truth, ("cable_stiffness", key), "grounded", DT, False, False, None, "shape")
    smooth, rough = (
        stability.rough(prob, np.array([1.0, c / prob.units[1]]), 1e-6) for c in (0.9 * limit, 1.1 * limit)
    )
    assert smooth == pytest.approx([1.0, 1.0], rel=1e-2)
    assert rough[0] > 100 * stability.ROUGH


def test_a_fit_started_beyond_the_limit_moves(truth, limit):
    """Started at 1.3 c* (and the stiffness 10 % off), the fit stalled there before (the stiffness
    still +10 %: a forward-difference Jacobian of a chattering run is noise); now it starts at c*
    and recovers the stiffness and the damper of a run made below it."""
    run = truth.replace(ground_damping=0.8 * limit)
    m = syn.measure(run, syn.excitation(0.6, 0.2, level=1.0), 0.2, "grounded", rate=100.0)
    start = run.replace(cable_stiffness=1.1 * run.cable_stiffness, ground_damping=1.3 * limit)
    c = calibrate(m, start, ("cable_stiffness", "ground_damping"), "grounded", DT, False, False, check=0.0, windows=0)
    err = c.estimate / np.array([run.cable_stiffness, run.ground_damping]) - 1
    assert abs(err[0]) < 1e-3 and abs(err[1]) < 0.05
    assert not [u for u in c.unc.undetermined if "stability limit" in u or "rough" in u]
