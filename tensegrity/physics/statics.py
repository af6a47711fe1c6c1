"""Static equilibrium by energy minimisation: the independent check of the dynamic simulator.

Free mode (no gravity, no ground; docs/design.md §3, paper III.A-B). The six struts are rigid
bodies, each given by its centre x (3,) m and an unnormalised direction d (3,), c = d / |d|, with
nodes x + (S/2) c and x - (S/2) c (eq. 4). The energy is the sum over the 24 cables of the integral
of the clamped tension of eq. 2 with the muscle of eq. 1 at zero velocity. For cable_exponent
a = 1 it is U = 0.5 (K + Kg P) max(0, l - l*)^2 with l* = (K L + Kg P Lmin) / (K + Kg P)
(`actuator.spring`, the NumPy form of the law). This module never calls `kernel` or
`dynamics.simulate`.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from . import actuator, frames
from . import topology as topo
from .params import Params
from .schedule import check_pressures

_NODE_STRUT, _NODE_SIGN = topo.NODE_STRUT, topo.NODE_SIGN  # node = centre + sign (S/2) c


def _scalar(params: Params, name: str) -> float:
    v = np.asarray(getattr(params, name), dtype=float)
    if v.ndim:
        raise ValueError(f"statics needs scalar parameters; {name} is an array of shape {v.shape}")
    return float(v)


def cable_law(params: Params, pressure: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Per-cable stiffness k = K + Kg P (24,) N/m and slack length l* (24,) m (a = 1), for pair
    pressures (12,) MPa: the tension is k max(0, l - l*), eq. 2 with eq. 1 at zero velocity
    (S1, `actuator.spring`)."""
    if _scalar(params, "cable_exponent") != 1.0:
        raise NotImplementedError("statics is implemented for cable_exponent = 1 only")
    p = check_pressures(pressure)
    if p.shape != (topo.N_PAIRS,):
        raise ValueError(f"pressure must have shape ({topo.N_PAIRS},) MPa, got {p.shape}")
    K, L = _scalar(params, "cable_stiffness"), _scalar(params, "cable_rest_length")
    Lmin, Kg = _scalar(params, "muscle_min_length"), _scalar(params, "muscle_gain")
    return actuator.spring(K, L, Lmin, actuator.activations(Kg, p))


def strut_nodes(centres: np.ndarray, directions: np.ndarray, strut_length: float) -> np.ndarray:
    """Node positions (12, 3) m from strut centres (6, 3) m and (unnormalised) directions (6, 3)."""
    c = directions / np.linalg.norm(directions, axis=1, keepdims=True)
    return centres[_NODE_STRUT] + (0.5 * strut_length * _NODE_SIGN)[:, None] * c[_NODE_STRUT]


def cable_energy(
    centres: np.ndarray, directions: np.ndarray, strut_length: float, k: np.ndarray, lstar: np.ndarray
) -> tuple[float, np.ndarray, np.ndarray]:
    """Cable energy U (J) and its gradients dU/d centres (6, 3) N and dU/d directions (6, 3) N m
    (per unit of the unnormalised direction), for the cable law (k, l*) of `cable_law`."""
    nd = np.linalg.norm(directions, axis=1, keepdims=True)
    c = directions / nd
    h = 0.5 * strut_length
    p = centres[_NODE_STRUT] + (h * _NODE_SIGN)[:, None] * c[_NODE_STRUT]
    e = p[topo.CABLES[:, 1]] - p[topo.CABLES[:, 0]]
    ln = np.linalg.norm(e, axis=1)
    stretch = np.maximum(0.0, ln - lstar)
    U = 0.5 * float(np.sum(k * stretch**2))
    f = (k * stretch / ln)[:, None] * e  # dU/d p2 = -dU/d p1 = tension * unit vector
    gp = np.zeros((topo.N_NODES, 3))
    np.add.at(gp, topo.CABLES[:, 1], f)
    np.add.at(gp, topo.CABLES[:, 0], -f)
    gx = gp[topo.STRUTS[:, 0]] + gp[topo.STRUTS[:, 1]]
    gc = h * (gp[topo.STRUTS[:, 0]] - gp[topo.STRUTS[:, 1]])
    gd = (gc - np.sum(gc * c, axis=1, keepdims=True) * c) / nd  # (I - c c^T) / |d|
    return U, gx, gd


def _solve(params: Params, pressure, start: np.ndarray) -> np.ndarray:
    """Minimise the cable energy from node positions `start` (12, 3) m; returns nodes (12, 3) m."""
    S = _scalar(params, "strut_length")
    k, lstar = cable_law(params, pressure)
    # Non-dimensional unknowns (centres / S, directions) and energy / (K S^2) keep the
    # Hessian O(1) for both translations and rotations.
    scale = _scalar(params, "cable_stiffness") * S**2
    a, b = start[topo.STRUTS[:, 0]], start[topo.STRUTS[:, 1]]
    z0 = np.concatenate([(0.5 * (a + b) / S).ravel(), ((a - b) / S).ravel()])

    def fun(z):
        U, gx, gd = cable_energy(S * z[:18].reshape(6, 3), z[18:].reshape(6, 3), S, k, lstar)
        return U / scale, np.concatenate([S * gx.ravel(), gd.ravel()]) / scale

    from scipy.optimize import minimize  # 0.7 s to import: only where an equilibrium is solved

    res = minimize(fun, z0, jac=True, method="BFGS", options={"gtol": 1e-11, "maxiter": 5000})
    z = res.x
    # Newton polish with a central-difference Hessian of the analytic gradient; lstsq drops the
    # 6 rigid-motion and 6 direction-scale null directions (eigenvalues ~1e-11, against >= 0.2
    # for the physical modes at the default parameters). Converges to round-off.
    for _ in range(4):
        z[18:] = (z[18:].reshape(6, 3) / np.linalg.norm(z[18:].reshape(6, 3), axis=1, keepdims=True)).ravel()
        grad = fun(z)[1]
        if np.max(np.abs(grad)) < 1e-14:
            break
        H = np.empty((z.size, z.size))
        eps = 1e-6
        for i in range(z.size):
            dz = np.zeros_like(z)
            dz[i] = eps
            H[:, i] = (fun(z + dz)[1] - fun(z - dz)[1]) / (2 * eps)
        H = 0.5 * (H + H.T)
        step = np.linalg.lstsq(H, -grad, rcond=1e-6)[0]
        if fun(z + step)[0] > fun(z)[0] + 1e-15:
            break
        z = z + step
    nodes = strut_nodes(S * z[:18].reshape(6, 3), z[18:].reshape(6, 3), S)
    if not np.all(np.isfinite(nodes)):
        raise RuntimeError("static equilibrium solve produced non-finite node positions")
    return nodes


def _align(nodes: np.ndarray, ref: np.ndarray) -> np.ndarray:
    """Remove the rigid-motion gauge: centroid at the origin, best-fit rotation onto ref."""
    p = nodes - nodes.mean(axis=0)
    u, _, vt = np.linalg.svd(p.T @ (ref - ref.mean(axis=0)))
    r = u @ np.diag([1.0, 1.0, np.sign(np.linalg.det(u @ vt))]) @ vt
    return p @ r


def equilibrium(params: Params, pressure: ArrayLike, start: np.ndarray | None = None) -> np.ndarray:
    """Node positions (12, 3) m of the free-mode static equilibrium under pair pressures (12,) MPa,
    starting from `start` (12, 3) m (default: the symmetric reference state). The rigid-motion
    gauge is fixed by putting the centroid at the origin with the best-fit rotation onto the
    reference nodes."""
    p = check_pressures(pressure)
    if p.shape != (topo.N_PAIRS,):
        raise ValueError(f"pressure must have shape ({topo.N_PAIRS},) MPa, got {p.shape}")
    ref = topo.reference_nodes(_scalar(params, "strut_length"))
    start = ref if start is None else np.asarray(start, dtype=float)
    return _align(_solve(params, p, start), ref)


def support_cog(nodes: np.ndarray, face: int | Sequence[int]) -> tuple[np.ndarray, np.ndarray]:
    """CoG (mean of the 12 nodes = mean of the strut centres) (3,) m and the face's corners
    (3, 3) m, both in the supporting-triangle frame of `face` (1..20 or three node numbers),
    docs/design.md §2. Corners are in the order of topology.FACES. The same as
    `frames.in_support_frame`, which new code calls."""
    return frames.in_support_frame(nodes, face)


def static_workspace(
    params: Params, face: int | Sequence[int], pair: int, pressures: ArrayLike
) -> tuple[np.ndarray, np.ndarray]:
    """Static CoG (n, 3) m in the support frame of `face` and margin (n,) m (frames.margin_2d
    of its in-plane coordinates against the deformed triangle, positive inside) for pressures
    (n,) MPa applied to the 1-based `pair` alone. Each level starts from the previous solution."""
    pair = topo.check_pair(pair)
    levels = np.atleast_1d(check_pressures(pressures, "pressures"))
    cogs, margins = np.empty((levels.size, 3)), np.empty(levels.size)
    nodes = None
    for i, lev in enumerate(levels):
        p = np.zeros(topo.N_PAIRS)
        p[pair - 1] = lev
        nodes = equilibrium(params, p, start=nodes)
        cogs[i], tri = frames.in_support_frame(nodes, face)
        margins[i] = frames.margin_2d(cogs[i, :2], tri[:, :2])
    return cogs, margins
