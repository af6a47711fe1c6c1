"""Validation of the two-pair workspace (issue 10, item 1): numbers, verdicts, files.

(a) the nominal CoG of the check combinations at three grid corners against the independent
    free-mode static equilibrium (`physics.statics.equilibrium`), both canonical faces;
(b) the 20-face dataset against direct simulations of the check combinations on the check
    faces, run along the staircase the mapped numbers come from (`staircase_pairs`); the same
    simulation along the other order is reported as the path dependence of the nominal;
(c) reported: the superposition error (sum of the single-pair shifts of results/workspace.nc
    against the measured two-pair shift) and the combinations that tip at a lower equal pressure
    than the best single pair needs.
"""
from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike

from ..physics import frames, statics, topology as topo
from ..physics.params import Params
from ..physics.topology import CONTACTS
from ..workspace import two_pair as tp
from ..workspace.two_pair import TwoPairSetup
from .common import INFO, SKIP, status
from .summary import Verdict, label, mm

def check_statics(params: Params, contacts: Mapping[str, xr.Dataset], combos: np.ndarray, tol: float) -> tuple[np.ndarray, str]:
    """(a): difference (C, K, 3) m between the nominal and the static CoG of the K check
    combinations at grid points (top, top), (low, top), (top, low), NaN where not available."""
    diff = np.full((len(CONTACTS), len(combos), 3), np.nan)
    for ci, contact in enumerate(CONTACTS):
        ds = contacts.get(contact)
        if ds is None:
            continue
        lv, face, P = ds["pressure_a"].values, int(ds.attrs["face"]), ds.sizes["level_a"]
        for k, (a, b) in enumerate(combos):
            cog = ds["cog"].values[tp.combo_index(a, b)]
            for g, (i, j) in enumerate(((P - 1, P - 1), (0, P - 1), (P - 1, 0))):
                if np.isfinite(cog[i, j]).all():
                    p = np.zeros(topo.N_PAIRS)
                    p[[min(a, b) - 1, max(a, b) - 1]] = lv[i], lv[j]
                    diff[ci, k, g] = np.linalg.norm(statics.support_cog(statics.equilibrium(params, p), face)[0] - cog[i, j])
    return diff, SKIP if not np.isfinite(diff).any() else status(bool(np.nanmax(diff) <= tol))


def check_direct(params: Params, setup: TwoPairSetup, ws: xr.Dataset, faces: Sequence[int], combos: np.ndarray,
                 tol: float) -> tuple[np.ndarray, np.ndarray, str]:
    """(b): per check face (F,) and combination (K,) the largest CoG difference m of the mapped
    grid from a direct simulation along the same staircase, and along the other order (the
    path dependence), both with the staircase of `setup`; NaN where the dataset holds no numbers."""
    same, other = np.full((len(faces), len(combos)), np.nan), np.full((len(faces), len(combos)), np.nan)
    rows = np.array([tp.combo_index(a, b) for a, b in combos], int)
    for fi, f in enumerate(faces):
        mapped = ws["cog"].values[f - 1, rows]
        path = ws["staircase_pairs"].values[f - 1, rows]
        ok = np.flatnonzero(np.isfinite(mapped).all(axis=(1, 2, 3)))
        if not ok.size:
            continue
        order = np.concatenate([path[ok], path[ok][:, ::-1]])
        r = tp.sweep(params, f, order, setup)
        cog = r["cog"][:, topo.FACE_REFERENCE[f - 1]]
        for n, k in enumerate(ok):
            first = cog[n] if path[k, 0] < path[k, 1] else cog[n].swapaxes(0, 1)
            second = cog[n + ok.size] if path[k, 1] < path[k, 0] else cog[n + ok.size].swapaxes(0, 1)
            same[fi, k] = np.linalg.norm(first - mapped[k], axis=-1).max()
            other[fi, k] = np.linalg.norm(second - mapped[k], axis=-1).max()
    return same, other, SKIP if not np.isfinite(same).any() else status(bool(np.nanmax(same) <= tol))


def superposition(contacts: Mapping[str, xr.Dataset], single: xr.Dataset, strut_length: float) -> dict[str, np.ndarray]:
    """(c): per contact (C,), combination (66,) and grid point (P, P): the in-plane shift of
    the CoG from the unactuated one measured (m) and predicted by adding the two single pairs'
    shifts (results/workspace.nc, NaN at levels it lacks); the equal-pressure tip (MPa) of each
    combination and the least single-pair tip of the face (MPa). strut_length m: the robot's S."""
    P = next(iter(contacts.values())).sizes["level_a"]
    out = {k: np.full((len(CONTACTS), len(tp.COMBOS), P, P), np.nan) for k in ("measured", "predicted", "error")}
    out["tip"] = np.full((len(CONTACTS), len(tp.COMBOS)), np.nan)
    out["single_tip"] = np.full(len(CONTACTS), np.nan)
    out["single_pair"] = np.zeros(len(CONTACTS), int)
    S = strut_length
    for ci, contact in enumerate(CONTACTS):
        ds = contacts.get(contact)
        if ds is None:
            continue
        face, lv = int(ds.attrs["face"]), ds["pressure_a"].values
        rest = frames.rest_frame(face, S)[0][:2]
        sp = single["pressure"].values
        at = [np.flatnonzero(np.isclose(sp, p, atol=1e-9, rtol=0)) for p in lv]
        shift1 = np.full((topo.N_PAIRS, P, 2), np.nan)
        for i, k in enumerate(at):
            if k.size:
                shift1[:, i] = single["cog"].sel(face=face).transpose("pair", "pressure", "axis").values[:, k[0], :2] - rest
        cog = ds["cog"].values[..., :2] - rest
        pred = shift1[tp.COMBOS[:, 0] - 1][:, :, None] + shift1[tp.COMBOS[:, 1] - 1][:, None, :]
        out["measured"][ci] = np.linalg.norm(cog, axis=-1)
        out["predicted"][ci] = np.linalg.norm(pred, axis=-1)
        out["error"][ci] = np.linalg.norm(pred - cog, axis=-1)
        out["tip"][ci] = ds["tip_pressure"].values
        t1 = single["tip_pressure"].sel(face=face).values
        if np.isfinite(t1).any():
            out["single_tip"][ci], out["single_pair"][ci] = np.nanmin(t1), int(single["pair"].values[np.nanargmin(t1)])
    return out


def _verdicts(tol: float, faces, combos, a, a_st, same, other, b_st, sup) -> list[Verdict]:
    names = ", ".join(f"#{x}+#{y}" for x, y in combos)
    out = [Verdict("a", f"Two-pair nominal CoG = static equilibrium (scipy) for {names} at three grid corners, both contacts",
                   "no data" if a_st == SKIP else f"largest {mm(np.nanmax(a))} over {int(np.isfinite(a).sum())} cases",
                   f"under {mm(tol)}", a_st),
           Verdict("b", "Mapped two-pair workspace = direct simulation (same staircase) on faces " + ", ".join(label(f) for f in faces),
                   "no data" if b_st == SKIP else f"largest {mm(np.nanmax(same))} over {int(np.isfinite(same).sum())} combinations x faces",
                   f"under {mm(tol)}", b_st),
           Verdict("b2", "Path dependence: the same grid reached along the other staircase order (free robot's undamped wobble)",
                   "no data" if b_st == SKIP else f"largest {mm(np.nanmax(other))}", "reported, not a check", INFO)]
    for ci, contact in enumerate(CONTACTS):
        err, meas = sup["error"][ci], sup["measured"][ci]
        if not np.isfinite(err).any():
            continue
        c, i, j = np.unravel_index(int(np.nanargmax(err)), err.shape)
        a_, b_ = tp.COMBOS[c]
        ratio = meas / np.where(sup["predicted"][ci] > 0.01, sup["predicted"][ci], np.nan)  # shifts over 10 mm
        out.append(Verdict(f"c1 {contact}", f"Superposition of single-pair shifts against the measured two-pair shift, {contact}",
                           f"largest error {mm(err[c, i, j])} (#{a_}+#{b_}, shift {mm(meas[c, i, j])} measured, "
                           f"{mm(sup['predicted'][ci, c, i, j])} predicted); measured/predicted {np.nanmin(ratio):.2f}..{np.nanmax(ratio):.2f} "
                           f"where over 10 mm is predicted",
                           "reported", INFO))
        t, best = sup["tip"][ci], sup["single_tip"][ci]
        low = np.flatnonzero(t < best) if np.isfinite(best) else np.array([], int)
        low = low[np.argsort(t[low])]
        words = ", ".join(f"#{tp.COMBOS[k][0]}+#{tp.COMBOS[k][1]} {t[k]:.2f} MPa" for k in low[:6])
        out.append(Verdict(f"c2 {contact}", f"Combinations tipping at a lower equal pressure than the best single pair, {contact}",
                           f"{low.size} of {int(np.isfinite(t).sum())} tipping: {words or 'none'}" + ("; ..." if low.size > 6 else ""),
                           f"best single pair #{sup['single_pair'][ci]} at {best:.2f} MPa" if np.isfinite(best) else "no single pair tips",
                           INFO))
    return out


TITLE = "Validation of the two-pair workspace"


@dataclass(frozen=True)
class TwoPairCheck:
    """The numbers of checks (a)-(c) and their verdict rows: statics (C, K, 3) m, direct and
    path (F, K) m, superposition (`superposition`), the check combinations (K, 2), faces (F,),
    levels (P,) MPa and the tolerance m."""
    rows: list[Verdict]
    statics: np.ndarray
    direct: np.ndarray
    path: np.ndarray
    superposition: dict[str, np.ndarray]
    combos: np.ndarray
    faces: list[int]
    levels: np.ndarray
    tolerance: float


def validate(params: Params, setup: TwoPairSetup, contacts: Mapping[str, xr.Dataset], ws: xr.Dataset,
             single: xr.Dataset, strut_length: float, combos: ArrayLike, faces: Sequence[int],
             tolerance: float) -> TwoPairCheck:
    """(a)-(c) on the two-pair contact datasets (contact -> results/two_pair/{contact}.nc), the
    20-face dataset `ws` (results/workspace_two_pair.nc) and the single-pair workspace `single`
    (results/workspace.nc) of a robot of strut length S m, for the check `combos` (K, 2) on the
    check `faces`, goal `tolerance` m. A failed check does not raise."""
    combos = np.asarray(combos, int).reshape(-1, 2)
    faces = [int(f) for f in faces]
    a, a_st = check_statics(params, contacts, combos, tolerance)
    same, other, b_st = check_direct(params, setup, ws, faces, combos, tolerance)
    sup = superposition(contacts, single, strut_length)
    rows = _verdicts(tolerance, faces, combos, a, a_st, same, other, b_st, sup)
    return TwoPairCheck(rows, a, same, other, sup, combos, faces,
                        next(iter(contacts.values()))["pressure_a"].values, tolerance)
