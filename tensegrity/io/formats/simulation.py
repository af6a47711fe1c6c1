"""The output of `tensegrity simulate --out FILE` (docs/datasets.md, "Simulation")."""

from __future__ import annotations

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike

from ...physics import frames
from ...physics import topology as topo
from .. import datasets
from .common import coords


def simulation_dataset(
    t: ArrayLike, nodes: np.ndarray, pressure: np.ndarray, face: int, attrs: dict, volts: bool = False
) -> xr.Dataset:
    """The output of `tensegrity simulate`: node positions (T, 12, 3) m world at times t (T,) s,
    the CoG and the start face's corners in its support frame, the CoG in the world frame and the
    commanded pair pressures (T, 12) MPa as `pressure_cmd` (volts: pair voltages V as
    `voltage_cmd`, the twisted strings); `attrs` (mode, pairs, level, ramp_s) with the face."""
    var = datasets.var
    cog, sup = frames.in_support_frame(nodes, face)
    c = coords(np.arange(1, topo.N_PAIRS + 1))
    return xr.Dataset(
        {
            "cog": var(("time", "axis"), cog, "m", "centre of gravity in the start face's support frame"),
            "cog_world": var(("time", "axis"), nodes.mean(axis=-2), "m", "centre of gravity, world frame"),
            "support": var(("time", "corner", "axis"), sup, "m", "start face corners in its support frame"),
            "nodes": var(("time", "node", "axis"), nodes, "m", "node positions, world frame"),
            **(
                {"voltage_cmd": var(("time", "pair"), pressure, "V", "pair voltages commanded")}
                if volts
                else {"pressure_cmd": var(("time", "pair"), pressure, "MPa", "pair pressures commanded")}
            ),
        },
        coords={"time": ("time", np.asarray(t, float), {"units": "s", "long_name": "time"}), **c},
        attrs={"face": face, "face_nodes": topo.FACES[face - 1] + 1, **attrs},
    )
