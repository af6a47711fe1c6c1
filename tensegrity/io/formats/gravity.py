"""The files of the gravity-aware workspace and the slope limit (docs/datasets.md), built from and
read back into the package's arrays:

- results/workspace_gravity.nc: `gravity_dataset` (from `workspace.gravity.GravitySweep` per
  contact case), read back by `sweeps_from_dataset`.
- results/slope_limit.nc: `slope_limit_dataset` (from `workspace.slope_limit.SlopeLimits` and
  `workspace.slope_multi.MultiLimits`).
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np
import xarray as xr

from ...physics import topology as topo
from .. import datasets
from .common import coords

if TYPE_CHECKING:
    from ...workspace.gravity import GravitySetup, GravitySweep
    from ...workspace.slope_limit import SlopeLimits
    from ...workspace.slope_multi import MultiLimits

__all__ = [
    "GRAVITY_ALLOW_NAN",
    "gravity_dataset",
    "sweeps_from_dataset",
    "read_gravity",
    "SLOPE_LIMIT_ALLOW_NAN",
    "slope_limit_dataset",
]

GRAVITY_ALLOW_NAN = ["tip_pressure", "cog", "support", "projection", "margin"]
_DIMS = ("contact", "slope", "heading", "pair")


def _case_coords(contacts, slopes, headings) -> dict:
    return {
        "contact": ("contact", list(contacts), {"long_name": "contact case (canonical face type)"}),
        "slope": ("slope", np.asarray(slopes, float), {"units": "degree", "long_name": "ground slope angle"}),
        "heading": (
            "heading",
            np.asarray(headings, float),
            {"units": "degree", "long_name": "uphill direction in the contact face's support frame, from +x toward +y"},
        ),
    }


_SETTINGS = ("ramp_rate", "interval", "lift_tolerance", "hold_time", "settle", "max_pressure")


def gravity_dataset(sweeps: Mapping[str, GravitySweep], setup: GravitySetup) -> xr.Dataset:
    """The gravity-aware workspace of the contact cases `sweeps` (contact -> GravitySweep, all on
    the same pairs, slopes, headings and pressure grid) made with `setup` (attributes
    `<name>_setting` of its ramp)."""
    var = datasets.var
    attrs = {f"{k}_setting": float(getattr(setup, k)) for k in _SETTINGS}
    first = next(iter(sweeps.values()))
    for c, s in sweeps.items():
        for k in ("pairs", "slopes", "headings", "pressure"):
            if not np.array_equal(getattr(s, k), getattr(first, k)):
                raise ValueError(f"contact {c!r}: {k} differ from the other contact cases")

    def stack(name):
        return np.stack([getattr(s, name) for s in sweeps.values()])

    proj = stack("projection")
    proj = np.concatenate([proj, np.where(np.isnan(proj[..., :1]), np.nan, 0.0)], axis=-1)
    P = (*_DIMS, "pressure")
    return xr.Dataset(
        {
            "face": var(("contact",), [s.face for s in sweeps.values()], "1", "contact face number"),
            "face_nodes": var(
                ("contact", "corner"),
                [topo.FACES[s.face - 1] + 1 for s in sweeps.values()],
                "1",
                "node numbers of the contact face's corners (support-frame corner order)",
            ),
            "stood": var(
                _DIMS[:3],
                stack("stood").astype(np.int8),
                "1",
                "1 if the unactuated robot stays on the face at this slope and heading",
            ),
            "rolled": var(
                _DIMS,
                stack("rolled").astype(np.int8),
                "1",
                "1 if ramping this pair rolled the robot off the face within the pressure range",
            ),
            "tip_pressure": var(
                _DIMS,
                stack("tip_pressure"),
                "MPa",
                "pressure at which the CoG projection along gravity left the support triangle (NaN: no roll)",
            ),
            "tip_edge": var(
                (*_DIMS, "end"), stack("tip_edge"), "1", "nodes of the edge the robot rolled over (0: none)"
            ),
            "cog": var((*P, "axis"), stack("cog"), "m", "centre of gravity in the deformed face's support frame"),
            "support": var(
                (*P, "corner", "axis"), stack("support"), "m", "deformed support triangle in the support frame"
            ),
            "projection": var(
                (*P, "axis"), proj, "m", "CoG projected along gravity onto the face plane, support frame"
            ),
            "margin": var(
                P,
                stack("margin"),
                "m",
                "signed distance of the CoG projection along gravity to the triangle boundary (positive inside)",
            ),
        },
        coords={
            **coords(first.pairs, first.pressure),
            **_case_coords(sweeps, first.slopes, first.headings),
            "end": ("end", [1, 2], {"units": "1", "long_name": "end of an edge"}),
        },
        attrs=attrs,
    )


def sweeps_from_dataset(ds: xr.Dataset) -> dict[str, GravitySweep]:
    """contact -> GravitySweep of a results/workspace_gravity.nc dataset."""
    from ...workspace.gravity import GravitySweep

    out = {}
    for c, contact in enumerate(ds["contact"].values.astype(str)):
        v = {
            k: ds[k].values[c]
            for k in ("stood", "rolled", "tip_pressure", "tip_edge", "cog", "support", "projection", "margin")
        }
        out[contact] = GravitySweep(
            int(ds["face"].values[c]),
            ds["pair"].values,
            ds["slope"].values,
            ds["heading"].values,
            ds["pressure"].values,
            v["stood"].astype(bool),
            v["rolled"].astype(bool),
            v["tip_pressure"],
            v["tip_edge"],
            v["cog"],
            v["support"],
            v["projection"][..., :2],
            v["margin"],
        )
    return out


def read_gravity(path: str | os.PathLike) -> dict[str, GravitySweep]:
    """contact -> GravitySweep of the file results/workspace_gravity.nc at `path`."""
    return sweeps_from_dataset(datasets.read(path))


SLOPE_LIMIT_ALLOW_NAN = [
    "predicted_free",
    "predicted_gravity",
    "simulated",
    "simulated_high",
    "pressure",
    "simulated_multi",
    "simulated_multi_high",
    "multi_pressure",
    "simulated_cables",
    "simulated_cables_high",
]


def slope_limit_dataset(lim: SlopeLimits, multi: MultiLimits, attrs: dict, cables: tuple | None = None) -> xr.Dataset:
    """results/slope_limit.nc: per kind (stand, uphill, downhill), contact and heading the
    steepest slope predicted from the free workspace, from the gravity-aware one and found by
    simulation, what sets it, and the pair and pressure used; the simulated limit with optimised
    actions of any set of pairs (`multi`, `workspace.slope_multi`) and its action; the uphill limit
    with per-cable actions `cables` (`slope_multi.uphill_limits`'s; None: not computed, NaN)."""
    var = datasets.var
    dims = ("kind", "contact", "heading")
    nan = np.full(lim.simulated.shape[1:], np.nan)
    lo, hi, w = (nan, nan, np.zeros((*nan.shape, topo.N_CABLES))) if cables is None else cables
    error = "error: the limit lies in the bisection bracket [simulated_cables, simulated_cables_high]; a lower "
    error += "bound of what the 24 cables allow, the statics' actions being local searches"
    with_cables = {
        "simulated_cables": var(
            dims[1:],
            lo,
            "degree",
            "steepest slope found by direct simulation to roll uphill with an action of the 24 cables one by one "
            "optimised on the statics (cable_actions.verdict), bisected up from simulated_multi where the statics "
            "find no pair action midway to the stand limit (elsewhere simulated_multi), the low end of its bracket "
            "(NaN: none, or not computed)",
            comment=error,
        ),
        "simulated_cables_high": var(
            dims[1:],
            hi,
            "degree",
            "high end of that bracket: the least slope where the cable action did not roll the robot uphill (or "
            "the stand limit's high end, if none failed; simulated_multi_high where that was copied) (NaN: none, "
            "or not computed)",
            comment=error,
        ),
        "cables_weights": var(
            (*dims[1:], "cable"),
            w,
            "1",
            "weights w of the cable action that rolled the robot uphill at simulated_cables, cable pressures s w "
            "(all 0: none above simulated_multi, or not computed)",
        ),
    }
    with_multi = {
        "simulated_multi": var(
            dims,
            multi.simulated,
            "degree",
            "steepest slope found by direct simulation with a single pair or an action of any set of pairs "
            "optimised on the statics, the low end of its bisection bracket (NaN: not computed)",
        ),
        "simulated_multi_high": var(
            dims,
            multi.simulated_high,
            "degree",
            "high end of that bracket: the least slope where the optimised action did not work (or the "
            "stand limit's high end, if none failed) (NaN: not computed)",
        ),
        "multi_weights": var(
            (*dims, "actuator"),
            multi.weights,
            "1",
            "weights w of the optimised action at simulated_multi, pressures s w (all 0: the single pair's limit)",
        ),
        "multi_pressure": var(dims, multi.pressure, "MPa", "its tipping scale s at simulated_multi (NaN: none)"),
        "multi_search": var(
            dims,
            multi.search,
            "1",
            "search on the statics that found that action: 1 least total pressure (sensitivity.edge_action), "
            "2 deepest crossing (cable_actions.reach_action), tried where the first did not roll the robot "
            "(0: the single pair's limit stands)",
        ),
    }
    return xr.Dataset(
        {
            "predicted_free": var(
                dims,
                lim.predicted_free,
                "degree",
                "steepest slope predicted from the free workspace projected along gravity (NaN: none)",
            ),
            "predicted_gravity": var(
                dims,
                lim.predicted_gravity,
                "degree",
                "steepest slope of the gravity-aware workspace's slope grid (NaN: none)",
            ),
            "simulated": var(
                dims,
                lim.simulated,
                "degree",
                "steepest slope found by direct simulation, the low end of the bisection bracket (NaN: none)",
            ),
            "simulated_high": var(
                dims,
                lim.simulated_high,
                "degree",
                "high end of the bisection bracket: the least slope found not to work (or the next grid slope, "
                "or the friction angle, if none failed); the limit lies between simulated and this (NaN: none)",
            ),
            "pair": var(dims, lim.pair, "1", "pair that rolls the robot at the limit (0: none, or standing)"),
            "pressure": var(dims, lim.pressure, "MPa", "its tipping pressure at the simulated limit (NaN: none)"),
            "limited_by": (
                dims,
                lim.limited_by.astype(str),
                {"long_name": "what sets the limit: geometry, pressure range, friction or grid"},
            ),
            **with_multi,
            **with_cables,
        },
        coords={
            "kind": ("kind", list(lim.kinds), {"long_name": "stand, roll uphill, roll downhill under control"}),
            "contact": ("contact", list(lim.contacts), {"long_name": "contact case (canonical face type)"}),
            "actuator": (
                "actuator",
                np.arange(1, topo.N_PAIRS + 1),
                {"units": "1", "long_name": "actuator pair (1-based)"},
            ),
            "cable": ("cable", np.arange(1, topo.N_CABLES + 1), {"units": "1", "long_name": "cable (1-based)"}),
            "cable_pair": ("cable", topo.CABLE_PAIR + 1, {"units": "1", "long_name": "actuator pair of the cable"}),
            "cable_nodes": (("cable", "end"), topo.CABLES + 1, {"units": "1", "long_name": "nodes the cable joins"}),
            "heading": (
                "heading",
                lim.headings,
                {"units": "degree", "long_name": "uphill direction in the contact face's support frame"},
            ),
        },
        attrs=attrs,
    )
