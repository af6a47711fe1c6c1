"""The heavier checks of calibration (issue 32), marked slow: the grounded mode in a turned and
shifted measurement frame, and the coverage of the 95 % intervals under 0.5 mm of noise (runs in
pressures and in volts)."""

import numpy as np
import pytest

from tensegrity.calibration import calibrate
from tensegrity.calibration import synthetic as syn
from tensegrity.physics import frames
from tensegrity.physics.twisted import TwistedString


def _grounded(truth, hold, start, residual="positions"):
    """Measured in a frame turned 3 deg off level and 40 deg in yaw, shifted by (0.3, -0.2,
    0.05) m; fitted with the initial state and the frame's tilt and height."""
    R = frames.turn([0.0, 0.0, 1.0], np.radians(40)) @ frames.turn([1.0, 0.0, 0.0], np.radians(3))
    m = syn.measure(truth, syn.excitation(0.8, hold), hold, "grounded", rotation=R, offset=(0.3, -0.2, 0.05))
    c = calibrate(m, start, ("cable_stiffness", "muscle_gain"), "grounded", 1e-4, check=0.0, residual=residual)
    Rf, _ = c.problem.frame(c.x)  # world = Rf measured + of: Rf R^T should have no tilt left
    tilt = np.degrees(np.arccos(np.clip((Rf @ R.T)[2, 2], -1, 1)))
    return np.abs(c.estimate / np.array([1000.0, 589.0]) - 1), tilt, c.rms_mm


@pytest.mark.slow
def test_grounded_in_a_tilted_frame_levels_the_frame_and_comes_close(truth, hold):
    """From 1 % off, the grounded fit levels the frame and comes within 0.5 %."""
    err, tilt, rms = _grounded(truth, hold, truth.replace(cable_stiffness=1010.0, muscle_gain=595.0))
    assert err.max() < 5e-3 and tilt < 0.2 and rms < 1.0, (err, tilt, rms)


@pytest.mark.slow
def test_grounded_recovers_parameters_to_a_thousandth(truth, hold):
    """The issue's target in the grounded mode, from 10 % off: met with the growing horizon
    (fitted on the whole trajectory at once, the fit stopped 3 % off at 2 mm RMS)."""
    err, tilt, _ = _grounded(truth, hold, truth.replace(cable_stiffness=1100.0, muscle_gain=540.0))
    assert err.max() < 1e-3 and tilt < 0.2, (err, tilt)


@pytest.mark.slow
def test_grounded_shape_recovers_parameters_to_a_thousandth(truth, hold):
    """The same with the residual 'shape' (the cable lengths, blind to the robot's place and
    heading, which MuJoCo's contact moves; docs/benchmarks.md): the parameters to 0.1 %."""
    err, _, _ = _grounded(truth, hold, truth.replace(cable_stiffness=1100.0, muscle_gain=540.0), "shape")
    assert err.max() < 1e-3, err


@pytest.mark.slow
def test_noisy_intervals_cover_the_truth(truth, start, four, hold):
    """0.5 mm Gaussian noise on every coordinate, 20 seeds drawn at random (seeded): the true
    values lie inside the reported 95 % intervals in 85-100 % of the 80 cases."""
    seeds = np.random.default_rng(32).integers(1000, 10**6, 20)
    inside = []
    for seed in seeds:
        m = syn.measure(truth, syn.excitation(1.2, hold), hold, "free", noise=5e-4, seed=int(seed))
        c = calibrate(m, start, four, "free", 1e-4, check=0.0)
        true = np.array([getattr(truth, k) for k in four])
        inside.append((c.unc.lower <= true) & (true <= c.unc.upper))
        assert abs(c.unc.s - 5e-4) < 0.05 * 5e-4  # the residual recovers the noise
    rate = np.mean(inside)
    assert 0.85 <= rate <= 1.0, np.mean(inside, axis=0)


@pytest.mark.slow  # ~30 min of CPU: 20 fits of 6.2 s in volts (17-50 s each) and their profiles (11-34 refits)
def test_noisy_runs_in_volts_give_intervals_that_hold(truth):
    """Runs in volts (the twisted strings twisted up and back for 3 s each, `synthetic.twisting`),
    0.5 mm of noise, 20 seeds drawn at random: the spring stiffness, pretension and stall torque
    fitted from 10-17 % off (the damping, which the slow twisting hardly sees, configured 15 %
    off). Where the cost along the linearised interval is not the linear prediction
    (`linearity.linear`: the stiffness and pretension, nearly always) the interval is the profile
    likelihood's (`profile`); every interval is given, and the true value lies inside
    85-100 % of them (docs/benchmarks.md, "Profile-likelihood intervals")."""
    key, strings = "actuator.twisted_string.", TwistedString()
    fit = ("spring_stiffness", "pretension", "stall_torque")
    start = strings.replace(spring_stiffness=1100.0, pretension=17.0, stall_torque=0.0833, damping=2.3)
    true = np.array([getattr(strings, k) for k in fit])
    inside, methods = [], []
    for seed in np.random.default_rng(32).integers(1000, 10**6, 20):
        m = syn.measure(truth, syn.twisting(6.2), 0.1, "free", motors=strings, noise=5e-4, seed=int(seed))
        c = calibrate(m, truth, tuple(key + k for k in fit), "free", 1e-4, check=0.0, motors=start)
        assert not c.unc.undetermined and np.isfinite([c.unc.lower, c.unc.upper]).all(), c.unc.undetermined
        inside.append((c.unc.lower <= true) & (true <= c.unc.upper))
        methods += c.unc.method
    assert methods.count("profile") >= 20, methods  # the profile is what gives them
    assert 0.85 <= np.mean(inside) <= 1.0, np.sum(inside, axis=0)
