"""Physical parameters (docs/design.md §4). SI units except pressure (MPa).

A `Params` never changes during a run. Each field is a float, or an array of shape (B,) when the
robots of a batch differ.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

import numpy as np

from . import actuator

# Column order of the packed (B, NP) parameter array read by the kernel: the struts, the
# actuator's fields side by side (actuator.NAMES), gravity and the ground contact.
NAMES = (("strut_length", "strut_radius", "strut_mass") + actuator.NAMES
         + ("gravity", "ground_stiffness", "ground_damping", "friction", "friction_stiffness",
            "friction_damping", "strut_damping", "max_speed"))
POSITIVE = ("strut_length", "strut_radius", "strut_mass", "cable_exponent", "cable_stiffness",
            "cable_rest_length", "muscle_min_length", "ground_stiffness", "friction_stiffness",
            "max_speed")


@dataclass(frozen=True)
class Params:
    """Robot, cable, ground and contact parameters (units in the comments)."""
    strut_length: float = 0.5          # S, m
    strut_radius: float = 0.01         # r, m (also the contact sphere radius)
    strut_mass: float = 0.2            # m, kg per strut
    cable_exponent: float = 1.0        # a in eq. 2, -
    cable_stiffness: float = 1000.0    # K, N/m
    cable_rest_length: float = float("nan")  # L, m; NaN -> l0 - pretension/K
    cable_pretension: float = 20.0     # T0, N in every cable of the symmetric state
    cable_damping: float = 2.0         # B, N s/m
    muscle_min_length: float = 0.20    # Lmin in eq. 1, m
    muscle_gain: float = 589.0         # Kg in eq. 1, N/(MPa m)
    gravity: float = 9.81              # g, m/s^2 (0 in the free mode)
    ground_stiffness: float = 2e4      # k_n, N/m
    ground_damping: float = 100.0      # c_n, N s/m
    friction: float = 0.8              # mu, -
    friction_stiffness: float = 2e4    # stick spring k_t, N/m
    friction_damping: float = 100.0    # stick damper c_t, N s/m
    strut_damping: float = 0.0         # optional linear damping of strut motion, 1/s (off)
    max_speed: float = 50.0            # a node faster than this (m/s) means the run blew up

    def __post_init__(self):
        rest = np.asarray(self.cable_rest_length, dtype=float)
        if np.all(np.isnan(rest)):
            l0 = np.asarray(self.strut_length, dtype=float) * math.sqrt(6) / 4
            with np.errstate(divide="ignore", invalid="ignore"):
                rest = l0 - np.asarray(self.cable_pretension, float) / np.asarray(self.cable_stiffness, float)
            object.__setattr__(self, "cable_rest_length", rest if rest.ndim else float(rest))
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
                raise ValueError(f"parameter {f.name} must be positive, got {np.asarray(getattr(self, f.name)).tolist()!r}")
            if np.any(val < 0):
                raise ValueError(f"parameter {f.name} must not be negative, got {np.asarray(getattr(self, f.name)).tolist()!r}")
        if np.any(np.asarray(self.muscle_min_length) >= np.asarray(self.cable_rest_length)):
            raise ValueError("parameter muscle_min_length must be below cable_rest_length")

    def replace(self, **kw: float | np.ndarray) -> "Params":
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
            packed[batch] = np.ascontiguousarray(np.stack(
                [np.broadcast_to(np.asarray(getattr(self, k), dtype=float), (batch,)) for k in NAMES], axis=1))
        return packed[batch].copy()

    @classmethod
    def from_dict(cls, d: dict) -> "Params":
        unknown = set(d) - {f.name for f in fields(cls)}
        if unknown:
            raise ValueError(f"unknown parameter(s): {', '.join(sorted(unknown))}")
        return cls(**d)


IDX = {name: k for k, name in enumerate(NAMES)}
