"""results/curves/{contact}.nc and results/curves/curves.json: the fitted curves as plain numbers
(docs/datasets.md), and the reader of curves.json with its contract check."""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike

from ...physics import topology as topo
from . import actuation
from .common import AXES

CURVES_ALLOW_NAN = ["breaks", "coefs", "cv_rmse", "max_residual"]


def curves_dataset(arrays: dict, pair: ArrayLike, axis: ArrayLike, attrs: dict) -> xr.Dataset:
    """The fitted curves of one contact case (workspace.fit.curves_to_arrays) as plain numbers."""
    units = {
        "breaks": "MPa",
        "coefs": "m",
        "degree": "1",
        "pmin": "MPa",
        "pmax": "MPa",
        "cv_rmse": "m",
        "max_residual": "m",
        "kind": "",
        "model": "",
    }
    names = {
        "breaks": "piece boundaries of the piecewise polynomial (NaN padded)",
        "coefs": "coefficients of the polynomial in u = (p - breaks[piece]) / (1 MPa), "
        "highest power first (NaN padded)",
        "degree": "polynomial degree",
        "pmin": "lowest pressure of the valid range",
        "pmax": "highest pressure of the valid range",
        "cv_rmse": "cross-validated RMSE of the fit",
        "max_residual": "largest absolute difference between the curve and the nominal CoG it was fitted to",
        "kind": "polynomial or spline",
        "model": "chosen model",
    }
    from ...workspace.fit import ARRAY_DIMS

    data = {}
    for k, a in arrays.items():
        spec = {"long_name": names[k]}
        if units[k]:
            spec["units"] = units[k]
        data[k] = (ARRAY_DIMS[k], a, spec)
    return xr.Dataset(data, coords={"pair": pair, "axis": axis}, attrs=attrs)


def curves_document(contacts: dict, config: dict | None = None, kind: str = actuation.PNEUMATIC) -> dict:
    """results/curves/curves.json: `contacts` maps a contact case to (face_nodes, pairs (n,),
    curves [n][3] of workspace.fit.Curve); plain numbers, evaluable in any language; `config`:
    the configuration the curves were made with (their files' provenance; `io.provenance`).
    `kind`: the actuator; twisted_string writes "units": {"pressure": "V"} and "actuator"."""
    from ...workspace.fit import to_dict

    doc = {
        "units": {"pressure": "MPa", "cog": "m"},
        "evaluate": "find piece i with breaks[i] <= p < breaks[i+1] (clamp to the end pieces); "
        "value = sum(coefs[i][k] * (p - breaks[i])**(deg - k))",
        "max_residual": "per curve, the largest |value(p) - nominal CoG| over the levels it was fitted to (m): "
        "the curve's own error at its data; cv_rmse (m) estimates it between the levels",
        "contacts": {},
    }
    actuation.document(doc, kind)
    if config is not None:
        doc["config"] = config
    for contact, (face_nodes, pairs, curves) in contacts.items():
        doc["contacts"][contact] = {
            "face_nodes": [int(n) for n in face_nodes],
            "pairs": {
                str(int(p)): {ax: to_dict(curves[i][j]) for j, ax in enumerate(AXES)} for i, p in enumerate(pairs)
            },
        }
    return doc


def read_curves(path: str | os.PathLike) -> dict:
    """The curves document results/curves/curves.json, checked (`check_curves`): a file that is
    not valid JSON or breaks the contract raises ValueError naming it."""
    try:
        doc = json.loads(Path(path).read_text())
    except (UnicodeDecodeError, json.JSONDecodeError) as e:
        raise ValueError(f"curves {os.fspath(path)!r} is not valid JSON (corrupted?): {e}") from e
    check_curves(doc, path)
    return doc


def check_curves(doc: dict, source: str | os.PathLike = "<curves>") -> None:
    """Raise ValueError naming `source` unless `doc` has the contract of curves.json: per contact
    case and pair an x, y and z curve whose `breaks` are finite and strictly increasing MPa,
    `coefs` finite with one row per piece, and pmin <= pmax within the breaks."""
    src = os.fspath(source)

    def bad(what: str) -> ValueError:
        return ValueError(f"curves {src!r} are not valid curves (corrupted?): {what}")

    if not isinstance(doc, dict) or not isinstance(doc.get("contacts"), dict):
        raise bad("no 'contacts' mapping")
    for contact, case in doc["contacts"].items():
        if not isinstance(case, dict) or not isinstance(case.get("pairs"), dict):
            raise bad(f"contact {contact!r} has no 'pairs' mapping")
        for pair, per_axis in case["pairs"].items():
            if not (isinstance(per_axis, dict) and pair.isdigit() and 1 <= int(pair) <= topo.N_PAIRS):
                raise bad(f"contact {contact!r}: pair key {pair!r} is not 1..{topo.N_PAIRS}")
            for ax in AXES:
                where = f"contact {contact!r}, pair {pair}, axis {ax}"
                c = per_axis.get(ax)
                try:
                    b = np.asarray(c["breaks"], float)
                    k = np.asarray(c["coefs"], float)
                    lo, hi = float(c["pmin"]), float(c["pmax"])
                except (TypeError, KeyError, ValueError) as e:
                    raise bad(f"{where}: missing or malformed breaks, coefs, pmin, pmax ({e})") from e
                if b.ndim != 1 or b.size < 2 or not np.all(np.isfinite(b)) or np.any(np.diff(b) <= 0):
                    raise bad(f"{where}: breaks must be finite and strictly increasing")
                if k.ndim != 2 or k.shape[0] != b.size - 1 or k.shape[1] < 1 or not np.all(np.isfinite(k)):
                    raise bad(f"{where}: coefs must be {b.size - 1} rows of finite numbers")
                if not (np.isfinite(lo) and np.isfinite(hi) and b[0] - 1e-9 <= lo <= hi <= b[-1] + 1e-9):
                    raise bad(f"{where}: pmin {lo}, pmax {hi} not within the breaks {b[0]}..{b[-1]}")
