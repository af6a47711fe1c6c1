"""The dataset contract file by file (docs/design.md §5, docs/datasets.md): what each file of
the workflow holds, built from and read back into the package's arrays and types.

Each file type has a builder (`*_dataset`: arrays or results -> xarray Dataset with units and
long names, written by `datasets.write`) and, where the package reads it back, a reader
(`*_from_dataset`, `read_*`):

- Sweeps, results/sweeps/{contact}/pairNN.nc: `sweep_dataset`, `SWEEP_FILE`.
- Nominal CoG, results/nominal/{contact}.nc: `nominal_dataset`.
- Curves, results/curves/{contact}.nc and curves.json: `curves_dataset`, `curves_document`.
- Workspace, results/workspace.nc: `workspace_dataset`; read as a `Workspace`:
  `workspace_from_dataset`, `read_workspace`.
The locomotion runs' files are in `run_formats`, the two-pair workspace's in `two_pair_formats`.
"""
from __future__ import annotations

import os
from typing import TYPE_CHECKING

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike

AXES = ["x", "y", "z"]

from ..physics import topology as topo
from . import datasets

if TYPE_CHECKING:  # imported where used: importing io.formats loads no simulator (numba)
    from ..workspace.sweep import Sweep
    from ..locomotion.lookup import Workspace

__all__ = ["coords", "SWEEP_FILE", "sweep_dataset", "NOMINAL_ALLOW_NAN", "nominal_dataset",
           "CURVES_ALLOW_NAN", "curves_dataset", "curves_document", "WORKSPACE_ALLOW_NAN",
           "workspace_dataset", "check_workspace", "read_workspace", "workspace_from_dataset"]


# ------------------------------------------------------------------ coordinates (all files)

def coords(pairs: ArrayLike | None = None, levels: ArrayLike | None = None) -> dict:
    """The coordinates every workspace file shares, one long_name each: axis, corner, node, and
    optionally pair (1-based) and pressure (MPa)."""
    c = {"axis": ("axis", AXES, {"long_name": "support-frame axis", "units": "1"}),
         "corner": ("corner", [1, 2, 3], {"units": "1", "long_name": "support triangle corner"}),
         "node": ("node", np.arange(1, topo.N_NODES + 1), {"units": "1", "long_name": "node number"})}
    if pairs is not None:
        c["pair"] = ("pair", np.asarray(pairs), {"units": "1", "long_name": "actuator pair number"})
    if levels is not None:
        c["pressure"] = ("pressure", np.asarray(levels, float), {"units": "MPa", "long_name": "muscle pressure"})
    return c


# ------------------------------------------------------ results/sweeps/{contact}/pairNN.nc

SWEEP_FILE = "pair{pair:02d}.nc"


def sweep_dataset(res: Sweep, b: int, contact: str, sweep: dict) -> xr.Dataset:
    """Robot `b` of a sweep result (workspace.sweep.Sweep) as the sweep file of its pair:
    CoG and support per sample in the support frame (m), the commanded pressure (MPa), the
    level held, whether it rests on the face, and every `sweep['node_stride']`-th node sample."""
    var = datasets.var
    pair, stride = int(res.pairs[b]), int(sweep["node_stride"])
    return xr.Dataset(
        {"cog": var(("time", "axis"), res.cog[b], "m", "centre of gravity in the support frame"),
         "support": var(("time", "corner", "axis"), res.support[b], "m",
                         "deformed support triangle in the support frame"),
         "pressure_cmd": var(("time",), res.pressure_cmd[b], "MPa", f"pressure commanded to pair #{pair}"),
         "level": var(("time",), res.level, "1", "index of the pressure level held (-1: settling)"),
         "on_face": var(("time",), res.on_face[b].astype(np.int8), "1",
                         "1 while the contact face's three nodes touch the ground (always 1 in the free mode)"),
         "nodes": var(("time_nodes", "node", "axis"), res.nodes[b, ::stride], "m",
                       "node positions, world frame (every node_stride-th sample)")},
        coords={**coords(), "time": ("time", res.t, {"units": "s", "long_name": "time"}),
                "time_nodes": ("time_nodes", res.t[::stride], {"units": "s", "long_name": "time of node samples"}),
                "levels": ("levels", res.levels, {"units": "MPa", "long_name": "pressure levels of the staircase"})},
        attrs={"contact": contact, "face": res.face, "face_nodes": topo.FACES[res.face - 1] + 1,
               "pair": int(pair), "mode": sweep["mode"], "hold_s": float(sweep["hold"]), "settle_s": float(sweep["settle"])})


# ---------------------------------------------------------- results/nominal/{contact}.nc

NOMINAL_ALLOW_NAN = ["tip_pressure", "cog", "cog_std", "support", "margin"]


def nominal_dataset(pairs: ArrayLike, levels: ArrayLike, cog: ArrayLike, std: ArrayLike, sup: ArrayLike,
                    margin: ArrayLike, tip: ArrayLike, rolled: ArrayLike, attrs: dict) -> xr.Dataset:
    """The nominal file of one contact case: per pair (n,) and level (P,) MPa the nominal CoG,
    its spread and the mean support (m, support frame), the margin (m), the tipping pressure
    (MPa) and where the grounded robot rolled off; `attrs` of the sweep files."""
    var = datasets.var
    return xr.Dataset(
        {"cog": var(("pair", "pressure", "axis"), cog, "m", "nominal centre of gravity in the support frame"),
         "cog_std": var(("pair", "pressure", "axis"), std, "m", "standard deviation of the CoG over the level (oscillation)"),
         "support": var(("pair", "pressure", "corner", "axis"), sup, "m", "mean deformed support triangle in the support frame"),
         "margin": var(("pair", "pressure"), margin, "m", "signed distance of the CoG projection to the support triangle boundary (positive inside)"),
         "tip_pressure": var(("pair",), tip, "MPa", "least pressure at which the CoG projection leaves the triangle (NaN: never)"),
         "rolled": var(("pair", "pressure"), rolled, "1", "1 from the level at which the grounded robot rolled off the face (always 0 in the free mode)")},
        coords=coords(pairs, levels),
        attrs=attrs)


# ----------------------------------------------------------- results/curves/{contact}.nc

CURVES_ALLOW_NAN = ["breaks", "coefs", "cv_rmse"]


def curves_dataset(arrays: dict, pair: ArrayLike, axis: ArrayLike, attrs: dict) -> xr.Dataset:
    """The fitted curves of one contact case (workspace.fit.curves_to_arrays) as plain numbers."""
    units = {"breaks": "MPa", "coefs": "m", "degree": "1", "pmin": "MPa", "pmax": "MPa",
             "cv_rmse": "m", "kind": "", "model": ""}
    names = {"breaks": "piece boundaries of the piecewise polynomial (NaN padded)",
             "coefs": "coefficients of the polynomial in u = (p - breaks[piece]) / (1 MPa), "
                      "highest power first (NaN padded)",
             "degree": "polynomial degree", "pmin": "lowest pressure of the valid range",
             "pmax": "highest pressure of the valid range", "cv_rmse": "cross-validated RMSE of the fit",
             "kind": "polynomial or spline", "model": "chosen model"}
    from ..workspace.fit import ARRAY_DIMS
    data = {}
    for k, a in arrays.items():
        spec = {"long_name": names[k]}
        if units[k]:
            spec["units"] = units[k]
        data[k] = (ARRAY_DIMS[k], a, spec)
    return xr.Dataset(data, coords={"pair": pair, "axis": axis}, attrs=attrs)


def curves_document(contacts: dict) -> dict:
    """results/curves/curves.json: `contacts` maps a contact case to (face_nodes, pairs (n,),
    curves [n][3] of workspace.fit.Curve); plain numbers, evaluable in any language."""
    from ..workspace.fit import to_dict
    doc = {"units": {"pressure": "MPa", "cog": "m"},
           "evaluate": "find piece i with breaks[i] <= p < breaks[i+1] (clamp to the end pieces); "
                       "value = sum(coefs[i][k] * (p - breaks[i])**(deg - k))",
           "contacts": {}}
    for contact, (face_nodes, pairs, curves) in contacts.items():
        doc["contacts"][contact] = {
            "face_nodes": [int(n) for n in face_nodes],
            "pairs": {str(int(p)): {ax: to_dict(curves[i][j]) for j, ax in enumerate(AXES)}
                      for i, p in enumerate(pairs)}}
    return doc


# ------------------------------------------------------------------ results/workspace.nc

WORKSPACE_ALLOW_NAN = ["cog", "support", "margin", "tip_pressure"]


def workspace_dataset(levels: ArrayLike, ws: dict) -> xr.Dataset:
    """The 20-face workspace (workspace.mapping.map_workspace) with the face table."""
    var = datasets.var
    return xr.Dataset(
        {"cog": var(("face", "pair", "pressure", "axis"), ws["cog"], "m", "nominal centre of gravity in the face's support frame"),
         "support": var(("face", "pair", "pressure", "corner", "axis"), ws["support"], "m", "deformed support triangle in the face's support frame"),
         "margin": var(("face", "pair", "pressure"), ws["margin"], "m", "signed distance of the CoG projection to the support triangle boundary (positive inside)"),
         "tip_pressure": var(("face", "pair"), ws["tip_pressure"], "MPa", "least pressure at which the CoG projection leaves the triangle (NaN: never or not computed)"),
         "face_nodes": var(("face", "corner"), topo.FACES + 1, "1", "node numbers of the face's corners (support-frame corner order)"),
         "face_type": (("face",), topo.FACE_TYPES.astype(str), {"long_name": "equilateral (3 cables) or isosceles (2 cables and a gap)"}),
         "reference_corner": var(("face",), topo.FACE_REFERENCE + 1, "1", "corner of the reference vertex (the support frame's +y)")},
        coords={**coords(np.arange(1, topo.N_PAIRS + 1), levels),
                "face": ("face", np.arange(1, topo.N_FACES + 1), {"units": "1", "long_name": "face number"})})


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

    need = {"cog": ("face", "pair", "pressure", "axis"),
            "support": ("face", "pair", "pressure", "corner", "axis")}
    for name, dims in need.items():
        if name not in ds.variables:
            raise bad(f"no variable {name!r}")
        if set(ds[name].dims) != set(dims):
            raise bad(f"{name!r} has dimensions {ds[name].dims}, expected {dims}")
        if ds[name].dtype.kind != "f":
            raise bad(f"{name!r} has dtype {ds[name].dtype}, expected float")
    expect = {"face": np.arange(1, topo.N_FACES + 1), "axis": np.array(AXES), "corner": np.arange(1, 4)}
    for dim, values in expect.items():
        if dim not in ds.coords or ds.sizes[dim] != values.size or \
                not np.array_equal(np.sort(np.asarray(ds[dim].values).astype(values.dtype)), values):
            raise bad(f"coordinate {dim!r} must be {values.tolist()}")
    pairs = np.asarray(ds["pair"].values) if "pair" in ds.coords else np.array([])
    if pairs.size == 0 or pairs.dtype.kind not in "iu" or len(set(pairs.tolist())) != pairs.size \
            or pairs.min() < 1 or pairs.max() > topo.N_PAIRS:
        raise bad(f"coordinate 'pair' must be distinct pair numbers 1..{topo.N_PAIRS}, got {pairs.tolist()}")
    lv = np.asarray(ds["pressure"].values) if "pressure" in ds.coords else np.array([])
    if lv.ndim != 1 or lv.size == 0 or lv.dtype.kind != "f" or not np.all(np.isfinite(lv)) \
            or lv[0] <= 0 or np.any(np.diff(lv) <= 0):
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
    from ..locomotion.lookup import Workspace
    check_workspace(ds)
    order = {"face": np.arange(1, 21), "pair": np.arange(1, 13), "axis": ["x", "y", "z"]}
    sel = {k: v for k, v in order.items() if k in ds.dims}
    cog = ds["cog"].sel(sel).transpose("face", "pair", "pressure", "axis").values
    support = ds["support"].sel(sel).transpose("face", "pair", "pressure", "corner", "axis").values
    return Workspace.from_arrays(ds["pressure"].values, cog, support, datasets.strut_length(ds))


def read_workspace(path: str | os.PathLike) -> Workspace:
    """Read results/workspace.nc (or a file of the same contract) as a `Workspace`."""
    return workspace_from_dataset(datasets.read(path))
