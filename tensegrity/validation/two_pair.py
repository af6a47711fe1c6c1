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

import os
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
import xarray as xr

from ..io import datasets
from ..io.config import params_from_config
from ..physics import frames, statics, topology as topo
from ..physics.params import Params
from ..workspace import two_pair as tp
from . import pages
from .common import CONTACTS, INFO, SKIP, status
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


def check_direct(cfg: Mapping, ws: xr.Dataset, faces: Sequence[int], combos: np.ndarray, tol: float) -> tuple[np.ndarray, np.ndarray, str]:
    """(b): per check face (F,) and combination (K,) the largest CoG difference m of the mapped
    grid from a direct simulation along the same staircase, and along the other order (the
    path dependence); NaN where the dataset holds no numbers."""
    s, params = cfg["two_pair"], params_from_config(cfg)
    same, other = np.full((len(faces), len(combos)), np.nan), np.full((len(faces), len(combos)), np.nan)
    rows = np.array([tp.combo_index(a, b) for a, b in combos], int)
    for fi, f in enumerate(faces):
        mapped = ws["cog"].values[f - 1, rows]
        path = ws["staircase_pairs"].values[f - 1, rows]
        ok = np.flatnonzero(np.isfinite(mapped).all(axis=(1, 2, 3)))
        if not ok.size:
            continue
        order = np.concatenate([path[ok], path[ok][:, ::-1]])
        r = tp.sweep(params, f, order, s["levels"], s["hold"], s["discard"], cfg["sim"]["dt"], s["record_every"])
        cog = r["cog"][:, topo.FACE_REFERENCE[f - 1]]
        for n, k in enumerate(ok):
            first = cog[n] if path[k, 0] < path[k, 1] else cog[n].swapaxes(0, 1)
            second = cog[n + ok.size] if path[k, 1] < path[k, 0] else cog[n + ok.size].swapaxes(0, 1)
            same[fi, k] = np.linalg.norm(first - mapped[k], axis=-1).max()
            other[fi, k] = np.linalg.norm(second - mapped[k], axis=-1).max()
    return same, other, SKIP if not np.isfinite(same).any() else status(bool(np.nanmax(same) <= tol))


def superposition(contacts: Mapping[str, xr.Dataset], single: xr.Dataset) -> dict[str, np.ndarray]:
    """(c): per contact (C,), combination (66,) and grid point (P, P): the in-plane shift of
    the CoG from the unactuated one measured (m) and predicted by adding the two single pairs'
    shifts (results/workspace.nc, NaN at levels it lacks); the equal-pressure tip (MPa) of each
    combination and the least single-pair tip of the face (MPa)."""
    P = next(iter(contacts.values())).sizes["level_a"]
    out = {k: np.full((len(CONTACTS), len(tp.COMBOS), P, P), np.nan) for k in ("measured", "predicted", "error")}
    out["tip"] = np.full((len(CONTACTS), len(tp.COMBOS)), np.nan)
    out["single_tip"] = np.full(len(CONTACTS), np.nan)
    out["single_pair"] = np.zeros(len(CONTACTS), int)
    S = datasets.strut_length(single)
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


def run_stage(cfg: Mapping, contact_paths: Sequence[str | os.PathLike], two_pair_path: str | os.PathLike,
              workspace_path: str | os.PathLike, nc_path: str | os.PathLike, md_path: str | os.PathLike,
              html_path: str | os.PathLike | None = None) -> list[Path]:
    """Run (a)-(c) and write the numbers (netCDF), the verdicts (Markdown, HTML). A failed
    check does not raise."""
    s = cfg["two_pair"]
    tol, faces = float(s["tolerance"]), [int(f) for f in s["check_faces"]]
    combos = np.array(s["check_combos"], int).reshape(-1, 2)
    contacts = {str(ds.attrs["contact"]): ds for ds in (datasets.read(p) for p in contact_paths)}
    ws, single = datasets.read(two_pair_path), datasets.read(workspace_path)
    a, a_st = check_statics(params_from_config(cfg), contacts, combos, tol)
    same, other, b_st = check_direct(cfg, ws, faces, combos, tol)
    sup = superposition(contacts, single)
    rows = _verdicts(tol, faces, combos, a, a_st, same, other, b_st, sup)
    for r in rows:
        print(f"  {r.id} {r.status}: {r.measured}", flush=True)
    var = datasets.var
    P = sup["error"].shape[-1]
    ds = xr.Dataset({
        "statics_difference": var(("contact", "check", "point"), a, "m", "nominal minus static-equilibrium CoG distance (a)"),
        "direct_difference": var(("face", "check"), same, "m", "largest CoG distance of the mapped grid from a direct simulation along the same staircase (b)"),
        "path_difference": var(("face", "check"), other, "m", "largest CoG distance of the mapped grid from a direct simulation along the other staircase order (b2)"),
        "check_pairs": var(("check", "member"), combos, "1", "actuator pairs of the check combinations"),
        "superposition_error": var(("contact", "combo", "level_a", "level_b"), sup["error"], "m", "in-plane distance of the summed single-pair shifts from the measured two-pair CoG shift (c)"),
        "measured_shift": var(("contact", "combo", "level_a", "level_b"), sup["measured"], "m", "in-plane CoG shift from the unactuated robot, two pairs"),
        "tip_pressure": var(("contact", "combo"), sup["tip"], "MPa", "least equal pressure of both pairs at which the CoG leaves the triangle"),
        "single_tip_pressure": var(("contact",), sup["single_tip"], "MPa", "least tipping pressure of any single pair"),
        "pressure_a": var(("level_a",), next(iter(contacts.values()))["pressure_a"].values, "MPa", "muscle pressure of the first pair"),
        "verdict": (("verdict",), np.array([f"{r.id}: {r.status}: {r.measured}" for r in rows]), {"long_name": "verdicts"})},
        coords={"contact": ("contact", list(CONTACTS), {"long_name": "contact case"}),
                "face": ("face", faces, {"units": "1", "long_name": "face number"}),
                "check": ("check", np.arange(1, len(combos) + 1), {"units": "1", "long_name": "check combination"}),
                "member": ("member", [1, 2], {"units": "1", "long_name": "member of the combination"}),
                "point": ("point", [1, 2, 3], {"units": "1", "long_name": "grid corner: (top, top), (low, top), (top, low)"}),
                "combo": ("combo", np.arange(1, len(tp.COMBOS) + 1), {"units": "1", "long_name": "combination number"}),
                "level_a": ("level_a", np.arange(1, P + 1), {"units": "1", "long_name": "level index of the first pair"}),
                "level_b": ("level_b", np.arange(1, P + 1), {"units": "1", "long_name": "level index of the second pair"})})
    allow = ["statics_difference", "direct_difference", "path_difference", "superposition_error", "measured_shift",
             "tip_pressure", "single_tip_pressure"]
    prov = {}
    for p in [*contact_paths, two_pair_path, workspace_path]:
        prov.update(datasets.provenance_config(p))
    note = (f"Levels {', '.join(f'{x:g}' for x in s['levels'])} MPa held "
            f"{s['hold']:g} s (nominal: mean after {s['discard']:g} s), free mode. Every number: two_pair.nc.")
    lead = [pages.counts([r.status for r in rows]), note]
    out = [datasets.write(ds, nc_path, prov | dict(cfg), "Validation of the two-pair workspace", stage="validate_two_pair", allow_nan=allow),
           datasets.write_text(md_path, pages.markdown(TITLE, lead, [pages.verdict_table(rows)]))]
    if html_path:
        out.append(datasets.write_text(html_path, pages.html_page(TITLE, lead, [pages.verdict_table(rows)])))
    return out
