"""Workspace queries from the exported curves: the nominal CoG and margin of any face, pair and
pressure (docs/design.md §5: the curves of results/curves/curves.json, `io.formats.read_curves`,
and the workspace of results/workspace.nc, `io.formats.read_workspace`)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..physics import frames
from ..physics import topology as topo
from . import fit, mapping
from .lookup import Workspace

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


def curve_cog(curves: dict, face: int | Sequence[int], pair: int, pressure: float) -> tuple[np.ndarray, str, int]:
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
        unit = curves.get("units", {}).get("pressure", "MPa")  # V: a document in volts (issue 31)
        what = "pressure" if unit == "MPa" else "motor voltage"
        raise ValueError(f"{what} {pressure} {unit} is outside the fitted range {lo}..{hi} {unit}")
    cog = np.array([float(fit.evaluate(per_axis[a], pressure)) for a in AXES]) * diag
    return cog, kind, src


def support_at(workspace: Workspace, face: int, pair: int, pressure: float) -> np.ndarray:
    """Deformed support triangle (3, 3) m of `pair` on `face` interpolated linearly in pressure
    (MPa) from the workspace, starting from the symmetric triangle at 0 MPa."""
    p = workspace.pressures
    s = np.concatenate([workspace.rest_support[face - 1][None], workspace.support[face - 1, pair - 1]])
    return np.stack([[np.interp(pressure, p, s[:, c, a]) for a in range(3)] for c in range(3)])


def query(
    curves: dict,
    workspace: Workspace,
    face: int | Sequence[int],
    pair: int,
    pressure: float,
    wsname: str = "<workspace>",
) -> Answer:
    """Nominal CoG, deformed triangle and margin of `pair` at `pressure` MPa on `face`, from the
    curves document `curves` and the workspace (read and checked by `io.formats`); at 0 MPa the
    unactuated symmetric robot (the workspace's rest state, the 0 MPa point of every curve). A NaN
    or out-of-range answer (a pair the workspace lacks, corrupted inputs) raises ValueError naming
    `wsname`, the workspace's file."""
    face, pair = topo.face_number(face), topo.check_pair(pair)
    if pressure == 0:
        kind, src = str(topo.FACE_TYPES[face - 1]), int(mapping.face_map(face)[0][pair - 1]) + 1
        rest, sup = workspace.rest_cog[face - 1], workspace.rest_support[face - 1]
        return Answer(
            face, pair, 0.0, rest.copy(), sup.copy(), float(frames.margin_2d(rest[:2], sup[:, :2])), kind, src
        )
    cog, kind, src = curve_cog(curves, face, pair, float(pressure))
    sup = support_at(workspace, face, pair, float(pressure))
    margin = float(frames.margin_2d(cog[:2], sup[:, :2]))
    S = workspace.strut_length
    if not np.all(np.isfinite(sup)):
        raise ValueError(f"workspace {wsname!r} has no support triangle for pair #{pair} on face {face} (not computed)")
    if not (np.all(np.isfinite(cog)) and np.max(np.abs(cog)) < S and np.isfinite(margin) and abs(margin) < S):
        raise ValueError(
            f"the curves give CoG {cog.tolist()} m, margin {margin} m for pair #{pair} on face "
            f"{face} at {pressure} MPa: not within the strut length {S} m (corrupted curves "
            f"or workspace {wsname!r}?)"
        )
    return Answer(face, pair, float(pressure), cog, sup, margin, kind, src)
