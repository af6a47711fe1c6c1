"""Actions of any set of pairs, by optimisation (issue 30, item 1): the CoG projection's
sensitivity to each pair's pressure, and the least actuation that moves it out over a chosen
edge of the support face while it stays inside the other two.

Model (`Model`): the free-mode static equilibrium (`physics.equilibrium`, batched Newton; no
gravity, no ground), its CoG moved along gravity onto the plane of its own deformed support face
(paper Fig. 10, `slopes.gravity_frame`), gravity given in the support frame. That frame is the
robot's current one: the face stays on the ground until a node lifts, so gravity keeps its
direction in the face's frame. For a grounded robot (`grounded`) the distances are shifted by
the difference, at rest, between its own and the free model's (its sag under its weight), taken
as constant in p. The distances d (3,) m of that projection to the three edge lines (positive
inside, edge k joins corners k and k+1 of `topology.FACES`, `frames.edge_distances`) are
linearised in the pair pressures p (12,) MPa, D = dd/dp (3, 12) m/MPa by forward differences of
`STEP` MPa, and a linear programme (scipy `linprog`, HiGHS) finds the least total pressure
sum(p) with d_k(p) <= 0 on the chosen edge k and d_j(p) >= margin on the others, 0 <= p <=
max_pressure. Its answer gives the direction w = p / max(p); the roll ramps s w, and the
statics along that ray give the crossing scale s and check that the other edges stay inside up
to it (`_ray`). The programme is then linearised again where the best ray crossed, in a trust
region (sequential LP, `edge_action`); the least total found is kept: a local optimum (the
responses saturate, d is concave in each pressure, so mixing pairs beats a single pair: on flat
ground two pairs at 1 : 0.46 cross at 2.2 MPa, one pair alone at 4.1-4.2 MPa).

Errors: the linearisation only proposes directions; the scale and the inside check come from the
statics themselves (interpolation error below ~0.01 MPa, `_ray`). Against the grounded simulator
(`control.roll`, `benchmarks/bench_actuation.py`, face (9,10,12), up to 5 MPa): on flat ground
the predicted scale 2.21 MPa against the simulated tip 2.22 MPa on all 12 pose-edges, median
error 0.01 MPa; on 20 deg up to 0.48 MPa early (3.18 predicted, 2.70 simulated: the free model
leaves out how the weight's pull on the struts changes with p). An action that the model
rejects may still roll the robot, and one it accepts is checked by simulation where it matters
(the slope limit, `slope_multi`; the planner's rolls).

Levers (`Model.levers`): the actuation vector p is one pressure per pair (12, the robot's
muscles; every caller's default) or one per cable (24, topology.CABLES order: the prototype's
24 independent actuators, issue 30), each cable then with its own muscle, eq. 1 with its own P
(`cable_law`). With 24 levers everything above holds with 24 for 12 (`cable_actions`); a pair
pressure P is the cable pressures P on both its cables (topology.CABLE_PAIR).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..physics import actuator, equilibrium, frames, statics
from ..physics import contact as ct
from ..physics import topology as topo
from ..physics.params import Params
from ..physics.schedule import check_pressures

STEP = 0.25  # MPa, forward-difference step of the sensitivity
RAY = 8  # samples of the ray s w checked by the statics, twice (`_ray`)
ITERATIONS = 5  # linear programmes per edge (sequential LP); the least total is kept
TRUST = 0.25  # after the first programme, the box trust region's half-width / max_pressure


@dataclass(frozen=True)
class ActuationSettings:
    """actuation_margin m: an optimised action keeps the CoG projection at least this far
    inside the two edges it does not roll over, at the pressure it crosses the third (config
    `locomotion.actuation_margin`)."""

    actuation_margin: float = 0.005

    def __post_init__(self):
        if not (np.isfinite(self.actuation_margin) and 0 <= self.actuation_margin < 0.1):
            raise ValueError(f"locomotion.actuation_margin {self.actuation_margin!r} m must be in [0, 0.1)")


@dataclass(frozen=True)
class EdgeAction:
    """An action that rolls the robot over `edge` (two 1-based nodes) of `face` onto `next_face`:
    weights (levers,) (largest 1; the roll ramps pressures s w), scale MPa: the least s at which the
    statics put the CoG projection over the edge (linearly interpolated between RAY samples),
    total MPa: sum of the pressures there; inside m: the least distance to the other two edges
    along the ray up to it."""

    face: int
    edge: tuple[int, int]
    next_face: int
    weights: np.ndarray
    scale: float
    total: float
    inside: float


def cable_law(params: Params, pressure: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per-cable stiffness (24,) N/m and slack length (24,) m under pair pressures (12,) MPa
    (`statics.cable_law`) or cable pressures (24,) MPa: the same law, each cable with its own
    pressure (the cable pressures P[CABLE_PAIR] give the pair law's arrays exactly)."""
    p = np.asarray(pressure, float)
    if p.shape != (topo.N_CABLES,):
        return statics.cable_law(params, p)
    statics.cable_law(params, np.zeros(topo.N_PAIRS))  # its checks: scalar parameters, a = 1
    names = ("cable_stiffness", "cable_rest_length", "muscle_min_length", "muscle_gain")
    K, L, Lmin, Kg = (float(getattr(params, n)) for n in names)
    return actuator.spring(K, L, Lmin, Kg * check_pressures(p))


def shapes(params: Params, pressures: np.ndarray) -> np.ndarray:
    """Free-mode equilibria (N, 12, 3) m under pair pressures (N, 12) or cable pressures (N, 24)
    MPa (`cable_law`), from the symmetric reference state (`equilibrium.solve`). RuntimeError if
    a solve does not converge."""
    p = np.atleast_2d(np.asarray(pressures, float))
    S = float(params.strut_length)
    laws = [cable_law(params, row) for row in p]
    ref = topo.reference_nodes(S)
    x0, c0 = equilibrium.struts(ref)
    N = p.shape[0]
    X, C, iters = equilibrium.solve(
        np.broadcast_to(x0, (N, 6, 3)),
        np.broadcast_to(c0, (N, 6, 3)),
        np.full(N, S),
        np.stack([k for k, _ in laws]),
        np.stack([ls for _, ls in laws]),
    )
    if np.any(iters < 0):
        raise RuntimeError(f"free equilibrium did not converge at pressures {p[iters < 0][0].tolist()} MPa")
    return equilibrium.nodes(X, C, np.full(N, S))


def distances(nodes: np.ndarray, face: int, gravity: np.ndarray) -> np.ndarray:
    """Distances (..., 3) m of the CoG of `nodes` (..., 12, 3) m, moved along `gravity` (3,) (in
    the support frame of `face`) onto the face's plane, to its three edge lines; positive inside."""
    cog, support = frames.in_support_frame(nodes, face)
    proj = ct.project_along_gravity(cog, np.zeros(3), np.eye(3)[2], gravity)[..., :2]
    return frames.edge_distances(proj, support[..., :2])


@dataclass(frozen=True)
class Model:
    """The robot on `face` (1..20) with `gravity` (3,) in its support frame (the current
    robot's; module docstring): the edge distances under pair pressures p are those of the free
    model plus `offset` (3,) m, the grounded robot's distances at rest minus the free model's
    (its sag under its weight and the ground's reaction, taken as not changing with p: the error
    of the free workspace, module docstring). offset 0: the free model alone. levers: 12 (p per
    pair) or 24 (p per cable)."""

    params: Params
    face: int
    gravity: np.ndarray
    offset: np.ndarray | float = 0.0
    levers: int = topo.N_PAIRS

    def __post_init__(self):
        if self.levers not in (topo.N_PAIRS, topo.N_CABLES):
            raise ValueError(f"levers {self.levers!r}: {topo.N_PAIRS} (pairs) or {topo.N_CABLES} (cables)")

    def d(self, pressures: np.ndarray) -> np.ndarray:
        """Edge distances (N, 3) m under pressures (N, levers) MPa."""
        return distances(shapes(self.params, pressures), self.face, self.gravity) + self.offset


def grounded(params: Params, face: int, nodes: np.ndarray, levers: int = topo.N_PAIRS) -> Model:
    """The `Model` of a robot at rest with nodes (12, 3) m (world) on `face`: gravity and the
    offset from those nodes; `levers` 12 (pairs) or 24 (cables)."""
    nodes = ct.check_nodes(nodes)
    origin, rot = frames.face_frame(nodes, face)
    g = rot @ ct.GRAVITY_DIR
    free = Model(params, face, g, levers=levers)
    here = distances(nodes, face, g)
    return Model(params, face, g, here - free.d(np.zeros((1, levers)))[0], levers)


def sensitivity(m: Model, base: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Edge distances d (3,) m at pressures `base` (levers,) MPa and their Jacobian D (3, levers)
    m/MPa (forward differences of STEP MPa; backward where base + STEP passes 10 MPa)."""
    base = np.asarray(base, float)
    h = np.where(base + STEP <= 10.0, STEP, -STEP)
    d = m.d(np.vstack([base, base + np.diag(h)]))
    return d[0], ((d[1:] - d[0]) / h[:, None]).T


def _ray(m: Model, k: int, w: np.ndarray, top: float) -> tuple[float, float]:
    """Along s w for s up to `top` MPa: the least s at which the projection crosses edge k (MPa,
    NaN: none), from RAY samples and RAY more between the two around the crossing (linear
    interpolation between those: error below a tenth of top / RAY^2 on these concave paths), and
    the least distance to the other edges up to it (m)."""
    s, d = np.zeros(1), m.d(np.zeros((1, m.levers)))
    for _ in range(2):
        n = int(np.argmax(d[:, k] < 0)) if np.any(d[:, k] < 0) else s.size
        lo = s[n - 1] if n < s.size else s[-1]
        hi = s[n] if n < s.size else top
        if lo >= top:
            break
        new = lo + (hi - lo) * np.arange(1, RAY + 1) / RAY
        s = np.concatenate([s[:n], new, s[n:]])
        d = np.concatenate([d[:n], m.d(new[:, None] * w), d[n:]])
    scale, n = frames.first_crossing(s, d[:, k])
    if n < 0:
        return float("nan"), float("nan")
    return scale, float(np.delete(d[: n + 1], k, axis=1).min())  # up to the first sample past it


def edge_action(m: Model, k: int, max_pressure: float, margin: float) -> EdgeAction | None:
    """The least-total-pressure action over edge k (0..2, corners k and k+1 of FACES) of the
    model's face, pressures up to max_pressure MPa, the projection kept `margin` m inside the
    other edges (module docstring); None if none is found. Each linear programme gives the
    direction w, the statics along the ray give the scale; the next programme is linearised
    where the best ray so far crossed (before one has: where the first ray crossed, or its
    end), within a box trust region of half-width TRUST max_pressure MPa, halved after each
    programme that finds nothing better."""
    p_lin, best, r = np.zeros(m.levers), None, max_pressure
    others = [j for j in range(3) if j != k]
    from scipy.optimize import linprog  # import cost only where an action is optimised

    for i in range(ITERATIONS):
        d0, D = sensitivity(m, p_lin)
        if i == 0 and (d0[k] <= 0 or d0.min() <= 0):
            return None  # not standing, or already past the edge: nothing to roll
        rows = np.vstack([D[k], -D[others]])
        rhs = np.concatenate([[-d0[k]], d0[others] - margin]) + rows @ p_lin
        box = np.stack([np.maximum(0.0, p_lin - r), np.minimum(max_pressure, p_lin + r)], axis=1)
        res = linprog(np.ones(m.levers), A_ub=rows, b_ub=rhs, bounds=box, method="highs")
        p = np.where(res.x > 1e-6 * max_pressure, res.x, 0.0) if res.status == 0 else np.zeros(1)
        r = min(r, TRUST * max_pressure)
        if p.max() <= 0:
            r *= 0.5
            continue
        w = p / p.max()
        scale, inside = _ray(m, k, w, max_pressure)
        ok = np.isfinite(scale) and inside >= 0.5 * margin
        if ok and (best is None or scale * w.sum() < best.total - 1e-9):
            e = topo.edge_nodes(m.face, k)
            best = EdgeAction(m.face, e, topo.neighbour(m.face, e), w, scale, scale * float(w.sum()), inside)
        elif i > 0:
            r *= 0.5  # no better: trust the linear model over a smaller box
        if best is not None:
            p_lin = best.scale * best.weights
        elif i == 0:
            p_lin = (scale if np.isfinite(scale) else max_pressure) * w
    return best


def edge_actions(m: Model, max_pressure: float, settings: ActuationSettings) -> list[EdgeAction]:
    """`edge_action` for each edge of the model's face that one is found for, in edge order."""
    out = [edge_action(m, k, max_pressure, settings.actuation_margin) for k in range(3)]
    return [a for a in out if a is not None]
