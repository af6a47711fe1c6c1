"""results/nominal/{contact}.nc: the nominal CoG of one contact case (docs/datasets.md)."""
from __future__ import annotations

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike

from ...physics import topology as topo
from .. import datasets
from .common import coords, rest_vars

NOMINAL_ALLOW_NAN = ["tip_pressure", "cog", "cog_std", "support", "margin"]


def nominal_dataset(pairs: ArrayLike, levels: ArrayLike, cog: ArrayLike, std: ArrayLike, sup: ArrayLike,
                    margin: ArrayLike, tip: ArrayLike, rolled: ArrayLike, attrs: dict,
                    strut_length: float) -> xr.Dataset:
    """The nominal file of one contact case: per pair (n,) and level (P,) MPa the nominal CoG,
    its spread and the mean support (m, support frame), the margin (m), the tipping pressure
    (MPa) and where the grounded robot rolled off; the robot's strut length and rest state on
    the face (`rest_vars`); `attrs` of the sweep files."""
    var = datasets.var
    return xr.Dataset(
        {"cog": var(("pair", "pressure", "axis"), cog, "m", "nominal centre of gravity in the support frame"),
         "cog_std": var(("pair", "pressure", "axis"), std, "m", "standard deviation of the CoG over the level (oscillation)"),
         "support": var(("pair", "pressure", "corner", "axis"), sup, "m", "mean deformed support triangle in the support frame"),
         "margin": var(("pair", "pressure"), margin, "m", "signed distance of the CoG projection to the support triangle boundary (positive inside)"),
         "tip_pressure": var(("pair",), tip, "MPa", "least pressure at which the CoG projection leaves the triangle (NaN: never)"),
         "rolled": var(("pair", "pressure"), rolled, "1", "1 from the level at which the grounded robot rolled off the face (always 0 in the free mode)"),
         **rest_vars(strut_length, int(attrs["face"]))},
        coords=coords(pairs, levels),
        attrs=attrs)
