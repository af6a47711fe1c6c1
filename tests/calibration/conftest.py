"""Measurements made by our own simulator, shared by the calibration tests."""

import pytest

from tensegrity.calibration import synthetic as syn
from tensegrity.physics.params import Params

HOLD = 0.2  # s per pressure step: the first at rest, so that the first samples stand still


@pytest.fixture(scope="session")
def four() -> tuple[str, ...]:
    """The four parameters of the issue's targets."""
    return ("cable_stiffness", "cable_pretension", "cable_damping", "muscle_gain")


@pytest.fixture(scope="session")
def hold() -> float:
    return HOLD


@pytest.fixture(scope="session")
def truth() -> Params:
    return Params()


@pytest.fixture(scope="session")
def start(truth) -> Params:
    """The configuration a calibration starts from: every fitted value 10-20 % off."""
    return truth.replace(cable_stiffness=1150.0, cable_pretension=17.0, cable_damping=2.4, muscle_gain=530.0)


@pytest.fixture(scope="session")
def free_run(truth):
    """1.2 s of the free robot driven by pressure steps, sampled at 100 Hz, no noise."""
    return syn.measure(truth, syn.excitation(1.2, HOLD), HOLD, "free", rate=100.0)
