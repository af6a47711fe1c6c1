"""Workspace queries from the exported curves: the nominal CoG and margin of any face, pair and
pressure (docs/design.md §5: results/curves/curves.json and results/workspace.nc)."""
from __future__ import annotations

import json
import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..io.datasets import strut_length
from . import fit
from ..physics import frames, topology as topo
from . import mapping

if TYPE_CHECKING:
    import xarray as xr

AXES = ("x", "y", "z")


@dataclass(frozen=True)
class Answer:
    """cog (3,) m and support (3, 3) m in the face's support frame; margin m (positive: the CoG
    projection is inside the triangle); source_pair: the canonical pair whose curve was used."""
    face: int
    pair: int
    pressure: float
    cog: np.ndarray
    support: np.ndarray
    margin: float
    contact: str
    source_pair: int


def load_curves(path: str | os.PathLike) -> dict:
    """The curves document written by the workflow (results/curves/curves.json), checked
    (`check_curves`): a file that is not valid JSON or breaks the contract raises ValueError
    naming it."""
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


def curve_cog(curves: dict, face: int | Sequence[int], pair: int,
              pressure: float) -> tuple[np.ndarray, str, int]:
    """CoG (3,) m of `pair` at `pressure` MPa in the support frame of `face`, from the fitted
    curve of the canonical face of its kind mapped by symmetry."""
    face, pair = topo.face_number(face), topo.check_pair(pair)
    kind = str(topo.FACE_TYPES[face - 1])
    if kind not in curves["contacts"]:
        raise ValueError(f"the curves hold no {kind} contact case (face {face} is {kind})")
    pair_src, _, diag = mapping.face_map(face)
    src = int(pair_src[pair - 1]) + 1
    per_axis = curves["contacts"][kind]["pairs"].get(str(src))
    if per_axis is None:
        raise ValueError(f"pair #{pair} on face {face} maps to canonical pair #{src}, which was not swept")
    lo, hi = per_axis["x"]["pmin"], per_axis["x"]["pmax"]
    if not (np.isfinite(pressure) and lo <= pressure <= hi):
        raise ValueError(f"pressure {pressure} MPa is outside the fitted range {lo}..{hi} MPa")
    cog = np.array([float(fit.evaluate(per_axis[a], pressure)) for a in AXES]) * diag
    return cog, kind, src


def support_at(workspace: xr.Dataset, face: int, pair: int, pressure: float) -> np.ndarray:
    """Deformed support triangle (3, 3) m interpolated linearly in pressure from workspace.nc,
    starting from the symmetric triangle at 0 MPa."""
    levels = workspace["pressure"].values
    sup = workspace["support"].sel(face=face, pair=pair).values
    rest = frames.rest_frame(face, strut_length(workspace))[1]
    p = np.concatenate([[0.0], levels])
    s = np.concatenate([rest[None], sup])
    return np.stack([[np.interp(pressure, p, s[:, c, a]) for a in range(3)] for c in range(3)])


def query(curves: dict, workspace: xr.Dataset, face: int | Sequence[int], pair: int,
          pressure: float) -> Answer:
    """Nominal CoG, deformed triangle and margin of `pair` at `pressure` MPa on `face`.
    `workspace` is checked first (`io.formats.check_workspace`); a NaN or out-of-range answer
    (a pair the workspace lacks, corrupted inputs) raises ValueError naming the files."""
    from ..io.formats import check_workspace
    face, pair = topo.face_number(face), topo.check_pair(pair)
    check_workspace(workspace)
    cog, kind, src = curve_cog(curves, face, pair, float(pressure))
    sup = support_at(workspace, face, pair, float(pressure))
    margin = float(frames.margin_2d(cog[:2], sup[:, :2]))
    S = strut_length(workspace)
    wsname = workspace.encoding.get("source", "<workspace>")
    if not np.all(np.isfinite(sup)):
        raise ValueError(f"workspace {wsname!r} has no support triangle for pair #{pair} on face {face} "
                         "(not computed)")
    if not (np.all(np.isfinite(cog)) and np.max(np.abs(cog)) < S and np.isfinite(margin) and abs(margin) < S):
        raise ValueError(f"the curves give CoG {cog.tolist()} m, margin {margin} m for pair #{pair} on face "
                         f"{face} at {pressure} MPa: not within the strut length {S} m (corrupted curves "
                         f"or workspace {wsname!r}?)")
    return Answer(face, pair, float(pressure), cog, sup, margin, kind, src)
