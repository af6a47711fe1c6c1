"""The free-mode workspace by statics: the equilibrium of every design, pair and level at once
(`physics.equilibrium`, batched Newton), the CoG and support triangle in each contact face's
frame, the margin, and the tipping pressure of each (design, contact, pair) by root-finding on
the margin as a function of pressure (Illinois regula falsi between the last level inside and
the first level outside; no interpolation). The path the dynamic study averages (paper III.A)
converges to these equilibria as its oscillation dies out: the same free mode, no gravity.

Errors: the equilibria are converged to Newton steps below `TOL` (1e-8 m, rad; the error left
is ~1e-15 m, `physics.equilibrium`); the tipping pressures to |margin| < MARGIN_TOL (1e-10 m) or a bracket narrower than
PRESSURE_TOL (1e-7 MPa).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..physics import actuator, frames
from ..physics import equilibrium as eq
from ..physics import topology as topo
from ..physics.params import Params

TOL = 1e-8  # m and rad: Newton's last step
MARGIN_TOL, PRESSURE_TOL = 1e-10, 1e-7  # m, MPa: the tipping pressure's root
MAX_ROOT_STEPS = 60


@dataclass(frozen=True)
class StaticWorkspace:
    """Free-mode equilibria of D designs, C contact faces, P pairs, L levels: faces (C,) 1..20,
    pairs (P,) 1-based, levels (L,) MPa; cog (D, C, P, L, 3) m and support (D, C, P, L, 3, 3) m in
    the support frame of the face, margin (D, C, P, L) m (positive inside); tip_pressure
    (D, C, P) MPa (root of the margin; NaN: inside at every level) and tip_edge (D, C, P, 2) the
    nodes of the edge crossed at the first level outside (0: none)."""

    faces: np.ndarray
    pairs: np.ndarray
    levels: np.ndarray
    cog: np.ndarray
    support: np.ndarray
    margin: np.ndarray
    tip_pressure: np.ndarray
    tip_edge: np.ndarray


def _field(designs: Sequence[Params], name: str) -> np.ndarray:
    return np.array([float(getattr(p, name)) for p in designs])


def _laws(designs: Sequence[Params]) -> dict[str, np.ndarray]:
    """The per-design (D,) arrays the equilibrium needs; ValueError unless every a = 1."""
    a = _field(designs, "cable_exponent")
    if np.any(a != 1.0):
        raise ValueError(f"parameter cable_exponent: the statics path needs 1.0, got {sorted(set(a.tolist()))}")
    names = ("strut_length", "cable_stiffness", "cable_rest_length", "muscle_min_length", "muscle_gain")
    return {n: _field(designs, n) for n in names}


def cable_law(law: dict[str, np.ndarray], index: np.ndarray, pressure: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """k (B, 24) N/m and l* (B, 24) m (`actuator.spring`, (S1)) of the designs `index` (B,)
    under pair pressures (B, 12) MPa."""
    act = actuator.activations(law["muscle_gain"][index, None], pressure)
    return actuator.spring(
        law["cable_stiffness"][index, None],
        law["cable_rest_length"][index, None],
        law["muscle_min_length"][index, None],
        act,
    )


def _solve(law, index, pressure, X, C):
    """Equilibria from (X, C) (B, 6, 3); RuntimeError naming a robot that does not converge."""
    k, ls = cable_law(law, index, pressure)
    X, C, it = eq.solve(X, C, law["strut_length"][index], k, ls, TOL)
    if np.any(it < 0):
        b = int(np.flatnonzero(it < 0)[0])
        raise RuntimeError(
            f"static equilibrium did not converge for design {int(index[b])} at pressures {pressure[b].tolist()} MPa"
        )
    return X, C


def _pressures(pairs: np.ndarray, level: np.ndarray) -> np.ndarray:
    """Pair pressures (B, 12) MPa: `level` (B,) on the 0-based pair `pairs` (B,), 0 elsewhere."""
    out = np.zeros((pairs.size, topo.N_PAIRS))
    out[np.arange(pairs.size), pairs] = level
    return out


def free_workspace(
    designs: Sequence[Params], faces: Sequence[int], pairs: Sequence[int], levels: Sequence[float]
) -> StaticWorkspace:
    """The static free-mode workspace (module docstring) of `designs` on `faces` (1..20), each
    1-based pair of `pairs` driven alone through `levels` (L,) MPa (strictly increasing, > 0).
    Every level starts from the previous one's equilibrium extrapolated linearly in pressure."""
    law = _laws(designs)
    faces = np.array([topo.face_number(f) for f in faces])
    pairs = np.array([topo.check_pair(p) for p in pairs])
    levels = np.asarray(levels, float)
    D, C, P, L = len(designs), faces.size, pairs.size, levels.size
    index, col = np.repeat(np.arange(D), P), np.tile(pairs - 1, D)
    ref = topo.reference_nodes(1.0)[None] * law["strut_length"][index, None, None]
    X0, C0 = eq.struts(ref)
    X, Cx, prev, p_prev = X0, C0, (X0, C0), 0.0
    cog, sup, mar = np.empty((D, C, P, L, 3)), np.empty((D, C, P, L, 3, 3)), np.empty((D, C, P, L))
    states = []
    for k, lev in enumerate(levels):
        w = (lev - p_prev) / (p_prev - (levels[k - 2] if k >= 2 else 0.0)) if k >= 1 else 0.0
        Xs, Cs = X + w * (X - prev[0]), Cx + w * (Cx - prev[1])
        prev = (X, Cx)
        X, Cx = _solve(law, index, _pressures(col, np.full(D * P, lev)), Xs, Cs)
        p_prev = lev
        states.append((X, Cx))
        nodes = eq.nodes(X, Cx, law["strut_length"][index]).reshape(D, P, topo.N_NODES, 3)
        for c, f in enumerate(faces):
            cog[:, c, :, k], sup[:, c, :, k] = frames.in_support_frame(nodes, int(f))
    mar[:] = frames.margin_2d(cog[..., :2], sup[..., :2])
    tip, edge = _tips(law, index, col, faces, levels, states, cog, sup, mar)
    return StaticWorkspace(faces, pairs, levels, cog, sup, mar, tip, edge)


def _tips(law, index, col, faces, levels, states, cog, sup, mar):
    """Tipping pressures (D, C, P) MPa and edges (D, C, P, 2) (`free_workspace`)."""
    D, C, P, L = mar.shape
    tip, edge = np.full((D, C, P), np.nan), np.zeros((D, C, P, 2), np.int64)
    out = mar < 0
    hit = np.argwhere(out.any(axis=-1))  # (d, c, j) of every path that leaves the triangle
    if not hit.size:
        return tip, edge
    d, c, j = hit.T
    k = np.argmax(out[d, c, j], axis=-1)  # first level outside
    for n in range(hit.shape[0]):
        e = frames.crossed_edge(cog[d[n], c[n], j[n], k[n], :2], sup[d[n], c[n], j[n], k[n], :, :2])
        edge[d[n], c[n], j[n]] = topo.edge_nodes(int(faces[c[n]]), e) if e is not None else (0, 0)
    b = d * P + j  # the robot of the staircase
    Xs = np.stack([s[0] for s in states], axis=1)[b, np.maximum(k - 1, 0)]
    Cs = np.stack([s[1] for s in states], axis=1)[b, np.maximum(k - 1, 0)]
    rest = topo.reference_nodes(1.0)[None] * law["strut_length"][index[b], None, None]
    r0 = eq.struts(rest)
    Xs = np.where((k == 0)[:, None, None], r0[0], Xs)
    Cs = np.where((k == 0)[:, None, None], r0[1], Cs)
    pa = np.where(k > 0, levels[np.maximum(k - 1, 0)], 0.0)
    ma = np.where(k > 0, mar[d, c, j, np.maximum(k - 1, 0)], _margin(rest, faces[c]))
    pb, mb = levels[k], mar[d, c, j, k]
    tip[d, c, j] = root(law, index[b], col[b], faces[c], (pa, ma), (pb, mb), (Xs, Cs))
    return tip, edge


def _margin(nodes: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Margin (B,) m of nodes (B, 12, 3) m on faces (B,) (1..20)."""
    out = np.empty(faces.size)
    for f in np.unique(faces):
        sel = faces == f
        cog, sup = frames.in_support_frame(nodes[sel], int(f))
        out[sel] = frames.margin_2d(cog[..., :2], sup[..., :2])
    return out


def root(
    law: dict[str, np.ndarray],
    index: np.ndarray,
    pair: np.ndarray,
    faces: np.ndarray,
    inside: tuple[np.ndarray, np.ndarray],
    outside: tuple[np.ndarray, np.ndarray],
    start: tuple[np.ndarray, np.ndarray],
) -> np.ndarray:
    """The pressure (B,) MPa on the 0-based `pair` (B,) of designs `index` (B,) at which the
    margin on `faces` (B,) crosses zero, between inside = (pressure, margin > 0) and outside =
    (pressure, margin < 0), each (B,): Illinois regula falsi, every step one batched
    equilibrium from the last one (start: centres, axes (B, 6, 3) at the inside end)."""
    (pa, ma), (pb, mb) = (np.array(v, float) for v in inside), (np.array(v, float) for v in outside)
    X, C = start
    p = pa.copy()
    side = np.zeros(pa.size, np.int8)  # the end replaced last: +1 inside, -1 outside
    todo = np.arange(pa.size)
    for _ in range(MAX_ROOT_STEPS):
        if not todo.size:
            break
        t = todo
        p[t] = pb[t] - mb[t] * (pb[t] - pa[t]) / (mb[t] - ma[t])
        X[t], C[t] = _solve(law, index[t], _pressures(pair[t], p[t]), X[t], C[t])
        m = _margin(eq.nodes(X[t], C[t], law["strut_length"][index[t]]), faces[t])
        ins = m > 0
        # Illinois: halve the other end's margin when the same end is replaced twice running
        mb[t] = np.where(ins & (side[t] == 1), 0.5 * mb[t], mb[t])
        ma[t] = np.where(~ins & (side[t] == -1), 0.5 * ma[t], ma[t])
        pa[t], ma[t] = np.where(ins, p[t], pa[t]), np.where(ins, m, ma[t])
        pb[t], mb[t] = np.where(ins, pb[t], p[t]), np.where(ins, mb[t], m)
        side[t] = np.where(ins, 1, -1)
        done = (np.abs(m) < MARGIN_TOL) | (pb[t] - pa[t] < PRESSURE_TOL)
        todo = t[~done]
    if todo.size:
        raise RuntimeError(
            f"tipping pressure root not found in {MAX_ROOT_STEPS} steps for design {int(index[todo[0]])}"
        )
    return p
