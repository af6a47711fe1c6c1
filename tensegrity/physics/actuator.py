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

import math

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
    N/(MPa m) (broadcast against the result) and the pressures (..., 12) MPa per pair or
    (..., 24) per cable (`topology.cable_levels`)."""
    return gain * topo.cable_levels(pressure)


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


# ---- The twisted-string actuator (docs/design.md §10, eq. T1-T5) --------------------------------
# A DC gear motor twists two strands of length L0 and radius r (Palli et al. 2013); they are in
# series with a spring and the aramid fibre (series stiffness K). Output angle theta (rad), speed
# omega (rad/s); the cable's pair voltage V (V). Its constants per cable, in the order packed
# (`TwistedString.pack`, rows of the kernel's motor constants M): K N/m, rest length at theta = 0
# LR m, damping B N s/m, L0 m, r m, torque per volt G = eta N kt / R (N m/V), electrical and
# viscous damping D = eta N^2 kt ke / R + b (N m s/rad), Coulomb friction TC N m,
# dt/J 1/(kg m^2 s) (J = N^2 J_rotor, output side), the time step dt s; then, derived
# from these so that the kernel's step need not (`motor_rows`): L0^2 m^2, r^2 m^2, the guard
# (P_MIN L0)^2 m^2 and L0 - LR m. A step of the kernel's (`kernel/strings.py`): t, p =
# `twist`, h = `ratio`, f = `string_tension`, tau = `motor_torque`, then `motor_step`.
MOTOR_ROWS = ("K", "LR", "B", "L0", "RS", "GAIN", "DAMP", "TC", "DT_J", "DT", "L0SQ", "RSQ", "PSQ_MIN", "L0_LR")
(_MK, _MLR, _MB, _ML0, _MRS, _MGAIN, _MDAMP, _MTC, _MDTJ, _MDT, _ML0SQ, _MRSQ, _MPSQ, _ML0LR) = range(len(MOTOR_ROWS))
# The strands stay apart from each other while p > P_MIN L0; below, the model is off (Palli et
# al. 2013 eq. 10: two strands lock at tan(alpha) = pi/2, p = 0.54 L0). The guard only keeps a
# run finite; `TwistedString` reports a twist past the lock.
P_MIN = 0.05


def motor_rows(*first: ArrayLike) -> np.ndarray:
    """The constants (len(MOTOR_ROWS), ...) from the first ten of MOTOR_ROWS, in its order
    (arrays broadcast), followed by those derived from them."""
    if len(first) != _ML0SQ:
        raise ValueError(f"motor_rows takes the first {_ML0SQ} constants of MOTOR_ROWS, got {len(first)}")
    v = [np.asarray(x, dtype=float) for x in first]
    L0, r, LR = v[_ML0], v[_MRS], v[_MLR]
    v += [L0 * L0, r * r, np.square(P_MIN * L0), L0 - LR]
    return np.stack(np.broadcast_arrays(*v))


def twist(theta: float, M: np.ndarray, l: int) -> tuple[float, float]:
    """(T1): of the two strands twisted by theta rad (constants M[:, l], MOTOR_ROWS), t = theta
    r^2 m^2/rad (for `ratio`) and their span p = sqrt(L0^2 - (theta r)^2) = sqrt(L0^2 - theta t)
    m, at least P_MIN L0; their contraction is c = L0 - p. NaN passes."""
    t = theta * M[_MRSQ, l]
    q = M[_ML0SQ, l] - theta * t
    return t, math.sqrt(M[_MPSQ, l] if q < M[_MPSQ, l] else q)


def ratio(t: float, ip: float) -> float:
    """(T2): the transmission ratio h = dc/dtheta = theta r^2 / p (m/rad) from t = theta r^2
    m^2/rad and ip = 1 / p 1/m (`twist`; the caller's reciprocal, which may share a division),
    so that the motor feels tau = f h (virtual work)."""
    return t * ip


def string_tension(ln: float, ldot: float, p: float, h: float, omega: float, M: np.ndarray, l: int) -> float:
    """(T3): tension (N) of a twisted-string cable of length ln m and rate ldot m/s whose strands
    span p m at the ratio h m/rad (`twist`, `ratio`), motor speed omega rad/s, constants M[:, l]
    (MOTOR_ROWS): the spring and fibre in series stretch by ln - LR + c = ln - p + (L0 - LR),
    f = max(0, K stretch + B d(stretch)/dt), d(stretch)/dt = ldot + h omega."""
    f = M[_MK, l] * (ln - p + M[_ML0LR, l]) + M[_MB, l] * (ldot + h * omega)
    return 0.0 if f <= 0.0 else f


def motor_torque(volt: float, omega: float, M: np.ndarray, l: int) -> float:
    """(T4): the motor's torque (N m, output side) at `volt` V and speed omega rad/s, before the
    string's load f h and the gears' Coulomb friction TC (`motor_step`): G V - D omega."""
    return M[_MGAIN, l] * volt - M[_MDAMP, l] * omega


def motor_step(
    theta: float, omega: float, tau: float, f: float, h: float, M: np.ndarray, l: int
) -> tuple[float, float]:
    """(T5): one semi-implicit Euler step of the motor with the torque tau N m (`motor_torque`)
    under the string's tension f N at the ratio h m/rad and the Coulomb friction TC, applied at
    the velocity level: w = omega + dt/J (tau - f h); the motor sticks (w = 0) where the friction
    can stop it within the step, |w| <= dt TC / J, else w -= sign(w) dt TC / J; then
    theta += dt w. Returns the new theta rad, omega rad/s."""
    w = omega + M[_MDTJ, l] * (tau - f * h)
    c = M[_MDTJ, l] * M[_MTC, l]
    w = 0.0 if abs(w) <= c else (w - c if w > 0.0 else w + c)
    return theta + M[_MDT, l] * w, w


def twists(theta: ArrayLike, L0: ArrayLike, r: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """The NumPy twin of `twist` and `ratio`, from their closed forms (T1)-(T2): contraction c
    (...) m and ratio h (...) m/rad, broadcast."""
    s = np.asarray(theta, dtype=float) * r
    p = np.sqrt(np.maximum(np.square(L0) - s * s, np.square(P_MIN * np.asarray(L0))))
    return L0 - p, s * r / p


def string_tensions(ln: ArrayLike, ldot: ArrayLike, theta: ArrayLike, omega: ArrayLike, rows: ArrayLike) -> np.ndarray:
    """The NumPy twin of `string_tension` at the motor angle theta rad (its c, h by `twists`; the
    stretch ln - LR + c as (T3) writes it), with the constants rows (len(MOTOR_ROWS), ...),
    broadcast."""
    K, LR, B, L0, r = np.asarray(rows, dtype=float)[:5]
    c, h = twists(theta, L0, r)
    f = K * (np.asarray(ln) - LR + c) + B * (np.asarray(ldot) + h * np.asarray(omega))
    return np.where(f <= 0.0, 0.0, f)
