"""How rolls are driven and judged: `RollSettings` (config section `locomotion`, documented in
config/README.md; the defaults are the schema's, pinned by tests/io/test_settings.py).

A module of its own, below `control` and `lockstep`, which both read it.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from ..physics.params import Params
from ..physics.schedule import MAX_PRESSURE, Schedule, whole_steps
from ..physics.twisted import MAX_VOLTAGE, TwistedString, Voltages

__all__ = ["RollSettings"]

_FLAGS = ("combine", "min_alignment", "brake", "escape_attempts", "lookahead", "optimised_actions", "cable_actions")
# (those may be 0 or False)
_COUNTS = ("max_attempts", "max_rolls", "escape_attempts", "lookahead")


@dataclass(frozen=True)
class RollSettings:
    """ramp_rate MPa/s; interval s (pressure step and check period); lift_tolerance m;
    hold_time s; release_margin m; release_time s; catch_time s; settle_speed m/s; settle_time s;
    contact_tolerance m; combine; min_alignment; max_attempts; max_rolls; arrive_tolerance m;
    brake; brake_margin m; brake_rate MPa/s; brake_release_time s;
    escape_attempts; lookahead; optimised_actions; cable_actions; strut_damping 1/s; dt s (the simulator's
    time step, config sim.dt); motors: the twisted-string actuators the rolls drive (config
    actuator.twisted_string under actuator.kind twisted_string; None: the pneumatic muscles).

    The level is the actuator's (`unit`): pressure in MPa for the muscles, motor voltage in V
    for the twisted strings; ramp_rate and brake_rate are then in V/s (one law, docs/design.md
    §6, "Locomotion in volts").

    A roll (see `control.roll`) ramps the pressure at ramp_rate; a support node lifted by more
    than lift_tolerance holds it (at most hold_time s, then the ramp goes on; where the brake
    does not act, not held again while a node stays lifted); once the unactuated robot would
    fall over the pivot edge by release_margin (`contact.past_edge`) the pressure ramps down
    over release_time, and once it has landed on the next face over catch_time (held while it
    tips back); it has settled when its CoG moves slower than settle_speed on a face
    (contact_tolerance) for three checks, or after settle_time. With brake, a run holds the
    robot on each face where the workspace puts its CoG projection less than brake_margin
    inside, with the pair `brake.hold` chooses, changed at most at brake_rate and handed over to
    a roll as its pressure nears the plan's; a roll is braked only where the unbraked robot is
    predicted not to stand (`brake.Brake.active`), and then its pressure falls over
    brake_release_time instead of release_time. Before each roll, on every ground, a run
    simulates candidate rolls from the robot's state, the first, then 2, 4, ... up to lookahead, then all
    while none is acceptable, and makes the max_attempts best (`lookahead.choose`). With
    optimised_actions, the optimised actions of any set of pairs (`actuation.candidates`)
    come last, computed only when the horizon reaches them; with cable_actions, after them,
    those of the 24 cables one by one (weights (24,)). With lookahead 0 the plan's
    max_attempts candidates are tried in the world, then escape_attempts
    more actions in the order of `brake.escape`, before the run ends "stuck".
    Every rolling simulation damps the struts by strut_damping (`rolling`), whatever the
    `Params` given: the robot of the pipeline's runs and of `roll_to` is the same."""

    ramp_rate: float = 1.0
    interval: float = 0.02
    lift_tolerance: float = 0.001
    hold_time: float = 1.0
    release_margin: float = 0.005
    release_time: float = 0.4
    catch_time: float = 1.5
    settle_speed: float = 0.03
    settle_time: float = 6.0
    contact_tolerance: float = 0.01
    combine: bool = True
    min_alignment: float = 0.0
    max_attempts: int = 3
    lookahead: int = 30
    max_rolls: int = 200
    arrive_tolerance: float = 0.3
    brake: bool = True
    brake_margin: float = 0.035
    brake_rate: float = 6.0
    brake_release_time: float = 1.5
    escape_attempts: int = 8
    optimised_actions: bool = True
    cable_actions: bool = False
    strut_damping: float = 1.0
    dt: float = 1e-4
    motors: TwistedString | None = None

    def __post_init__(self):
        if not (self.motors is None or isinstance(self.motors, TwistedString)):
            raise ValueError(f"locomotion motors must be a TwistedString or None, got {type(self.motors).__name__}")
        for f in fields(self):
            v = getattr(self, f.name)
            if f.name in _FLAGS or f.name == "motors":
                continue
            if f.name == "strut_damping":
                if isinstance(v, bool) or not (np.isfinite(v) and v >= 0):
                    raise ValueError(f"locomotion setting strut_damping must be >= 0, got {np.asarray(v).tolist()!r}")
                continue
            if isinstance(v, bool) or not (np.isfinite(v) and v > 0):
                raise ValueError(
                    f"locomotion setting {f.name} must be a positive number, got {np.asarray(v).tolist()!r}"
                )
        for name in _COUNTS:
            v = getattr(self, name)
            if isinstance(v, bool) or not np.isfinite(v) or v < 0 or float(v) != int(v):
                raise ValueError(f"locomotion setting {name} must be a whole number, got {np.asarray(v).tolist()!r}")
            object.__setattr__(self, name, int(v))
        if not (np.isfinite(self.min_alignment) and -1.0 <= self.min_alignment < 1.0):
            raise ValueError(
                f"locomotion setting min_alignment must be in [-1, 1), got {np.asarray(self.min_alignment).tolist()!r}"
            )
        if self.motors is not None and self.hold_time < self.twist_time - 1e-9:
            raise ValueError(
                f"locomotion setting hold_time {self.hold_time} s is shorter than the {self.twist_time:.1f} s the "
                "motors of actuator.twisted_string take to twist their strands to the lock at no-load speed: a "
                "roll in volts would give up before its voltage is reached; set locomotion.hold_time >= "
                f"{self.twist_time:.1f}"
            )
        if not whole_steps(self.interval, self.dt):
            raise ValueError(
                f"locomotion interval {self.interval} s is not a whole number of time steps of {self.dt} s"
            )

    @property
    def twist_time(self) -> float:
        """s the motors take to twist their strands from rest to the lock at no-load speed (the
        longest of a batch; 11.1 s for the defaults of config/README.md); 0 for the muscles. A
        level in volts is reached once the motor stalls against the string, after up to that long:
        a roll in volts holds each level at least that long (hold_time)."""
        if self.motors is None:
            return 0.0
        return float(np.max(np.asarray(self.motors.lock_angle) / np.asarray(self.motors.no_load_speed)))

    @property
    def unit(self) -> str:
        """The unit of the rolls' level: MPa (pneumatic) or V (twisted strings)."""
        return "MPa" if self.motors is None else "V"

    @property
    def max_level(self) -> float:
        """The highest level a roll may command: MAX_PRESSURE MPa or MAX_VOLTAGE V."""
        return MAX_PRESSURE if self.motors is None else MAX_VOLTAGE

    def schedule(self, levels: np.ndarray) -> Schedule:
        """The pair levels (B, 12) held one check interval, as the simulator takes them: pressures
        (MPa) or, with motors, voltages (V, `twisted.Voltages`)."""
        return (Schedule if self.motors is None else Voltages).constant(levels, self.interval)

    def rolling(self, params: Params) -> Params:
        """`params` as every rolling simulation runs them: struts damped by strut_damping 1/s."""
        if np.all(np.asarray(params.strut_damping) == self.strut_damping):
            return params
        return params.replace(strut_damping=float(self.strut_damping))
