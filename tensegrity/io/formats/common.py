"""What every file of the workspace pipeline shares (docs/datasets.md): the coordinates, one
long_name each, and the robot's geometry (strut length and rest state) stored in the file."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ...physics import frames
from ...physics import topology as topo
from .. import datasets

AXES = ["x", "y", "z"]


def coords(pairs: ArrayLike | None = None, levels: ArrayLike | None = None) -> dict:
    """The coordinates every workspace file shares, one long_name each: axis, corner, node, and
    optionally pair (1-based) and pressure (MPa)."""
    c = {
        "axis": ("axis", AXES, {"long_name": "support-frame axis", "units": "1"}),
        "corner": ("corner", [1, 2, 3], {"units": "1", "long_name": "support triangle corner"}),
        "node": ("node", np.arange(1, topo.N_NODES + 1), {"units": "1", "long_name": "node number"}),
    }
    if pairs is not None:
        c["pair"] = ("pair", np.asarray(pairs), {"units": "1", "long_name": "actuator pair number"})
    if levels is not None:
        c["pressure"] = ("pressure", np.asarray(levels, float), {"units": "MPa", "long_name": "muscle pressure"})
    return c


def rest_vars(strut_length: float, faces: ArrayLike | int) -> dict:
    """The robot's strut length S and its unactuated symmetric state in the support frame of
    each face of `faces` (a face number, or (F,) numbers on the dimension `face`): rest_cog and
    rest_support, the 0 MPa point of every curve (`frames.rest_frame`)."""
    var = datasets.var
    one = np.ndim(faces) == 0
    rest = [frames.rest_frame(int(f), strut_length) for f in np.atleast_1d(faces)]
    cog, sup = np.stack([r[0] for r in rest]), np.stack([r[1] for r in rest])
    lead = () if one else ("face",)
    return {
        **datasets.geometry_vars(strut_length),
        "rest_cog": var(
            (*lead, "axis"),
            cog[0] if one else cog,
            "m",
            "centre of gravity of the unactuated symmetric robot in the support frame",
        ),
        "rest_support": var(
            (*lead, "corner", "axis"),
            sup[0] if one else sup,
            "m",
            "support triangle of the unactuated symmetric robot in the support frame",
        ),
    }
