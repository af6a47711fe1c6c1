"""The twisted-string actuator's parameters (docs/design.md §10): `TwistedString`, a DC gear motor
from its datasheet figures and the strands, spring and fibre it pulls, packed for the kernel
(`actuator.MOTOR_ROWS`). The law itself is `actuator`'s (T1)-(T5); the defaults and their sources
are in config/README.md ("The prototype's actuator")."""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

import numpy as np

from . import actuator
from .params import Params
from .schedule import Schedule

# The strands lock at tan(alpha) = theta r / p = pi / 2 (two strands, Palli et al. 2013 eq. 10).
LOCK_SLOPE = math.pi / 2


@dataclass(frozen=True)
class TwistedString:
    """One motor per cable (24), the two of a pair at the pair's voltage. Each field is a float,
    or an array (B,) when the robots of a batch differ.

    Attributes:
        rated_voltage: V at which the datasheet figures hold, V.
        stall_torque: at the output shaft and rated voltage, N m.
        stall_current: A at stall and rated voltage.
        no_load_speed: at the output shaft, rad/s.
        no_load_current: A.
        gear_ratio: N, motor turns per output turn.
        rotor_inertia: J_r, kg m^2 (motor side).
        viscous_friction: b, N m s/rad (output side; 0: all friction in the Coulomb term).
        string_length: L0, m, of the twisted strands (untwisted).
        string_radius: r, m, of one strand.
        spring_stiffness: N/m of the cable's spring.
        fibre_stiffness: N/m of the aramid fibre in series with it.
        pretension: T0, N in every cable of the symmetric robot at theta = 0.
        damping: B, N s/m of the cable's stretch.
    """

    rated_voltage: float = 12.0
    stall_torque: float = 0.0980665
    stall_current: float = 0.75
    no_load_speed: float = 47.124
    no_load_current: float = 0.08
    gear_ratio: float = 75.81
    rotor_inertia: float = 2.0e-8
    viscous_friction: float = 0.0
    string_length: float = 0.28
    string_radius: float = 4.5e-4
    spring_stiffness: float = 1000.0
    fibre_stiffness: float = 1.8e5
    pretension: float = 20.0
    damping: float = 2.0

    def __post_init__(self):
        for f in fields(self):
            v = np.asarray(getattr(self, f.name), dtype=float)
            if v.ndim > 1 or not np.all(np.isfinite(v)):
                raise ValueError(
                    f"actuator parameter {f.name} must be a finite number or a 1-D array, got {v.tolist()!r}"
                )
            if np.any(v < 0) or (f.name not in ("viscous_friction", "damping", "pretension") and np.any(v <= 0)):
                raise ValueError(f"actuator parameter {f.name} must be positive, got {v.tolist()!r}")
        if np.any(np.asarray(self.no_load_current) >= np.asarray(self.stall_current)):
            raise ValueError("actuator parameter no_load_current must be below stall_current")

    def replace(self, **kw: float | np.ndarray) -> TwistedString:
        return replace(self, **kw)

    # ---- the motor's constants from its datasheet (docs/design.md §10) ----
    @property
    def resistance(self) -> float | np.ndarray:
        """R = V / I_stall, ohm."""
        return np.divide(self.rated_voltage, self.stall_current)

    @property
    def emf_constant(self) -> float | np.ndarray:
        """ke = (V - R I0) / (N omega0), V s/rad (motor side); kt = ke in SI units."""
        return (self.rated_voltage - self.resistance * self.no_load_current) / (self.gear_ratio * self.no_load_speed)

    @property
    def gear_efficiency(self) -> float | np.ndarray:
        """eta = tau_stall / (N kt I_stall): the gearbox's share of the motor's stall torque."""
        return self.stall_torque / (self.gear_ratio * self.emf_constant * self.stall_current)

    @property
    def friction_torque(self) -> float | np.ndarray:
        """TC = tau_stall I0 / I_stall, N m (output side): what the no-load current drives."""
        return self.stall_torque * self.no_load_current / self.stall_current

    @property
    def inertia(self) -> float | np.ndarray:
        """J = N^2 J_r, kg m^2 at the output shaft (the gears' own inertia neglected)."""
        return np.square(self.gear_ratio) * self.rotor_inertia

    @property
    def stiffness(self) -> float | np.ndarray:
        """K of the spring and fibre in series, N/m."""
        return 1.0 / (1.0 / np.asarray(self.spring_stiffness, float) + 1.0 / np.asarray(self.fibre_stiffness, float))

    def rows(self, params: Params, dt: float) -> np.ndarray:
        """The constants (len(actuator.MOTOR_ROWS), ...) of (T1)-(T5) at time step dt s; the rest
        length from the strut length S: LR = S sqrt(6)/4 - T0/K (as params.rest_length)."""
        gain = self.gear_efficiency * self.gear_ratio * self.emf_constant / self.resistance
        damp = gain * self.gear_ratio * self.emf_constant + self.viscous_friction
        rest = np.asarray(params.strut_length, float) * math.sqrt(6) / 4 - np.asarray(self.pretension) / self.stiffness
        return actuator.motor_rows(
            self.stiffness,
            rest,
            self.damping,
            self.string_length,
            self.string_radius,
            gain,
            damp,
            self.friction_torque,
            dt / self.inertia,
            dt,
        )

    def pack(self, params: Params, batch: int, dt: float) -> np.ndarray:
        """(B, len(MOTOR_ROWS)) float64, C-ordered: `rows` per robot."""
        r = self.rows(params, dt)
        if r.ndim > 1 and r.shape[1] not in (1, batch):
            raise ValueError(f"actuator parameter arrays have length {r.shape[1]}, but the batch has {batch} robots")
        return np.ascontiguousarray(np.broadcast_to(r.reshape(len(actuator.MOTOR_ROWS), -1).T, (batch, r.shape[0])))

    @property
    def lock_angle(self) -> float | np.ndarray:
        """The twist rad at which the strands lock: theta r = L0 sin(atan(LOCK_SLOPE)) (T1)."""
        L0, r = np.asarray(self.string_length, float), np.asarray(self.string_radius, float)
        return L0 * math.sin(math.atan(LOCK_SLOPE)) / r

    def locked(self, theta: np.ndarray) -> np.ndarray:
        """True where the twist theta rad is past the strands' lock (the model no longer holds)."""
        limit = np.asarray(self.lock_angle)
        return np.abs(theta) > (limit[..., None] if limit.ndim else limit)

    @classmethod
    def from_dict(cls, d: dict) -> TwistedString:
        """From a dict of fields; ValueError naming any unknown key."""
        unknown = set(d) - {f.name for f in fields(cls)}
        if unknown:
            raise ValueError(f"unknown actuator parameter(s): {', '.join(sorted(unknown))}")
        return cls(**d)


MAX_VOLTAGE = 24.0  # V; twice the rated voltage of a 12 V motor


def check_voltages(v: np.ndarray, name: str = "voltage") -> np.ndarray:
    """v as a float array; ValueError naming `name` if any value is NaN or outside
    [-MAX_VOLTAGE, MAX_VOLTAGE] V (a negative voltage untwists)."""
    a = np.asarray(v, dtype=float)
    bad = ~(np.abs(a) <= MAX_VOLTAGE)
    if np.any(bad):
        raise ValueError(f"{name}: {float(a[bad].ravel()[0])!r} V is outside -{MAX_VOLTAGE}..{MAX_VOLTAGE} V")
    return a


class Voltages(Schedule):
    """A `Schedule` of voltages (V) instead of pressures: its `pressure` array holds volts
    (B, K, 12) per pair or (B, K, 24) per cable, for `dynamics.simulate(..., motors=...)`."""

    check = staticmethod(check_voltages)
