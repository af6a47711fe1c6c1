"""The slope limit (issue 10, item 4): for each contact case and heading, the steepest slope on
which the robot can stand, roll uphill, and roll downhill under control (it tips over an edge
with a downhill component and then stands, or is held by a pair, on the landing face).

Each limit is predicted from the free workspace projected along gravity (`lookup.predict` on
the rigid robot posed on a plane of that slope), read off the gravity-aware workspace's slope
grid (`gravity.GravitySweep`), and checked by direct simulation: bisection between the last grid
slope that works and the next one (or the friction angle, beyond which the robot slides).
Headings are the uphill direction in the face's support frame, deg (see `gravity`). `look` is
the free workspace (`lookup.Workspace`; with measured two-pair curves, their combinations are
tried too: `Workspace.actions`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ..physics import contact as ct
from ..physics import dynamics as d
from ..physics import frames
from ..physics import topology as topo
from ..physics.params import Params
from ..physics.terrain import Terrain
from ..physics.twisted import TwistedString
from . import gravity as gv
from .lookup import Workspace, predict
from .slopes import heading_of, place, slope_field, stands

KINDS = ("stand", "uphill", "downhill")


@dataclass(frozen=True)
class SlopeLimits:
    """Slopes in deg, shape (3, C, H) for KINDS x contacts x headings: predicted_free,
    predicted_gravity, simulated (NaN: not even on flat ground) and simulated_high: the
    bisection's bracket, the steepest slope that worked and the least that did not (or the next
    grid slope, or the friction angle, if none failed), the limit between them; pair (0: none)
    and pressure MPa of the roll at the simulated limit; limited_by: 'geometry', 'landing',
    'pressure range' or 'friction'."""

    kinds: tuple
    contacts: tuple
    headings: np.ndarray
    predicted_free: np.ndarray
    predicted_gravity: np.ndarray
    simulated: np.ndarray
    pair: np.ndarray
    pressure: np.ndarray
    limited_by: np.ndarray
    simulated_high: np.ndarray


def friction_angle(params: Params) -> float:
    """Slope (deg) beyond which a robot standing on a face slides: atan(mu)."""
    return float(np.degrees(np.arctan(float(params.friction))))


def direction(support: np.ndarray, face: int, edge: Sequence[int]) -> np.ndarray:
    """Outward unit normal (2,) in the support plane of `edge` (two 1-based nodes) of `face`,
    for the triangle `support` (3, >=2) m in its support frame (corner order of FACES):
    `contact.edge_outward`."""
    k = [topo.edge_nodes(face, i) for i in range(3)].index(tuple(sorted(int(n) for n in edge)))
    tri = np.zeros((3, 3))
    tri[:, :2] = support[:, :2]
    return ct.edge_outward(tri)[k, :2]


def pose(params: Params, face: int, slope: float, heading: float) -> np.ndarray:
    """Nodes (12, 3) m of the unactuated symmetric robot on `face` on a plane of `slope` deg
    rising toward +x, uphill at `heading` deg in the face's support frame."""
    s = place(params, face, Terrain.slope(slope), (0.0, 0.0), heading)
    return d.nodes(s.x, s.q, params.strut_length)[0]


def _free_ok(
    look: Workspace,
    params: Params,
    face: int,
    slope: float,
    heading: float,
    max_pressure: float,
    wanted: tuple[bool, bool] = (True, True),
) -> tuple[bool, bool, bool]:
    """(stand, uphill, downhill) possible at this slope and heading by the free workspace.
    wanted: whether uphill and downhill are asked for; one not asked for is reported False
    without its search (the landing check of a downhill roll)."""
    nodes = pose(params, face, slope, heading)
    acts = look.actions(face)
    pr = predict(look, face, nodes, acts)
    ok_p = pr.pressure <= max_pressure + 1e-9
    stand = bool(pr.margin[0, 0] > 0)
    if not stand:
        return False, False, False
    u = np.array([np.cos(np.radians(heading)), np.sin(np.radians(heading))])
    up = down = False
    for a in range(len(acts)):
        if (up or not wanted[0]) and (down or not wanted[1]):
            break  # nothing left to find
        # the first sample outside up to max_pressure (ok_p is a prefix: the pressures rise)
        _, k, e = frames.crossing(
            pr.pressure[ok_p], pr.margin[a, ok_p], pr.projection_2d[a, ok_p], pr.support[a, ok_p], face
        )
        if e is None:
            continue
        along = float(np.dot(direction(pr.support[a, k], face, e), u))
        up |= along > 0 and wanted[0]
        if along < 0 and wanted[1] and not down:
            down = _lands(look, face, nodes, e, max_pressure)
    return stand, up, down


def _lands(look: Workspace, face: int, nodes: np.ndarray, edge: Sequence[int], max_pressure: float) -> bool:
    """Whether the robot posed `nodes` on `face`, rolled rigidly over `edge`
    (`contact.roll_over`), stands on the landing face, or some pair holds it there (a positive
    margin at some pressure up to max_pressure), by the free workspace."""
    to, after = ct.roll_over(nodes, face, edge)
    pr = predict(look, to, after, look.actions(to))
    return bool(np.any(pr.margin[:, pr.pressure <= max_pressure + 1e-9] > 0))


def _last(ok: np.ndarray, slopes: np.ndarray) -> float:
    """Largest slope of the run of True from the first slope on (NaN: the first is False)."""
    bad = np.flatnonzero(~np.asarray(ok, bool))
    n = bad[0] if bad.size else len(ok)
    return float(slopes[n - 1]) if n else float("nan")


def predict_free(
    look: Workspace, params: Params, face: int, headings: np.ndarray, max_pressure: float, step: float = 1.0
) -> np.ndarray:
    """Limits (3, H) deg by the free workspace: slopes scanned every `step` deg up to the
    friction angle, or until each limit has failed once; NaN if the free workspace has no pair
    on `face` (a subset of the contacts)."""
    slopes = np.arange(0.0, friction_angle(params), step)
    out = np.full((3, len(headings)), np.nan)
    if not len(look.actions(face)):
        return out
    for j, h in enumerate(headings):
        ok = np.zeros((slopes.size, 3), bool)
        for i, a in enumerate(slopes):  # up the slopes while a limit is still open (`_last`)
            ok[i] = _free_ok(look, params, face, a, h, max_pressure, (ok[:i, 1].all(), ok[:i, 2].all()))
            if not ok[: i + 1].all(axis=0).any():
                break
        out[:, j] = [_last(ok[:, k], slopes) for k in range(3)]
    return out


def grid_ok(sw: gv.GravitySweep, look: Workspace, params: Params, max_pressure: float) -> tuple[np.ndarray, np.ndarray]:
    """(3, S, H) whether stand / uphill / downhill worked on the gravity-aware grid, and the
    pair (3, S, H) that rolled at the least pressure (0: none)."""
    S, H = sw.stood.shape
    ok, pair = np.zeros((3, S, H), bool), np.zeros((3, S, H), np.int64)
    ok[0] = sw.stood
    rest = frames.rest_frame(sw.face, float(params.strut_length))[1]
    for i in range(S):
        for j in range(H):
            if not sw.stood[i, j]:
                continue
            u = np.array([np.cos(np.radians(sw.headings[j])), np.sin(np.radians(sw.headings[j]))])
            nodes = None
            best = [np.inf, np.inf]
            for n in np.argsort(sw.tip_pressure[i, j]):
                p = sw.tip_pressure[i, j, n]
                if not (sw.rolled[i, j, n] and p <= max_pressure):
                    continue
                e = tuple(int(v) for v in sw.tip_edge[i, j, n])
                along = float(np.dot(direction(rest, sw.face, e), u))
                k = 1 if along > 0 else 2
                if along < 0:
                    nodes = pose(params, sw.face, sw.slopes[i], sw.headings[j]) if nodes is None else nodes
                    if not _lands(look, sw.face, nodes, e, max_pressure):
                        continue
                if p < best[k - 1]:
                    best[k - 1], ok[k, i, j], pair[k, i, j] = p, True, sw.pairs[n]
    return ok, pair


def _sim_ok(
    look: Workspace,
    params: Params,
    kind: int,
    face: int,
    slopes: np.ndarray,
    headings: np.ndarray,
    pairs: np.ndarray,
    setup: gv.GravitySetup,
    motors: TwistedString | None = None,
) -> tuple[np.ndarray, np.ndarray, list]:
    """Direct simulation of limit `kind` (1 uphill, 2 downhill; 0 stand) at slopes[j] and
    headings[j] with pairs[j]: (ok (J,), tip pressure (J,) MPa, or V with `motors`, failure
    reason per robot)."""
    J = len(slopes)
    if kind == 0:
        ok = stands(params, [face] * J, slopes, headings, setup.settle + 0.5, setup.dt, motors)
        return ok, np.full(J, np.nan), ["geometry"] * J
    terrain, centres = slope_field(slopes)
    state = d.State.concat([place(params, face, terrain, centres[j], headings[j]) for j in range(J)])
    level, n_settle = setup.levels()
    rec, gone = gv.ramp(params, terrain, face, state, np.asarray(pairs), level, n_settle, setup, motors=motors)
    ok, tips, why, land = np.zeros(J, bool), np.full(J, np.nan), ["pressure range"] * J, []
    for j in range(J):
        if gone[j] <= n_settle:
            why[j] = "geometry"
            continue
        p, k, e = gv.tip(rec, j, face, n_settle, gone[j])
        if e is None:
            continue
        u = np.array([np.cos(np.radians(headings[j])), np.sin(np.radians(headings[j]))])
        along = float(np.dot(direction(rec["support"][j, k], face, e), u))
        if (along > 0) == (kind == 1) and along != 0:
            ok[j], tips[j] = True, p
            if kind == 2:
                to, after = ct.roll_over(pose(params, face, slopes[j], headings[j]), face, e)
                land.append((j, to, float(heading_of(after, to)), e))
    if land:
        held = stands(
            params,
            [t for _, t, _, _ in land],
            [slopes[j] for j, *_ in land],
            [h for _, _, h, _ in land],
            setup.settle + 0.5,
            setup.dt,
            motors,
        )
        for (j, _, _, e), h in zip(land, held):
            if not h and not _lands(look, face, pose(params, face, slopes[j], headings[j]), e, setup.max_pressure):
                ok[j], why[j] = False, "landing"
    return ok, tips, why


def limits(
    look: Workspace,
    params: Params,
    sweeps: Mapping[str, gv.GravitySweep],
    setup: gv.GravitySetup,
    iterations: int = 3,
    free_step: float = 1.0,
    motors: TwistedString | None = None,
) -> SlopeLimits:
    """The slope limits of every contact case of `sweeps` (see the module docstring), simulated
    with the ramp of `setup` (the gravity-aware workspace's), `iterations` bisection steps, the
    free workspace's slopes scanned in steps of `free_step` deg. With `motors` (the
    twisted-string actuator) the workspaces, the ramp and the tipping levels are in volts."""
    params = setup.rolling(params)
    contacts = tuple(sweeps)
    first = next(iter(sweeps.values()))
    H, C = first.headings.size, len(contacts)
    shape = (3, C, H)
    free, grid, sim, sim_hi = (np.full(shape, np.nan) for _ in range(4))
    pair, pres = np.zeros(shape, np.int64), np.full(shape, np.nan)
    why = np.full(shape, "", dtype=object)
    cap = friction_angle(params)
    for c, contact in enumerate(contacts):
        sw = sweeps[contact]
        free[:, c] = predict_free(look, params, sw.face, sw.headings, setup.max_pressure, free_step)
        ok, best = grid_ok(sw, look, params, setup.max_pressure)
        for kind in range(3):
            n_ok = [
                int(np.flatnonzero(~ok[kind, :, j])[0]) if (~ok[kind, :, j]).any() else sw.slopes.size for j in range(H)
            ]
            js = [j for j in range(H) if n_ok[j] > 0]
            grid[kind, c, js] = [sw.slopes[n_ok[j] - 1] for j in js]
            lo = np.array([sw.slopes[n_ok[j] - 1] for j in js])
            hi = np.array([sw.slopes[n_ok[j]] if n_ok[j] < sw.slopes.size else cap for j in js])
            p = np.array([best[kind, n_ok[j] - 1, j] for j in js])
            tip = np.full(len(js), np.nan)
            reason = ["friction" if h >= cap else ("geometry" if kind == 0 else "pressure range") for h in hi]
            for _ in range(int(iterations) if js else 0):
                mid = 0.5 * (lo + hi)
                good, t, r = _sim_ok(look, params, kind, sw.face, mid, sw.headings[js], p, setup, motors)
                lo, hi = np.where(good, mid, lo), np.where(good, hi, mid)
                tip = np.where(good, t, tip)
                reason = [reason[i] if good[i] else r[i] for i in range(len(js))]
            sim[kind, c, js], sim_hi[kind, c, js], pair[kind, c, js], pres[kind, c, js] = lo, hi, p, tip
            why[kind, c, js] = reason
    stand_lim = sim[0]
    for kind in (1, 2):  # a roll needs the robot to stand first
        at_stand = sim[kind] >= stand_lim - 0.5 * (first.slopes.max() / 2**iterations + 1e-9)
        why[kind] = np.where(at_stand & (why[kind] != "friction"), "geometry", why[kind])
    why[np.isnan(sim)] = "pressure range"
    return SlopeLimits(KINDS, contacts, first.headings, free, grid, sim, pair, pres, why.astype(str), sim_hi)
