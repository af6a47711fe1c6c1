"""Actions of the 24 cables one by one (issue 30: "as a configured option, of the 24 cables one
by one, as the prototype can"), on the statics: would 24 independent actuators extend the slope
limit beyond what actions of any set of the 12 pairs reach (`slope_multi`)?

The model is `sensitivity.Model` with 24 levers (one pressure per cable, `sensitivity.cable_law`)
beside 12 (one per pair): the rigid robot posed on the slope (`slope_limit.pose`), its grounded
model (`sensitivity.grounded`), gravity in its support frame. A slope is climbable by a lever
set if some action within max_pressure MPa puts the CoG projection over an edge of the face
with an uphill component while it stays `margin` m inside the other two up to then (the ray's
check, `sensitivity._ray`: the criterion of `edge_action`). The search for such an action, per
uphill edge (`uphill`):

- `sensitivity.edge_action` (least total pressure, sequential LP from p = 0; the action whose
  simulation gives `simulated_multi`);
- `reach_action`: the deepest crossing instead, a sequential LP (scipy linprog) minimising the
  linearised distance to the edge, in a trust region, each step accepted only if the statics
  bring the projection nearer the edge; a second search, as edge_action's least-total LP
  linearised at 0 picks the single steepest lever, which saturates (d is concave in each
  pressure) and may leave it stuck short of the edge;
- for cables, also the pair actions lifted (a pair pressure P is P on both its cables,
  `topology.cable_levels`; `sensitivity.cable_law` gives the same cable law to the bit): whatever a
  set of pairs does, the cables do, so the cable limit found is never below the pair limit.

Both searches are local: a slope where none finds an action may still have one (the limits are
lower bounds of the statics' own), and the statics leave out how the weight's pull on the
struts changes with p (`sensitivity`'s errors: on 20 deg the tipping scale up to 0.48 MPa
early). `limit` finds the steepest climbable slope per heading: a scan up from 0 deg in `step`
deg to the first slope where it fails (or where the robot no longer stands), then bisection.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..physics import frames
from ..physics import topology as topo
from ..physics.params import Params
from . import gravity as gv
from . import sensitivity as sv
from . import slope_limit as sl
from .lookup import Workspace

CRITERIA = ("pairs_least", "pairs", "cables")  # edge_action on pairs; + reach_action; cables (+ lifts)


def uphill(params: Params, face: int, nodes: np.ndarray, heading: float) -> list[int]:
    """The edges k (0..2) of `face` whose outward normal has an uphill component, for the robot
    posed `nodes` with uphill at `heading` deg in its support frame (as `slope_multi.action`)."""
    support = frames.in_support_frame(nodes, face)[1]
    u = np.array([np.cos(np.radians(heading)), np.sin(np.radians(heading))])
    return [k for k in range(3) if float(np.dot(sl.direction(support, face, topo.edge_nodes(face, k)), u)) > 0]


def reach_action(
    m: sv.Model, k: int, max_pressure: float, margin: float, iterations: int = 2 * sv.ITERATIONS
) -> sv.EdgeAction | None:
    """An action over edge k by the deepest crossing (module docstring), None if none is found:
    each programme minimises d_k linearised at p_lin subject to the other distances >= margin
    (linearised), 0 <= p <= max_pressure, in a box of half-width r about p_lin; its optimum p
    is checked along the ray p / max(p) (`sensitivity._ray`) and becomes p_lin if the statics
    put it nearer the edge with the others >= margin / 2, else r halves. Stops at the first
    action found."""
    from scipy.optimize import linprog

    others = [j for j in range(3) if j != k]
    p_lin, r = np.zeros(m.levers), max_pressure
    d_lin = m.d(p_lin[None])[0]
    if d_lin[k] <= 0 or d_lin.min() <= 0:
        return None
    for _ in range(iterations):
        d0, D = sv.sensitivity(m, p_lin)
        rows = -D[others]
        rhs = d0[others] - margin + rows @ p_lin
        box = np.stack([np.maximum(0.0, p_lin - r), np.minimum(max_pressure, p_lin + r)], axis=1)
        res = linprog(D[k], A_ub=rows, b_ub=rhs, bounds=box, method="highs")
        p = np.where(res.x > 1e-6 * max_pressure, res.x, 0.0) if res.status == 0 else np.zeros(1)
        if p.max() <= 0:
            r *= 0.5
            continue
        w = p / p.max()
        scale, inside = sv._ray(m, k, w, max_pressure)
        if np.isfinite(scale) and inside >= 0.5 * margin:
            e = topo.edge_nodes(m.face, k)
            return sv.EdgeAction(m.face, e, topo.neighbour(m.face, e), w, scale, scale * float(w.sum()), inside)
        d = m.d(p[None])[0]
        if d[k] < d_lin[k] and d[others].min() >= 0.5 * margin:
            p_lin, d_lin = p, d
            r = min(r, sv.TRUST * max_pressure)
        else:
            r *= 0.5
    return None


@dataclass(frozen=True)
class Verdict:
    """Whether the slope is climbable by each criterion of CRITERIA (None: not asked), whether
    the robot stands there, and the actions found (criterion -> EdgeAction)."""

    stands: bool
    ok: dict
    actions: dict


def verdict(
    params: Params,
    face: int,
    slope: float,
    heading: float,
    max_pressure: float,
    margin: float,
    need: tuple[str, ...] = CRITERIA,
) -> Verdict:
    """The criteria `need` (of CRITERIA) at this slope and heading, each searched only as far as
    needed: a pair action is a cable action, and pairs_least's action is one of pairs."""
    nodes = sl.pose(params, face, slope, heading)
    m12 = sv.grounded(params, face, nodes)
    d0 = m12.d(np.zeros((1, topo.N_PAIRS)))[0]
    if d0.min() <= 0:
        return Verdict(False, {c: False for c in need}, {})
    edges = uphill(params, face, nodes, heading)
    ok, acts = {}, {}

    def first(search, model) -> sv.EdgeAction | None:
        for k in edges:
            a = search(model, k, max_pressure, margin)
            if a is not None:
                return a
        return None

    a = first(sv.edge_action, m12)
    if a is not None:
        acts["pairs_least"] = a
    elif "pairs" in need or "cables" in need:
        a = first(reach_action, m12)
    if a is not None:
        acts["pairs"] = a
    if "cables" in need:
        if a is not None:
            acts["cables"] = sv.EdgeAction(
                a.face, a.edge, a.next_face, topo.cable_levels(a.weights), a.scale, 2 * a.total, a.inside
            )
        else:
            m24 = sv.grounded(params, face, nodes, topo.N_CABLES)
            c = first(sv.edge_action, m24) or first(reach_action, m24)
            if c is not None:
                acts["cables"] = c
    for c in need:
        ok[c] = c in acts
    return Verdict(True, ok, {c: acts[c] for c in need if c in acts})


def limit(
    params: Params,
    face: int,
    heading: float,
    max_pressure: float,
    margin: float,
    step: float = 2.0,
    iterations: int = 3,
    top: float | None = None,
) -> dict:
    """Per criterion of CRITERIA: (lo, hi, action) deg: the steepest slope found climbable
    (NaN: not even 0 deg), the least slope above it where it failed (scan in `step` deg up to
    `top`, default the friction angle, then `iterations` bisection steps), and the action found
    at lo (None at NaN); and "stand": (lo, hi, None) the same for the rigid robot standing (its
    CoG projection inside the face: the statics' stand limit, above which nothing climbs)."""
    top = sl.friction_angle(params) if top is None else float(top)
    cache: dict[float, Verdict] = {}

    def at(slope: float, c: str) -> Verdict:
        v = cache.get(slope)
        if v is None or c not in v.ok:  # the criteria up to c (CRITERIA's order: each needs the last)
            v = verdict(params, face, slope, heading, max_pressure, margin, CRITERIA[: CRITERIA.index(c) + 1])
            cache[slope] = v
        return v

    def ok(slope: float, c: str) -> bool:
        if c == "stand":
            v = cache.get(slope)
            return v.stands if v is not None else bool(stands(params, face, slope, heading))
        return at(slope, c).ok[c]

    keys = ("stand", *CRITERIA)
    lo = {c: np.nan for c in keys}
    hi = {c: top for c in keys}
    open_ = set(keys)
    for s in np.arange(0.0, top, step):
        if open_ - {"stand"}:
            at(float(s), max(open_ - {"stand"}, key=CRITERIA.index))
        for c in list(open_):
            if ok(float(s), c):
                lo[c] = float(s)
            else:
                hi[c] = float(s)
                open_.discard(c)
        if not open_:
            break
    for c in keys:
        a, b = lo[c], hi[c]
        if not np.isfinite(a):
            continue
        for _ in range(int(iterations)):
            mid = 0.5 * (a + b)
            a, b = (mid, b) if ok(mid, c) else (a, mid)
        lo[c], hi[c] = a, b
    act = {c: cache[lo[c]].actions.get(c) if c != "stand" and np.isfinite(lo[c]) else None for c in keys}
    return {c: (lo[c], hi[c], act[c]) for c in keys}


def stands(params: Params, face: int, slope: float, heading: float) -> bool:
    """Whether the rigid robot posed on `slope` deg at `heading` deg stands by the statics: its
    CoG projected along gravity inside its face (the grounded model at 0 MPa)."""
    m = sv.grounded(params, face, sl.pose(params, face, slope, heading))
    return bool(m.d(np.zeros((1, topo.N_PAIRS)))[0].min() > 0)


def simulated(
    look: Workspace,
    params: Params,
    face: int,
    headings: np.ndarray,
    lo: np.ndarray,
    hi: np.ndarray,
    setup: gv.GravitySetup,
    margin: float,
    iterations: int = 3,
    criterion: str = "pairs",
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The uphill limit by direct simulation with the statics' actions of `criterion` ("pairs":
    `edge_action`, else `reach_action`, on the 12 pairs; "cables": those lifted to their cables
    where the statics find one, else the same two searches on the 24 cables, `verdict`), as
    `slope_multi.multi_limits` does with edge_action's: bisection from lo (deg, (H,), a slope
    known to roll, e.g. simulated_multi) to hi (H,) (the stand limit's high end), each mid slope
    simulated with the action the statics find for the pose there (`slope_limit._sim_ok`, the
    ramp of `setup`, a `gravity.GravitySetup`; cable actions as (R, 24) weights). A NaN lo (no
    known roll) is tried at 0 deg first, and stays NaN if that fails. Returns the bracket (lo,
    hi) deg, (H,) each, and the weights (H, 12 or 24) of the action that rolled the robot at lo
    (0: none did, lo is the given one)."""
    if criterion not in CRITERIA[1:]:
        raise ValueError(f"criterion {criterion!r}: use one of {CRITERIA[1:]}")
    lo, hi, headings = np.array(lo, float), np.array(hi, float), np.asarray(headings, float)
    need = CRITERIA[: CRITERIA.index(criterion) + 1]
    weights = np.zeros((lo.size, topo.N_CABLES if criterion == "cables" else topo.N_PAIRS))

    def rolls(slopes: np.ndarray, js: np.ndarray) -> np.ndarray:
        acts = [
            verdict(params, face, m, headings[j], setup.max_pressure, margin, need).actions.get(criterion)
            for m, j in zip(slopes, js)
        ]
        good = np.zeros(js.size, bool)
        run = [i for i, a in enumerate(acts) if a is not None]
        if run:
            w = np.stack([acts[i].weights for i in run])
            good[run] = sl._sim_ok(look, params, 1, face, slopes[run], headings[js[run]], w, setup)[0]
            for i, ok in zip(run, good[run]):
                weights[js[i]] = acts[i].weights if ok else weights[js[i]]
        return good

    nan = np.flatnonzero(np.isnan(lo) & np.isfinite(hi))
    if nan.size:
        lo[nan] = np.where(rolls(np.zeros(nan.size), nan), 0.0, np.nan)
    js = np.flatnonzero(np.isfinite(lo) & (lo < hi))
    for _ in range(int(iterations) if js.size else 0):
        mid = 0.5 * (lo[js] + hi[js])
        good = rolls(mid, js)
        lo[js], hi[js] = np.where(good, mid, lo[js]), np.where(good, hi[js], mid)
    return lo, hi, weights
