"""The slope limit with actions of any set of pairs (issue 30, item 1; results/slope_limit.nc
`simulated_multi`): where the robot still stands above the single-pair limit to roll uphill or
downhill, bisection by direct simulation with the optimised action (`sensitivity.edge_action`:
the least total pressure over an edge with an uphill, or downhill, component) of the pose at
each slope tried.

The bracket starts at the single-pair limit (`slope_limit.limits`, `simulated`: a single pair
is an action of a set of pairs, and works there) and ends at the stand limit's high end (no
roll starts from a pose that does not stand). Each bisection step simulates the robot posed on
the mid slope (`slope_limit.pose`, the rigid robot), ramping the pressures s w of the action
the statics optimised for that pose, judged as the single-pair rolls are (`slope_limit._sim_ok`,
the ramp of the gravity-aware workspace, the landing check for downhill).
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
from .lookup import Workspace
from .sensitivity import ActuationSettings, EdgeAction, edge_action, grounded


@dataclass(frozen=True)
class MultiLimits:
    """Slopes in deg, shape (3, C, H) for KINDS x contacts x headings: simulated (the low end
    of the bracket: the steepest slope where the single pair or the optimised action rolled the
    robot that way) and simulated_high (the least slope where the optimised action did not, or
    the stand limit's high end if none failed); weights (3, C, H, 12) of the optimised action
    at `simulated` (0: the single pair's limit stands) and its tipping scale `pressure` MPa
    (NaN: none). Stand: the single-pair file's stand limit, copied."""

    simulated: np.ndarray
    simulated_high: np.ndarray
    weights: np.ndarray
    pressure: np.ndarray


def action(
    params: Params, face: int, slope: float, heading: float, kind: int, max_pressure: float, settings: ActuationSettings
) -> EdgeAction | None:
    """The optimised action (`sensitivity.edge_action`) with the least tipping scale over an
    edge of `face` with an uphill (kind 1) or downhill (kind 2) component, for the rigid robot
    posed on `slope` deg at `heading` deg (`slope_limit.pose`); None if there is none."""
    nodes = sl.pose(params, face, slope, heading)
    m = grounded(params, face, nodes)
    support = frames.in_support_frame(nodes, face)[1]
    u = np.array([np.cos(np.radians(heading)), np.sin(np.radians(heading))])
    best = None
    for k in range(3):
        along = float(np.dot(sl.direction(support, face, topo.edge_nodes(face, k)), u))
        if along == 0 or (along > 0) != (kind == 1):
            continue
        a = edge_action(m, k, max_pressure, settings.actuation_margin)
        if a is not None and (best is None or a.scale < best.scale):
            best = a
    return best


def multi_limits(
    look: Workspace,
    params: Params,
    sweeps: Mapping[str, gv.GravitySweep],
    lim: sl.SlopeLimits,
    setup: gv.GravitySetup,
    settings: ActuationSettings,
    iterations: int = 3,
) -> MultiLimits:
    """The limits with optimised actions beside the single-pair ones `lim` (module docstring),
    `iterations` bisection steps (0: not computed, NaN); the contacts and headings of `lim`
    (from `sweeps`)."""
    params = setup.rolling(params)
    sim, high = lim.simulated.copy(), lim.simulated_high.copy()
    weights = np.zeros((*sim.shape, topo.N_PAIRS))
    pres = np.full(sim.shape, np.nan)
    if int(iterations) <= 0:  # not computed
        return MultiLimits(np.full(sim.shape, np.nan), np.full(sim.shape, np.nan), weights, pres)
    for c, contact in enumerate(lim.contacts):
        face = sweeps[contact].face
        for kind in (1, 2):
            lo0, stand_lo = lim.simulated[kind, c], lim.simulated[0, c]
            js = [j for j in range(lim.headings.size) if np.isfinite(lo0[j]) and lo0[j] < stand_lo[j]]
            if not js:
                continue
            lo, hi = lo0[js].copy(), lim.simulated_high[0, c, js].copy()
            for _ in range(int(iterations)):
                mid = 0.5 * (lo + hi)
                acts = [
                    action(params, face, mid[i], lim.headings[j], kind, setup.max_pressure, settings)
                    for i, j in enumerate(js)
                ]
                good, tip = np.zeros(len(js), bool), np.full(len(js), np.nan)
                run = [i for i, a in enumerate(acts) if a is not None]
                if run:
                    w = np.stack([acts[i].weights for i in run])
                    ok, t, _ = sl._sim_ok(
                        look, params, kind, face, mid[run], lim.headings[[js[i] for i in run]], w, setup
                    )
                    good[run], tip[run] = ok, t
                for i in np.flatnonzero(good):
                    weights[kind, c, js[i]], pres[kind, c, js[i]] = acts[i].weights, tip[i]
                lo, hi = np.where(good, mid, lo), np.where(good, hi, mid)
            sim[kind, c, js], high[kind, c, js] = lo, hi
    return MultiLimits(sim, high, weights, pres)
