"""The slope limit with actions of any set of pairs (issue 30, item 1; results/slope_limit.nc
`simulated_multi`): where the robot still stands above the single-pair limit to roll uphill or
downhill, bisection by direct simulation with the optimised actions of the pose at each slope
tried, of two searches on the statics (SEARCHES), each over an edge with an uphill, or downhill,
component: `sensitivity.edge_action` (the least total pressure) and
`cable_actions.reach_action` (the deepest crossing: it drives many pairs at once and finds
crossings the other misses, e.g. from the equilateral face at heading 270).

The bracket starts at the single-pair limit (`slope_limit.limits`, `simulated`: a single pair
is an action of a set of pairs, and works there; where no single pair rolls the robot that way
even on flat ground (NaN), at 0 deg if an optimised action does there, else it stays NaN) and
ends at the stand limit's high end (no roll starts from a pose that does not stand). Each
bisection step simulates the robot posed on the mid slope (`slope_limit.pose`, the rigid
robot), ramping the pressures s w of the action the statics optimised for that pose, judged as
the single-pair rolls are (`slope_limit._sim_ok`, the ramp of the gravity-aware workspace, the
landing check for downhill). One method, decided by the simulation (`rolls`): the least-total
action is simulated first; where it fails (or the statics find none), the deepest-crossing
action (if it differs) is; the slope works if either rolls the robot. So at each pose the
bracket with both searches is never below the one with `edge_action` alone (the first slope
where they part is one where edge_action's failed and the other's worked).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..physics import frames
from ..physics import topology as topo
from ..physics.params import Params
from . import gravity as gv
from . import slope_limit as sl
from .cable_actions import reach_action
from .lookup import Workspace
from .sensitivity import ActuationSettings, EdgeAction, edge_action, grounded

SEARCHES = ("least", "reach")  # sensitivity.edge_action; cable_actions.reach_action (tried in this order)


@dataclass(frozen=True)
class MultiLimits:
    """Slopes in deg, shape (3, C, H) for KINDS x contacts x headings: simulated (the low end
    of the bracket: the steepest slope where the single pair or the optimised action rolled the
    robot that way) and simulated_high (the least slope where the optimised action did not, or
    the stand limit's high end if none failed); weights (3, C, H, 12) of the optimised action
    at `simulated` (0: the single pair's limit stands), its tipping scale `pressure` MPa
    (NaN: none) and `search` (3, C, H) the search that found it (1 + its index in SEARCHES: 1
    least total, 2 deepest crossing; 0: the single pair's limit stands). Stand: the
    single-pair file's stand limit, copied."""

    simulated: np.ndarray
    simulated_high: np.ndarray
    weights: np.ndarray
    pressure: np.ndarray
    search: np.ndarray


def action(
    params: Params,
    face: int,
    slope: float,
    heading: float,
    kind: int,
    max_pressure: float,
    settings: ActuationSettings,
    search: str = "least",
) -> EdgeAction | None:
    """The optimised action of `search` (SEARCHES: `sensitivity.edge_action`,
    `cable_actions.reach_action`) with the least tipping scale over an edge of `face` with an
    uphill (kind 1) or downhill (kind 2) component, for the rigid robot posed on `slope` deg at
    `heading` deg (`slope_limit.pose`); None if there is none."""
    find = {"least": edge_action, "reach": reach_action}[search]
    nodes = sl.pose(params, face, slope, heading)
    m = grounded(params, face, nodes)
    support = frames.in_support_frame(nodes, face)[1]
    u = np.array([np.cos(np.radians(heading)), np.sin(np.radians(heading))])
    best = None
    for k in range(3):
        along = float(np.dot(sl.direction(support, face, topo.edge_nodes(face, k)), u))
        if along == 0 or (along > 0) != (kind == 1):
            continue
        a = find(m, k, max_pressure, settings.actuation_margin)
        if a is not None and (best is None or a.scale < best.scale):
            best = a
    return best


def rolls(
    look: Workspace,
    params: Params,
    kind: int,
    face: int,
    slopes: np.ndarray,
    headings: np.ndarray,
    setup: gv.GravitySetup,
    settings: ActuationSettings,
    searches: tuple[str, ...] = SEARCHES,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Whether the robot posed on slopes[j] (deg) at headings[j] (deg) rolls uphill (kind 1) or
    downhill (kind 2) with an optimised action (module docstring): each search of `searches`
    in turn, simulated (`slope_limit._sim_ok`) where the ones before did not roll it, skipping an
    action equal to one already simulated there. Returns ok (J,), the tipping scale (J,) MPa,
    the weights (J, 12) of the action that rolled it and its search (J,) (1 + index in
    SEARCHES; 0 where none did)."""
    J = len(slopes)
    good, tip = np.zeros(J, bool), np.full(J, np.nan)
    weights, used = np.zeros((J, topo.N_PAIRS)), np.zeros(J, int)
    tried: list[list[np.ndarray]] = [[] for _ in range(J)]
    for search in searches:
        acts = {
            j: action(params, face, slopes[j], headings[j], kind, setup.max_pressure, settings, search)
            for j in range(J)
            if not good[j]
        }
        run = [j for j, a in acts.items() if a is not None and not any(np.array_equal(a.weights, w) for w in tried[j])]
        if not run:
            continue
        w = np.stack([acts[j].weights for j in run])
        ok, t, _ = sl._sim_ok(look, params, kind, face, slopes[run], headings[run], w, setup)
        for i, j in enumerate(run):
            tried[j].append(w[i])
            if ok[i]:
                good[j], tip[j], weights[j], used[j] = True, t[i], w[i], SEARCHES.index(search) + 1
    return good, tip, weights, used


def multi_limits(
    look: Workspace,
    params: Params,
    sweeps: Mapping[str, gv.GravitySweep],
    lim: sl.SlopeLimits,
    setup: gv.GravitySetup,
    settings: ActuationSettings,
    iterations: int = 3,
    searches: tuple[str, ...] = SEARCHES,
) -> MultiLimits:
    """The limits with optimised actions beside the single-pair ones `lim` (module docstring),
    `iterations` bisection steps (0: not computed, NaN), the actions of `searches` (of SEARCHES,
    tried in that order: `rolls`); the contacts and headings of `lim` (from `sweeps`)."""
    params = setup.rolling(params)
    sim, high = lim.simulated.copy(), lim.simulated_high.copy()
    weights = np.zeros((*sim.shape, topo.N_PAIRS))
    pres, found = np.full(sim.shape, np.nan), np.zeros(sim.shape, int)
    if int(iterations) <= 0:  # not computed
        return MultiLimits(np.full(sim.shape, np.nan), np.full(sim.shape, np.nan), weights, pres, found)
    for c, contact in enumerate(lim.contacts):
        face = sweeps[contact].face
        for kind in (1, 2):
            lo0, stand_lo = lim.simulated[kind, c].copy(), lim.simulated[0, c]
            # no single pair rolls the robot that way even on flat ground: an action at 0 deg may
            nan = np.flatnonzero(np.isnan(lo0) & (stand_lo > 0))
            if nan.size:
                zero = np.zeros(nan.size)
                good, tip, w, used = rolls(look, params, kind, face, zero, lim.headings[nan], setup, settings, searches)
                for i, j in enumerate(nan[good]):
                    lo0[j] = 0.0
                    weights[kind, c, j], pres[kind, c, j], found[kind, c, j] = w[good][i], tip[good][i], used[good][i]
            js = np.array([j for j in range(lim.headings.size) if np.isfinite(lo0[j]) and lo0[j] < stand_lo[j]], int)
            if not js.size:
                continue
            lo, hi = lo0[js].copy(), lim.simulated_high[0, c, js].copy()
            for _ in range(int(iterations)):
                mid = 0.5 * (lo + hi)
                good, tip, w, used = rolls(look, params, kind, face, mid, lim.headings[js], setup, settings, searches)
                for i in np.flatnonzero(good):
                    weights[kind, c, js[i]], pres[kind, c, js[i]], found[kind, c, js[i]] = w[i], tip[i], used[i]
                lo, hi = np.where(good, mid, lo), np.where(good, hi, mid)
            sim[kind, c, js], high[kind, c, js] = lo, hi
    return MultiLimits(sim, high, weights, pres, found)


def uphill_limits(
    look: Workspace,
    params: Params,
    sweeps: Mapping[str, gv.GravitySweep],
    lim: sl.SlopeLimits,
    multi: MultiLimits,
    setup: gv.GravitySetup,
    margin: float,
    iterations: int = 3,
    criterion: str = "cables",
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The uphill limit with the statics' actions of `criterion` ("cables": the 24 cables one by
    one; "pairs"), per contact of `lim` and heading: `cable_actions.simulated`, bisection
    (`iterations` steps, 0: not computed) from the pair limit (uphill `simulated_multi` of
    `multi`, the single-pair `simulated` where that is NaN) up to the stand limit's high end, so
    never below the pair limit it starts from. For cables only where the statics find no pair
    action at the first bisection slope (`pairs_reach`): elsewhere the cable action there is a
    pair action lifted, the pairs' question, and the bracket is the pairs' (simulated_multi and
    its high end, copied). Returns the bracket (lo, hi) deg, (C, H) each (NaN: no roll found, or
    not computed), and the weights (C, H, 24 or 12) of the action that rolled the robot at lo
    (0: none above the start); `margin` m as in `sensitivity.edge_action`."""
    from .cable_actions import simulated

    shape = lim.simulated.shape[1:]
    lo, hi = np.full(shape, np.nan), np.full(shape, np.nan)
    weights = np.zeros((*shape, topo.N_CABLES if criterion == "cables" else topo.N_PAIRS))
    if int(iterations) <= 0:
        return lo, hi, weights
    params = setup.rolling(params)
    for c, contact in enumerate(lim.contacts):
        face, heads = sweeps[contact].face, lim.headings
        start, top = np.fmax(multi.simulated[1, c], lim.simulated[1, c]), lim.simulated_high[0, c]
        run = np.ones(heads.size, bool)
        if criterion == "cables":
            run = ~np.array(
                [pairs_reach(params, face, start[j], top[j], heads[j], setup, margin) for j in range(heads.size)]
            )
            high = np.where(np.isnan(multi.simulated_high[1, c]), top, multi.simulated_high[1, c])
            lo[c, ~run], hi[c, ~run] = start[~run], high[~run]
        js = np.flatnonzero(run)
        if js.size:
            a, b, weights[c, js] = simulated(
                look, params, face, heads[js], start[js], top[js], setup, margin, iterations, criterion
            )
            lo[c, js], hi[c, js] = a, np.where(np.isnan(a), np.nan, b)
    return lo, hi, weights


def pairs_reach(
    params: Params, face: int, start: float, top: float, heading: float, setup: gv.GravitySetup, margin: float
) -> bool:
    """Whether the statics find a pair action (`cable_actions.verdict`, criterion "pairs") uphill
    at the first bisection slope (start + top) / 2 deg of `uphill_limits` (False if start is NaN
    or not below top)."""
    from .cable_actions import CRITERIA, verdict

    if not (np.isfinite(start) and start < top):
        return False
    v = verdict(params, face, 0.5 * (start + top), heading, setup.max_pressure, margin, CRITERIA[:2])
    return bool(v.ok["pairs"])
