"""The actuator: the muscle and cable law of the paper, eq. 1-2 (docs/design.md §3). A cable of
length l (m) and rate dl/dt (m/s), whose pair has the pressure P (MPa), pulls with

    (1)  A = Kg P max(0, l - Lmin)                              muscle force, N
    (2)  f = max(0, K (l^a - L^a) + B dl/dt + A)                 tension, N (never pushes)

The law is written here once, as two twins that tests/physics/test_twins.py pins together:

- the scalar rule `tension` (with `pack` and `activation`, the constants it reads), written in
  the Python that numba compiles: the kernel compiles them with its own flags and inlines them
  into its cable loop (kernel/stages.py);
- the NumPy twin `tensions` on arrays, and `spring`, the linear spring (S1) that the law is at
  rest for a = 1, which `statics.cable_law` and `dynamics.energy` use.

This module imports no numba, so `params` and the statics load it without the kernel.

Its parameters are the Params fields NAMES, packed side by side into the kernel's parameter
array (`params.NAMES`, from a column c on); `pack` turns them into the ROWS constants of a
robot's lane in the kernel (its per-lane constants C, from a row r on). A new law (selected by a
config key, say `actuator.kind`) is added here: its fields in NAMES (and Params), its constants
in ROWS and `pack` / `constants`, its rule in `tension` / `tensions` with the same arguments.
The kernel calls only `pack`, `activation` and `tension`.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from . import topology as topo

# The law's Params fields, in the order packed (params.NAMES): a, K N/m, L m, B N s/m, Lmin m,
# Kg N/(MPa m).
NAMES = ("cable_exponent", "cable_stiffness", "cable_rest_length", "cable_damping", "muscle_min_length", "muscle_gain")
_EXP, _STIFF, _REST, _DAMP, _MIN, _GAIN = range(len(NAMES))
# Its constants per robot (rows of the kernel's C, `pack`): K N/m, L m, a, L**a, B N s/m, Lmin m.
ROWS = ("K", "LR", "A_EXP", "LA", "BC", "LMIN")
_K, _LR, _A, _LA, _BC, _LMIN = range(len(ROWS))


def pack(prm: np.ndarray, b: int, c: int, C: np.ndarray, r: int, l: int) -> bool:
    """C[r + k, l] <- the constants ROWS of robot b from its parameters prm[b, c + k] (NAMES).
    Returns True if its law is linear (a = 1: `tension` may skip the power)."""
    a = prm[b, c + _EXP]
    C[r + _K, l], C[r + _LR, l] = prm[b, c + _STIFF], prm[b, c + _REST]
    C[r + _A, l], C[r + _LA, l] = a, prm[b, c + _REST] ** a
    C[r + _BC, l], C[r + _LMIN, l] = prm[b, c + _DAMP], prm[b, c + _MIN]
    return a == 1.0


def activation(prm: np.ndarray, b: int, c: int, pressure: float) -> float:
    """The muscle's gain Kg P (N/m, eq. 1) of a cable of robot b (parameters prm[b, c:], NAMES)
    whose pair has `pressure` MPa."""
    return prm[b, c + _GAIN] * pressure


def tension(ln: float, ldot: float, act: float, linear: bool, C: np.ndarray, r: int, l: int) -> float:
    """Cable tension (N) by eq. 2 at length ln m and rate ldot m/s, with the muscle of eq. 1
    (act = Kg P N/m, `activation`), and the constants in rows r... of C[:, l] (`pack`; `linear`
    as it returned). Never negative: 0.0 for a slack cable; NaN passes."""
    K, Lmin = C[r + _K, l], C[r + _LMIN, l]
    f = K * (ln - C[r + _LR, l]) if linear else K * (ln ** C[r + _A, l] - C[r + _LA, l])
    f += C[r + _BC, l] * ldot
    f += (act if (act > 0.0) & (ln > Lmin) else 0.0) * (ln - Lmin)
    return 0.0 if f <= 0.0 else f


def constants(values: ArrayLike) -> np.ndarray:
    """The NumPy twin of `pack`: the constants (len(ROWS), ...) from the parameters values
    (len(NAMES), ...) in the order of NAMES."""
    v = np.asarray(values, dtype=float)
    return np.stack([v[_STIFF], v[_REST], v[_EXP], v[_REST] ** v[_EXP], v[_DAMP], v[_MIN]])


def activations(gain: ArrayLike, pressure: ArrayLike) -> np.ndarray:
    """The NumPy twin of `activation`: Kg P (..., 24) N/m per cable from the muscle gain Kg
    N/(MPa m) (broadcast against the result) and the pair pressures (..., 12) MPa."""
    return gain * np.asarray(pressure, dtype=float)[..., topo.CABLE_PAIR]


def tensions(ln: ArrayLike, ldot: ArrayLike, act: ArrayLike, rows: ArrayLike) -> np.ndarray:
    """The NumPy twin of `tension`: tensions (...) N at lengths ln (...) m, rates ldot (...) m/s
    with muscles act (...) N/m and constants rows (len(ROWS), ...) (`constants`), broadcast."""
    ln, ldot, act = (np.asarray(x, dtype=float) for x in (ln, ldot, act))
    K, Lr, a, La, Bc, Lmin = np.asarray(rows, dtype=float)
    with np.errstate(invalid="ignore"):
        f = np.where(a == 1.0, K * (ln - Lr), K * (ln**a - La))
        f = f + Bc * ldot
        f = f + np.where((act > 0.0) & (ln > Lmin), act, 0.0) * (ln - Lmin)
        return np.where(f <= 0.0, 0.0, f)


def spring(K: ArrayLike, L: ArrayLike, Lmin: ArrayLike, act: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """(S1): eq. 1-2 at rest for a = 1 and l > Lmin is a linear spring, f = k max(0, l - l*),
    of stiffness k = K + Kg P (N/m) and slack length l* = (K L + Kg P Lmin) / k (m), from K N/m,
    L m, Lmin m and act = Kg P N/m (`activations`), broadcast."""
    k = K + act
    return k, (K * L + act * Lmin) / k
