"""results/nominal/{contact}.nc: the nominal CoG of one contact case (docs/datasets.md), its
builder and its reader (a `workspace.nominal.Nominal`)."""

from __future__ import annotations

import os
from collections.abc import Sequence

import xarray as xr
from numpy.typing import ArrayLike

from ...workspace.nominal import METHODS, Nominal
from .. import datasets
from .common import coords, rest_vars

STATICS_COMMENT = (
    "0: no average (nominal_method statics); the nominal CoG is the static equilibrium, converged to Newton "
    "steps below 1e-8 m, which leaves ~1e-15 m (tensegrity.workspace.equilibria, physics.equilibrium)"
)
NOMINAL_ALLOW_NAN = ["tip_pressure", "cog", "cog_std", "support", "margin", "averaging_error"]


def nominal_dataset(
    pairs: ArrayLike,
    levels: ArrayLike,
    cog: ArrayLike,
    std: ArrayLike,
    sup: ArrayLike,
    margin: ArrayLike,
    tip: ArrayLike,
    rolled: ArrayLike,
    averaging_error: ArrayLike,
    attrs: dict,
    strut_length: float,
    method: str = "averaging",
) -> xr.Dataset:
    """The nominal file of one contact case: per pair (n,) and level (P,) MPa the nominal CoG,
    its spread and the mean support (m, support frame), the margin (m), the tipping pressure
    (MPa), where the grounded robot rolled off and the estimated error of each average (n, P) m
    (`workspace.nominal.averaging_error`); the robot's strut length and rest state on the face
    (`rest_vars`); `attrs` of the sweep files; `method` (nominal.method) the attribute
    nominal_method: averaging (the sweeps' means) or statics (the static equilibria: cog_std and
    averaging_error are 0, the latter with a comment saying why)."""
    var = datasets.var
    if method not in METHODS:
        raise ValueError(f"nominal.method: {method!r} is not one of {METHODS}")
    ds = xr.Dataset(
        {
            "averaging_error": var(
                ("pair", "pressure"),
                averaging_error,
                "m",
                "estimated error of the nominal CoG from the oscillation left in the level's window: a "
                "quarter of the range of the mean CoG over all half-length sub-windows (NaN: rolled off)",
            ),
            "cog": var(("pair", "pressure", "axis"), cog, "m", "nominal centre of gravity in the support frame"),
            "cog_std": var(
                ("pair", "pressure", "axis"), std, "m", "standard deviation of the CoG over the level (oscillation)"
            ),
            "support": var(
                ("pair", "pressure", "corner", "axis"), sup, "m", "mean deformed support triangle in the support frame"
            ),
            "margin": var(
                ("pair", "pressure"),
                margin,
                "m",
                "signed distance of the CoG projection to the support triangle boundary (positive inside)",
            ),
            "tip_pressure": var(
                ("pair",), tip, "MPa", "least pressure at which the CoG projection leaves the triangle (NaN: never)"
            ),
            "rolled": var(
                ("pair", "pressure"),
                rolled,
                "1",
                "1 from the level at which the grounded robot rolled off the face (always 0 in the free mode)",
            ),
            **rest_vars(strut_length, int(attrs["face"])),
        },
        coords=coords(pairs, levels),
        attrs=attrs | {"nominal_method": method},
    )
    if method == "statics":
        ds["averaging_error"].attrs["comment"] = STATICS_COMMENT
    return ds


def nominal_from_dataset(ds: xr.Dataset) -> Nominal:
    """The `Nominal` of a dataset with the contract of results/nominal/{contact}.nc: cog
    (pair, pressure, axis) m, support (pair, pressure, corner, axis) m and margin (pair,
    pressure) m of the pairs swept at the levels `pressure` MPa; attributes contact, face and
    mode (and nominal_method; absent: averaging, a file made before it). ValueError naming the
    file if one is missing."""
    try:
        return Nominal.of_pairs(
            ds.attrs["contact"],
            int(ds.attrs["face"]),
            ds.attrs["mode"],
            ds["pressure"].values,
            ds["pair"].values,
            ds["cog"].transpose("pair", "pressure", "axis").values,
            ds["support"].transpose("pair", "pressure", "corner", "axis").values,
            ds["margin"].transpose("pair", "pressure").values,
            ds["averaging_error"].transpose("pair", "pressure").values if "averaging_error" in ds else None,
            method=str(ds.attrs.get("nominal_method", "averaging")),
        )
    except (KeyError, ValueError) as e:
        src = ds.encoding.get("source", "<dataset>")
        raise ValueError(f"{src!r} is not a nominal CoG file: {e}") from e


def read_nominal(path: str | os.PathLike) -> Nominal:
    """Read results/nominal/{contact}.nc (or a file of the same contract) as a `Nominal`."""
    return nominal_from_dataset(datasets.read(path))


def read_nominals(paths: Sequence[str | os.PathLike]) -> dict[str, Nominal]:
    """The nominal files `paths` by contact case (contact -> `Nominal`), in the order given."""
    return {n.contact: n for n in map(read_nominal, paths)}
