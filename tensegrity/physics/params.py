"""Physical parameters (docs/design.md §4). SI units except pressure (MPa).

A `Params` never changes during a run. Each field is a float, or an array of shape (B,) when the
robots of a batch differ.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

import numpy as np
from numpy.typing import ArrayLike

from . import actuator

# Column order of the packed (B, NP) parameter array read by the kernel: the struts, the
# actuator's fields side by side (actuator.NAMES), gravity and the ground contact.
NAMES = (
    ("strut_length", "strut_radius", "strut_mass")
    + actuator.NAMES
    + (
        "gravity",
        "ground_stiffness",
        "ground_damping",
        "friction",
        "friction_stiffness",
        "friction_damping",
        "strut_damping",
        "max_speed",
    )
)
POSITIVE = (
    "strut_length",
    "strut_radius",
    "strut_mass",
    "cable_exponent",
    "cable_stiffness",
    "cable_rest_length",
    "muscle_min_length",
    "ground_stiffness",
    "friction_stiffness",
    "max_speed",
)


def rest_length(strut_length: ArrayLike, pretension: ArrayLike, stiffness: ArrayLike) -> float | np.ndarray:
    """Cable rest length L = l0 - T0/K (m) that gives every cable the prestress T0 (N) in the
    symmetric state at zero pressure, where its length is l0 = S sqrt(6)/4 (strut length S m,
    cable stiffness K N/m; docs/design.md §3-4). A float, or an array if any input is one."""
    l0 = np.asarray(strut_length, dtype=float) * math.sqrt(6) / 4
    with np.errstate(divide="ignore", invalid="ignore"):
        rest = l0 - np.asarray(pretension, float) / np.asarray(stiffness, float)
    return rest if rest.ndim else float(rest)


@dataclass(frozen=True)
class Params:
    """Robot, cable, ground and contact parameters.

    Attributes:
        strut_length: S, m.
        strut_radius: r, m (also the radius of the contact sphere at a strut end).
        strut_mass: m, kg per strut.
        cable_exponent: a in eq. 2, dimensionless.
        cable_stiffness: K, N/m.
        cable_rest_length: L, m; NaN (the default) -> `rest_length` from the pretension.
        cable_pretension: T0, N in every cable of the symmetric state at zero pressure.
        cable_damping: B, N s/m.
        muscle_min_length: Lmin in eq. 1, m.
        muscle_gain: Kg in eq. 1, N/(MPa m).
        gravity: g, m/s^2 (0 in the free mode).
        ground_stiffness: k_n in (C2), N/m.
        ground_damping: c_n in (C2), N s/m.
        friction: mu in (C3)-(C4), dimensionless.
        friction_stiffness: stick spring k_t in (C3)-(C4), N/m.
        friction_damping: stick damper c_t in (C4), N s/m.
        strut_damping: ds in eq. 3, optional linear damping of strut motion, 1/s (0: off).
        max_speed: m/s; a strut end faster than this means the run blew up.
    """

    strut_length: float = 0.5
    strut_radius: float = 0.01
    strut_mass: float = 0.2
    cable_exponent: float = 1.0
    cable_stiffness: float = 1000.0
    cable_rest_length: float = float("nan")
    cable_pretension: float = 20.0
    cable_damping: float = 2.0
    muscle_min_length: float = 0.20
    muscle_gain: float = 589.0
    gravity: float = 9.81
    ground_stiffness: float = 2e4
    ground_damping: float = 100.0
    friction: float = 0.8
    friction_stiffness: float = 2e4
    friction_damping: float = 100.0
    strut_damping: float = 0.0
    max_speed: float = 50.0

    def __post_init__(self):
        if np.all(np.isnan(np.asarray(self.cable_rest_length, dtype=float))):
            object.__setattr__(
                self, "cable_rest_length", rest_length(self.strut_length, self.cable_pretension, self.cable_stiffness)
            )
        self.validate()

    def validate(self) -> None:
        """Raise ValueError naming the first non-finite, non-positive or negative parameter."""
        for f in fields(self):
            val = np.asarray(getattr(self, f.name), dtype=float)
            if val.ndim > 1:
                raise ValueError(f"parameter {f.name}: expected a number or a 1-D array, got shape {val.shape}")
            if not np.all(np.isfinite(val)):
                raise ValueError(f"parameter {f.name} is not finite: {np.asarray(getattr(self, f.name)).tolist()!r}")
            if f.name in POSITIVE and np.any(val <= 0):
                raise ValueError(
                    f"parameter {f.name} must be positive, got {np.asarray(getattr(self, f.name)).tolist()!r}"
                )
            if np.any(val < 0):
                raise ValueError(
                    f"parameter {f.name} must not be negative, got {np.asarray(getattr(self, f.name)).tolist()!r}"
                )
        if np.any(np.asarray(self.muscle_min_length) >= np.asarray(self.cable_rest_length)):
            raise ValueError("parameter muscle_min_length must be below cable_rest_length")

    def replace(self, **kw: float | np.ndarray) -> Params:
        """A copy with the fields kw changed (dataclasses.replace). A change of the pretension,
        the cable stiffness or the strut length recomputes the rest length (`rest_length`),
        unless kw gives it."""
        if "cable_pretension" in kw or "cable_stiffness" in kw or "strut_length" in kw:
            kw.setdefault("cable_rest_length", float("nan"))
        return replace(self, **kw)

    def batch_size(self) -> int | None:
        """B if any field is an array, else None."""
        sizes = {np.size(getattr(self, f.name)) for f in fields(self) if np.ndim(getattr(self, f.name))}
        if len(sizes) > 1:
            raise ValueError(f"parameter arrays have different lengths {sorted(sizes)}")
        return sizes.pop() if sizes else None

    def pack(self, batch: int) -> np.ndarray:
        """(B, NP) float64 array in the column order of NAMES (a fresh copy: the caller may
        write it). A Params never changes, so the array is built once per batch size and kept
        (`simulate` packs at every call, thousands of times in a controlled run)."""
        packed = self.__dict__.get("_packed")
        if packed is None:
            packed = {}
            object.__setattr__(self, "_packed", packed)  # not a field: eq, repr, replace ignore it
        if batch not in packed:
            n = self.batch_size()
            if n is not None and n != batch:
                raise ValueError(f"parameter arrays have length {n}, but the batch has {batch} robots")
            packed[batch] = np.ascontiguousarray(
                np.stack([np.broadcast_to(np.asarray(getattr(self, k), dtype=float), (batch,)) for k in NAMES], axis=1)
            )
        return packed[batch].copy()

    @classmethod
    def from_dict(cls, d: dict) -> Params:
        """Params from a dict of fields; ValueError naming any unknown key."""
        unknown = set(d) - {f.name for f in fields(cls)}
        if unknown:
            raise ValueError(f"unknown parameter(s): {', '.join(sorted(unknown))}")
        return cls(**d)


IDX = {name: k for k, name in enumerate(NAMES)}
