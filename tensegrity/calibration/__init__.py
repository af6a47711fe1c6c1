"""Calibration from measured trajectories (docs/design.md §9): the model that reproduces a
measured robot's motion, and what the measurement can and cannot tell about it.

measurement  the measured samples, their grid and gaps, the pressure schedule they replay
initial      the initial state (rigid fit of the strut ends) and the measurement's frame
model        the batched residual of simulated against measured node positions or cable lengths
fit          least squares, the batched Jacobian, the prediction check (`calibrate`)
uncertainty  standard errors, intervals, correlations, the combinations not determined
misfit       whether the model fits the run to its noise (else no interval holds)
linearity    whether each interval holds: the cost at its ends against the linear prediction
profile      the profile-likelihood interval of a parameter whose linearised one does not hold
minima       restarts from a lower point those checks find; extra starts, the lowest cost kept
"""

from .fit import Calibration, calibrate
from .measurement import Measurement

__all__ = ["Calibration", "Measurement", "calibrate"]
