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
    """The curves document written by the workflow (results/curves/curves.json)."""
    return json.loads(Path(path).read_text())


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
    """Nominal CoG, deformed triangle and margin of `pair` at `pressure` MPa on `face`."""
    face, pair = topo.face_number(face), topo.check_pair(pair)
    cog, kind, src = curve_cog(curves, face, pair, float(pressure))
    sup = support_at(workspace, face, pair, float(pressure))
    margin = float(frames.margin_2d(cog[:2], sup[:, :2]))
    return Answer(face, pair, float(pressure), cog, sup, margin, kind, src)
