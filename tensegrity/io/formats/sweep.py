"""results/sweeps/{contact}/pairNN.nc: the pressure staircase of one pair (docs/datasets.md)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import xarray as xr

from ...physics import topology as topo
from .. import datasets
from .common import coords, rest_vars

if TYPE_CHECKING:  # imported where used: importing io.formats loads no simulator (numba)
    from ...workspace.sweep import Sweep, SweepSetup

SWEEP_FILE = "pair{pair:02d}.nc"


def sweep_dataset(
    res: Sweep, b: int, contact: str, setup: SweepSetup, node_stride: int, strut_length: float
) -> xr.Dataset:
    """Robot `b` of a sweep result (workspace.sweep.Sweep, run with `setup`) as the sweep file
    of its pair: CoG and support per sample in the support frame (m), the commanded pressure
    (MPa), the level held, whether it rests on the face, every node_stride-th node sample, and
    the robot's strut length and rest state (`rest_vars`)."""
    var = datasets.var
    pair, stride = int(res.pairs[b]), int(node_stride)
    return xr.Dataset(
        {
            "cog": var(("time", "axis"), res.cog[b], "m", "centre of gravity in the support frame"),
            "support": var(
                ("time", "corner", "axis"), res.support[b], "m", "deformed support triangle in the support frame"
            ),
            "pressure_cmd": var(("time",), res.pressure_cmd[b], "MPa", f"pressure commanded to pair #{pair}"),
            "level": var(("time",), res.level, "1", "index of the pressure level held (-1: settling)"),
            "on_face": var(
                ("time",),
                res.on_face[b].astype(np.int8),
                "1",
                "1 while the contact face's three nodes touch the ground (always 1 in the free mode)",
            ),
            "nodes": var(
                ("time_nodes", "node", "axis"),
                res.nodes[b, ::stride],
                "m",
                "node positions, world frame (every node_stride-th sample)",
            ),
            **rest_vars(strut_length, res.face),
        },
        coords={
            **coords(),
            "time": ("time", res.t, {"units": "s", "long_name": "time"}),
            "time_nodes": ("time_nodes", res.t[::stride], {"units": "s", "long_name": "time of node samples"}),
            "levels": ("levels", res.levels, {"units": "MPa", "long_name": "pressure levels of the staircase"}),
        },
        attrs={
            "contact": contact,
            "face": res.face,
            "face_nodes": topo.FACES[res.face - 1] + 1,
            "pair": int(pair),
            "mode": setup.mode,
            "hold_s": float(setup.hold),
            "settle_s": float(setup.settle),
        },
    )
