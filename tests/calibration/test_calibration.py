"""Calibration recovers the parameters of trajectories made by our own simulator (issue 32):
without noise to 0.1 %, with gaps in the samples too; it names what a measurement cannot
determine (the free mode's common scale of mass and forces) instead of giving a number."""

import numpy as np
import pytest

from tensegrity.calibration import Measurement, calibrate
from tensegrity.calibration import synthetic as syn


def _relative_errors(c, truth):
    return {k: abs(e / getattr(truth, k) - 1) for k, e in zip(c.names, c.estimate, strict=True)}


def test_noise_free_free_mode_recovers_four_parameters_to_a_thousandth(free_run, start, truth, four):
    """The robot stands still over the first samples, so the initial state read from them is
    exact and need not be fitted (the fast path, 5 robots per Jacobian)."""
    c = calibrate(free_run, start, four, "free", 1e-4, fit_initial=False, check=0.0)
    err = _relative_errors(c, truth)
    assert max(err.values()) < 1e-3, err
    assert c.rms_mm < 1e-3 and not c.unc.undetermined
    assert np.all(c.unc.lower <= c.estimate) and np.all(c.estimate <= c.unc.upper)


def test_the_shape_residual_recovers_four_parameters_to_a_thousandth(free_run, start, truth, four):
    """The 24 cable lengths instead of the node positions (`--residual shape`): they do not see
    the robot's rigid motion, but they do the cable law, to 0.1 % without noise."""
    c = calibrate(free_run, start, four, "free", 1e-4, fit_initial=False, check=0.0, residual="shape")
    err = _relative_errors(c, truth)
    assert max(err.values()) < 1e-3, err
    assert c.problem.valid.shape == (free_run.t.size, 24) and c.rms_mm < 1e-3


def test_gaps_occluded_markers_and_missing_rows_are_left_out(free_run, truth):
    """A NaN coordinate (an occluded marker) and rows missing from the grid do not bias the fit:
    the noise-free answer is the same to 0.1 %."""
    keep = np.ones(free_run.t.size, bool)
    keep[[45, 46, 77, 103]] = False  # missing rows: the next row's pressure is held over the gap
    nodes = free_run.nodes.copy()
    nodes[30:60, 4, :] = np.nan  # node 5 occluded for 0.3 s
    nodes[85, 0, 2] = np.nan
    m = Measurement(free_run.t[keep], nodes[keep], free_run.pressure[keep], "free", "with gaps")
    # no row dropped is where the pressure changes (rows 21, 41, ...: it would be held too early)
    start = truth.replace(cable_stiffness=1150.0, cable_pretension=17.0)  # the rest as they are
    c = calibrate(m, start, ("cable_stiffness", "cable_pretension"), "free", 1e-4, fit_initial=False, check=0.0)
    assert max(_relative_errors(c, truth).values()) < 1e-3


def test_free_mode_names_the_common_scale_of_mass_and_forces(free_run, truth):
    """Scaling the strut mass and every force together leaves the free motion unchanged: the
    fit names that combination and gives its parameters no interval."""
    names = ("strut_mass", "cable_stiffness", "cable_pretension", "cable_damping", "muscle_gain")
    c = calibrate(free_run, truth.replace(strut_mass=0.22), names, "free", 1e-4, fit_initial=False, check=0.0)
    assert len(c.unc.undetermined) == 1, c.unc.undetermined
    assert c.unc.undetermined[0].startswith("a common scale of strut_mass, cable_stiffness")
    assert np.isnan(c.unc.se).all() and np.isnan(c.unc.lower).all()
    # the motion is reproduced all the same: the estimates are the truth times one factor
    ratio = c.estimate / np.array([getattr(truth, k) for k in names])
    assert np.ptp(ratio) < 1e-3 * ratio.mean() and c.rms_mm < 1e-3


@pytest.mark.slow  # 20 s: 65 robots per Jacobian
def test_fitting_the_initial_state_recovers_a_moving_start(truth, start, four, hold):
    """The run of `tensegrity simulate` starts moving before its first sample: the initial
    state is fitted with the parameters (60 unknowns more), on a short trajectory."""
    m = syn.measure(truth, syn.excitation(0.6, hold)[1:], hold, "free", rate=100.0)
    m = m.head(m.t.size)  # starts at rest, under pressure: moving from the first interval on
    m = Measurement(m.t[2:], m.nodes[2:], m.pressure[2:], "free", "moving start")
    c = calibrate(m, start, four, "free", 1e-4, check=0.0)
    assert max(_relative_errors(c, truth).values()) < 1e-3
