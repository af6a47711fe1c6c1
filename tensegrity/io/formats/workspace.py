"""results/workspace.nc: the workspace of all 20 faces (docs/datasets.md), its contract check
and its reader, a `Workspace` for planning (and its tipping pressures, `tip_pressures`)."""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike

from ...physics import topology as topo
from .. import datasets
from .common import AXES, coords, rest_vars

if TYPE_CHECKING:  # imported where used: importing io.formats loads no simulator (numba)
    from ...workspace.lookup import Workspace

WORKSPACE_ALLOW_NAN = ["cog", "support", "margin", "tip_pressure"]


def workspace_dataset(levels: ArrayLike, ws: dict, strut_length: float) -> xr.Dataset:
    """The 20-face workspace (workspace.mapping.map_workspace) with the face table and the
    robot's strut length and rest state on every face (`rest_vars`)."""
    var = datasets.var
    return xr.Dataset(
        {
            "cog": var(
                ("face", "pair", "pressure", "axis"),
                ws["cog"],
                "m",
                "nominal centre of gravity in the face's support frame",
            ),
            "support": var(
                ("face", "pair", "pressure", "corner", "axis"),
                ws["support"],
                "m",
                "deformed support triangle in the face's support frame",
            ),
            "margin": var(
                ("face", "pair", "pressure"),
                ws["margin"],
                "m",
                "signed distance of the CoG projection to the support triangle boundary (positive inside)",
            ),
            "tip_pressure": var(
                ("face", "pair"),
                ws["tip_pressure"],
                "MPa",
                "least pressure at which the CoG projection leaves the triangle (NaN: never or not computed)",
            ),
            "face_nodes": var(
                ("face", "corner"),
                topo.FACES + 1,
                "1",
                "node numbers of the face's corners (support-frame corner order)",
            ),
            "face_type": (
                ("face",),
                topo.FACE_TYPES.astype(str),
                {"long_name": "equilateral (3 cables) or isosceles (2 cables and a gap)"},
            ),
            "reference_corner": var(
                ("face",), topo.FACE_REFERENCE + 1, "1", "corner of the reference vertex (the support frame's +y)"
            ),
            **rest_vars(strut_length, np.arange(1, topo.N_FACES + 1)),
        },
        coords={
            **coords(np.arange(1, topo.N_PAIRS + 1), levels),
            "face": ("face", np.arange(1, topo.N_FACES + 1), {"units": "1", "long_name": "face number"}),
        },
    )


def check_workspace(ds: xr.Dataset, source: str | os.PathLike | None = None) -> None:
    """Raise ValueError (naming `source`, default the file the dataset was read from) unless `ds`
    holds what the contract of results/workspace.nc says: `cog` (face, pair, pressure, axis)
    and `support` (face, pair, pressure, corner, axis) with face 1..20, axis x, y, z, corner
    1..3 and the pairs among 1..12; levels `pressure` finite, positive, strictly increasing
    MPa; cog and support NaN (a pair or face not computed) or finite, NaN together, and within
    one strut length S of the support-frame origin (the robot is S across); `margin` within S
    and `tip_pressure` NaN or within the levels where present."""
    src = os.fspath(source) if source is not None else ds.encoding.get("source", "<dataset>")

    def bad(what: str) -> ValueError:
        return ValueError(f"workspace {src!r} is not a valid workspace (corrupted?): {what}")

    need = {"cog": ("face", "pair", "pressure", "axis"), "support": ("face", "pair", "pressure", "corner", "axis")}
    for name, dims in need.items():
        if name not in ds.variables:
            raise bad(f"no variable {name!r}")
        if set(ds[name].dims) != set(dims):
            raise bad(f"{name!r} has dimensions {ds[name].dims}, expected {dims}")
        if ds[name].dtype.kind != "f":
            raise bad(f"{name!r} has dtype {ds[name].dtype}, expected float")
    expect = {"face": np.arange(1, topo.N_FACES + 1), "axis": np.array(AXES), "corner": np.arange(1, 4)}
    for dim, values in expect.items():
        if (
            dim not in ds.coords
            or ds.sizes[dim] != values.size
            or not np.array_equal(np.sort(np.asarray(ds[dim].values).astype(values.dtype)), values)
        ):
            raise bad(f"coordinate {dim!r} must be {values.tolist()}")
    pairs = np.asarray(ds["pair"].values) if "pair" in ds.coords else np.array([])
    if (
        pairs.size == 0
        or pairs.dtype.kind not in "iu"
        or len(set(pairs.tolist())) != pairs.size
        or pairs.min() < 1
        or pairs.max() > topo.N_PAIRS
    ):
        raise bad(f"coordinate 'pair' must be distinct pair numbers 1..{topo.N_PAIRS}, got {pairs.tolist()}")
    lv = np.asarray(ds["pressure"].values) if "pressure" in ds.coords else np.array([])
    if (
        lv.ndim != 1
        or lv.size == 0
        or lv.dtype.kind != "f"
        or not np.all(np.isfinite(lv))
        or lv[0] <= 0
        or np.any(np.diff(lv) <= 0)
    ):
        raise bad(f"levels 'pressure' must be finite, positive and strictly increasing MPa, got {lv.tolist()}")
    S = datasets.strut_length(ds)
    if not (np.isfinite(S) and S > 0):
        raise bad(f"strut length {S} m in its configuration")
    cog, sup = ds["cog"].values, ds["support"].values
    for name, a in (("cog", cog), ("support", sup)):
        if np.any(np.isinf(a)):
            raise bad(f"{name!r} holds infinite values")
        fin = a[np.isfinite(a)]
        if fin.size and np.max(np.abs(fin)) >= S:
            raise bad(f"{name!r} reaches {np.max(np.abs(fin)):.6g} m, not within the strut length {S} m")
    cog_nan = np.isnan(ds["cog"].transpose("face", "pair", "pressure", "axis").values).any(axis=-1)
    sup_nan = np.isnan(ds["support"].transpose("face", "pair", "pressure", "corner", "axis").values).any(axis=(-2, -1))
    if np.any(cog_nan != sup_nan):
        raise bad("'cog' and 'support' are not NaN at the same faces, pairs and levels")
    if "margin" in ds.variables:
        m = ds["margin"].values
        if np.any(np.isinf(m)) or (np.isfinite(m).any() and np.max(np.abs(m[np.isfinite(m)])) >= S):
            raise bad(f"'margin' is infinite or not within the strut length {S} m")
    if "tip_pressure" in ds.variables:
        t = ds["tip_pressure"].values
        t = t[~np.isnan(t)]
        if np.any(~np.isfinite(t)) or np.any(t < lv[0] - 1e-9) or np.any(t > lv[-1] + 1e-9):
            raise bad(f"'tip_pressure' is outside the levels {lv[0]}..{lv[-1]} MPa")


def workspace_from_dataset(ds: xr.Dataset) -> Workspace:
    """The `Workspace` of a dataset with the contract of results/workspace.nc: cog
    (face, pair, pressure, axis) m and support (face, pair, pressure, corner, axis) m at the
    levels `pressure` MPa; the 0 MPa point is the symmetric robot of the dataset's strut length
    (`datasets.strut_length`, m). Checked first (`check_workspace`): a dataset that breaks the
    contract raises ValueError naming its file."""
    from ...workspace.lookup import Workspace

    check_workspace(ds)
    order = {"face": np.arange(1, 21), "pair": np.arange(1, 13), "axis": ["x", "y", "z"]}
    sel = {k: v for k, v in order.items() if k in ds.dims}
    cog = ds["cog"].sel(sel).transpose("face", "pair", "pressure", "axis").values
    support = ds["support"].sel(sel).transpose("face", "pair", "pressure", "corner", "axis").values
    return Workspace.from_arrays(ds["pressure"].values, cog, support, datasets.strut_length(ds))


def tip_pressures(ds: xr.Dataset) -> np.ndarray:
    """The tipping pressures (20, 12) MPa of a dataset with the contract of results/workspace.nc,
    faces 1..20 and pairs 1..12 in order (NaN: never or not computed)."""
    tip = ds["tip_pressure"].sel(face=np.arange(1, topo.N_FACES + 1), pair=np.arange(1, topo.N_PAIRS + 1))
    return tip.transpose("face", "pair").values


def read_workspace(path: str | os.PathLike, two_pair: str | os.PathLike | None = None) -> Workspace:
    """Read results/workspace.nc (or a file of the same contract) as a `Workspace`; with the
    measured two-pair curves of `two_pair` (results/workspace_two_pair.nc), if given: a file of
    another run (another robot or time step) is refused, naming both (`io.provenance`)."""
    ds = datasets.read(path)
    ws = workspace_from_dataset(ds)
    if two_pair is None:
        return ws
    from ..provenance import check_together
    from .two_pair import read_two_pair

    check_together({os.fspath(path): config_of(ds), os.fspath(two_pair): config_of(two_pair)})
    return ws.with_two_pair(*read_two_pair(two_pair))


def config_of(ds: xr.Dataset | str | os.PathLike) -> dict | None:
    """The configuration a dataset (or the file at a path) names, None if it names none."""
    try:
        return datasets.provenance_config(ds)
    except ValueError:
        return None


def face_table(path: str | os.PathLike, face: int) -> str:
    """One face (1..20) of the workspace file at `path` as CSV text: a row per pair swept and
    pressure (0 MPa: the unactuated robot, the file's rest state), columns pair, pressure_MPa,
    cog_x_m, cog_y_m, cog_z_m (support frame), margin_m (positive inside) and tip_pressure_MPa
    (empty: never); a workspace in volts (`actuation`) has pressure_V and tip_pressure_V.
    Read and checked by `read_workspace`."""
    from ...physics import frames
    from . import actuation

    ws, ds = read_workspace(path), datasets.read(path)
    u = actuation.units(actuation.kind_of(ds))
    rows = [f"pair,pressure_{u},cog_x_m,cog_y_m,cog_z_m,margin_m,tip_pressure_{u}"]
    tips = ds["tip_pressure"].sel(face=face).values
    for p in ws.pairs(face):
        tip = "" if not np.isfinite(tips[p - 1]) else f"{tips[p - 1]:.6g}"
        cog = np.concatenate([ws.rest_cog[face - 1][None], ws.cog[face - 1, p - 1]])
        sup = np.concatenate([ws.rest_support[face - 1][None], ws.support[face - 1, p - 1]])
        margin = frames.margin_2d(cog[:, :2], sup[:, :, :2])
        for k, pressure in enumerate(ws.pressures):
            x, y, z = cog[k]
            rows.append(f"{p},{pressure:g},{x:.9f},{y:.9f},{z:.9f},{margin[k]:.9f},{tip}")
    return "\n".join(rows) + "\n"
