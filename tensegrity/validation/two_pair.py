"""Validation of the two-pair workspace (issue 10, item 1): numbers, verdicts, files.

(a) the nominal CoG of the check combinations at three grid corners against the independent
    free-mode static equilibrium (`physics.statics.equilibrium`), both canonical faces;
(b) the 20-face dataset against direct simulations of the check combinations on the check
    faces, run along the staircase the mapped numbers come from (`staircase_pairs`); the same
    simulation along the other order is reported as the path dependence of the nominal;
(c) reported: the superposition error (sum of the single-pair shifts of results/workspace.nc
    against the measured two-pair shift) and the combinations that tip at a lower equal pressure
    than the best single pair needs;
(d) every swept grid point's estimated averaging error within a tolerance (`two_pair_averaging`).
The files are read by `io.formats.two_pair` and `io.formats.workspace`; the checks take arrays,
`workspace.nominal.TwoPairNominal` and `workspace.lookup.Workspace`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike

from ..physics import statics
from ..physics import topology as topo
from ..physics.params import Params
from ..physics.topology import CONTACTS
from ..physics.twisted import TwistedString
from ..workspace import two_pair as tp
from ..workspace.lookup import Workspace
from ..workspace.nominal import TwoPairNominal
from ..workspace.two_pair import TwoPairSetup
from . import two_pair_averaging as tpa
from .common import INFO, SKIP, STATICS_IN_VOLTS, status
from .words import Verdict, label, mm


def check_statics(
    params: Params, contacts: Mapping[str, TwoPairNominal], combos: np.ndarray, tol: float
) -> tuple[np.ndarray, str]:
    """(a): difference (C, K, 3) m between the nominal and the static CoG of the K check
    combinations at grid points (top, top), (low, top), (top, low), NaN where not available;
    `contacts` maps a contact case to its two-pair nominal CoG (results/two_pair/{contact}.nc)."""
    diff = np.full((len(CONTACTS), len(combos), 3), np.nan)
    for ci, contact in enumerate(CONTACTS):
        n = contacts.get(contact)
        if n is None:
            continue
        lv, face, P = n.levels, n.face, len(n.levels)
        for k, (a, b) in enumerate(combos):
            cog = n.cog[tp.combo_index(a, b)]
            for g, (i, j) in enumerate(((P - 1, P - 1), (0, P - 1), (P - 1, 0))):
                if np.isfinite(cog[i, j]).all():
                    p = np.zeros(topo.N_PAIRS)
                    p[[min(a, b) - 1, max(a, b) - 1]] = lv[i], lv[j]
                    diff[ci, k, g] = np.linalg.norm(
                        statics.support_cog(statics.equilibrium(params, p), face)[0] - cog[i, j]
                    )
    return diff, SKIP if not np.isfinite(diff).any() else status(bool(np.nanmax(diff) <= tol))


def check_direct(
    params: Params,
    setup: TwoPairSetup,
    cog: np.ndarray,
    staircase: np.ndarray,
    faces: Sequence[int],
    combos: np.ndarray,
    tol: float,
    motors: TwistedString | None = None,
) -> tuple[np.ndarray, np.ndarray, str]:
    """(b): per check face (F,) and combination (K,) the largest CoG difference m of the mapped
    grid from a direct simulation along the same staircase, and along the other order (the
    path dependence), both with the staircase of `setup`; NaN where the grid holds no numbers.
    cog (20, 66, P, P, 3) m and staircase (20, 66, 2), the pairs in the order of the grid axes of
    the staircase the numbers come from, per face and combination (rows of `two_pair.COMBOS`):
    the 20-face two-pair workspace (results/workspace_two_pair.nc). With `motors`
    (`twisted.TwistedString`) the levels are motor voltages, V."""
    same, other = np.full((len(faces), len(combos)), np.nan), np.full((len(faces), len(combos)), np.nan)
    rows = np.array([tp.combo_index(a, b) for a, b in combos], int)
    for fi, f in enumerate(faces):
        mapped = cog[f - 1, rows]
        path = staircase[f - 1, rows]
        ok = np.flatnonzero(np.isfinite(mapped).all(axis=(1, 2, 3)))
        if not ok.size:
            continue
        order = np.concatenate([path[ok], path[ok][:, ::-1]])
        r = tp.sweep(params, f, order, setup, motors)
        sim = r["cog"][:, topo.FACE_REFERENCE[f - 1]]
        for n, k in enumerate(ok):
            first = sim[n] if path[k, 0] < path[k, 1] else sim[n].swapaxes(0, 1)
            second = sim[n + ok.size] if path[k, 1] < path[k, 0] else sim[n + ok.size].swapaxes(0, 1)
            same[fi, k] = np.linalg.norm(first - mapped[k], axis=-1).max()
            other[fi, k] = np.linalg.norm(second - mapped[k], axis=-1).max()
    return same, other, SKIP if not np.isfinite(same).any() else status(bool(np.nanmax(same) <= tol))


def superposition(
    contacts: Mapping[str, TwoPairNominal], single: Workspace, single_tip: np.ndarray
) -> dict[str, np.ndarray]:
    """(c): per contact (C,), combination (66,) and grid point (P, P): the in-plane shift of
    the CoG from the unactuated one (the robot's of `single`) measured (m) and predicted by
    adding the two single pairs' shifts of the single-pair workspace `single`
    (results/workspace.nc, NaN at levels it lacks); the equal-pressure tip (MPa) of each
    combination and the least single-pair tip of the face (MPa) among `single_tip` (20, 12) MPa,
    the single-pair workspace's tipping pressures (NaN: never)."""
    P = len(next(iter(contacts.values())).levels)
    out = {k: np.full((len(CONTACTS), len(tp.COMBOS), P, P), np.nan) for k in ("measured", "predicted", "error")}
    out["tip"] = np.full((len(CONTACTS), len(tp.COMBOS)), np.nan)
    out["single_tip"] = np.full(len(CONTACTS), np.nan)
    out["single_pair"] = np.zeros(len(CONTACTS), int)
    for ci, contact in enumerate(CONTACTS):
        n = contacts.get(contact)
        if n is None:
            continue
        face, lv = n.face, n.levels
        rest = single.rest_cog[face - 1][:2]
        sp = single.levels
        at = [np.flatnonzero(np.isclose(sp, p, atol=1e-9, rtol=0)) for p in lv]
        shift1 = np.full((topo.N_PAIRS, P, 2), np.nan)
        for i, k in enumerate(at):
            if k.size:
                shift1[:, i] = single.cog[face - 1][:, k[0], :2] - rest
        cog = n.cog[..., :2] - rest
        pred = shift1[tp.COMBOS[:, 0] - 1][:, :, None] + shift1[tp.COMBOS[:, 1] - 1][:, None, :]
        out["measured"][ci] = np.linalg.norm(cog, axis=-1)
        out["predicted"][ci] = np.linalg.norm(pred, axis=-1)
        out["error"][ci] = np.linalg.norm(pred - cog, axis=-1)
        out["tip"][ci] = n.tip_pressure
        t1 = np.asarray(single_tip)[face - 1]
        if np.isfinite(t1).any():
            out["single_tip"][ci], out["single_pair"][ci] = np.nanmin(t1), int(np.nanargmin(t1)) + 1
    return out


def _verdicts(tol: float, faces, combos, a, a_st, same, other, b_st, sup) -> list[Verdict]:
    names = ", ".join(f"#{x}+#{y}" for x, y in combos)
    out = [
        Verdict(
            "a",
            f"Two-pair nominal CoG = static equilibrium (scipy) for {names} at three grid corners, both contacts",
            "no data" if a_st == SKIP else f"largest {mm(np.nanmax(a))} over {int(np.isfinite(a).sum())} cases",
            f"under {mm(tol)}",
            a_st,
        ),
        Verdict(
            "b",
            "Mapped two-pair workspace = direct simulation (same staircase) on faces "
            + ", ".join(label(f) for f in faces),
            "no data"
            if b_st == SKIP
            else f"largest {mm(np.nanmax(same))} over {int(np.isfinite(same).sum())} combinations x faces",
            f"under {mm(tol)}",
            b_st,
        ),
        Verdict(
            "b2",
            "Path dependence: the same grid reached along the other staircase order (free robot's undamped wobble)",
            "no data" if b_st == SKIP else f"largest {mm(np.nanmax(other))}",
            "reported, not a check",
            INFO,
        ),
    ]
    for ci, contact in enumerate(CONTACTS):
        err, meas = sup["error"][ci], sup["measured"][ci]
        if not np.isfinite(err).any():
            continue
        c, i, j = np.unravel_index(int(np.nanargmax(err)), err.shape)
        a_, b_ = tp.COMBOS[c]
        ratio = meas / np.where(sup["predicted"][ci] > 0.01, sup["predicted"][ci], np.nan)  # shifts over 10 mm
        out.append(
            Verdict(
                f"c1 {contact}",
                f"Superposition of single-pair shifts against the measured two-pair shift, {contact}",
                f"largest error {mm(err[c, i, j])} (#{a_}+#{b_}, shift {mm(meas[c, i, j])} measured, "
                f"{mm(sup['predicted'][ci, c, i, j])} predicted); "
                f"measured/predicted {np.nanmin(ratio):.2f}..{np.nanmax(ratio):.2f} "
                f"where over 10 mm is predicted",
                "reported",
                INFO,
            )
        )
        t, best = sup["tip"][ci], sup["single_tip"][ci]
        low = np.flatnonzero(t < best) if np.isfinite(best) else np.array([], int)
        low = low[np.argsort(t[low])]
        words = ", ".join(f"#{tp.COMBOS[k][0]}+#{tp.COMBOS[k][1]} {t[k]:.2f} MPa" for k in low[:6])
        out.append(
            Verdict(
                f"c2 {contact}",
                f"Combinations tipping at a lower equal pressure than the best single pair, {contact}",
                f"{low.size} of {int(np.isfinite(t).sum())} tipping: {words or 'none'}"
                + ("; ..." if low.size > 6 else ""),
                f"best single pair #{sup['single_pair'][ci]} at {best:.2f} MPa"
                if np.isfinite(best)
                else "no single pair tips",
                INFO,
            )
        )
    return out


TITLE = "Validation of the two-pair workspace"


@dataclass(frozen=True)
class TwoPairCheck:
    """The numbers of checks (a)-(d) and their verdict rows: statics (C, K, 3) m, direct and
    path (F, K) m, superposition (`superposition`), the check combinations (K, 2), faces (F,),
    levels (P,) MPa and the tolerance m; the averaging error of (d) and its tolerance m."""

    rows: list[Verdict]
    statics: np.ndarray
    direct: np.ndarray
    path: np.ndarray
    superposition: dict[str, np.ndarray]
    combos: np.ndarray
    faces: list[int]
    levels: np.ndarray
    tolerance: float
    averaging: np.ndarray | None = None  # (C, 66, P, P) m, check (d); None: not asked for
    averaging_tolerance: float = float("nan")  # m, of (d)


def validate(
    params: Params,
    setup: TwoPairSetup,
    contacts: Mapping[str, TwoPairNominal],
    cog: np.ndarray,
    staircase: np.ndarray,
    single: Workspace,
    single_tip: np.ndarray,
    *,
    combos: ArrayLike,
    faces: Sequence[int],
    tolerance: float,
    averaging_tolerance: float | None = None,
    motors: TwistedString | None = None,
) -> TwoPairCheck:
    """(a)-(c) on the two-pair nominal CoG of the contact cases (contact -> `TwoPairNominal`,
    results/two_pair/{contact}.nc), the 20-face grid cog and staircase (`check_direct`,
    results/workspace_two_pair.nc) and the single-pair workspace `single` with its tipping
    pressures `single_tip` (20, 12) MPa (results/workspace.nc), for the check `combos` (K, 2) on
    the check `faces`, goal `tolerance` m; (d) against `averaging_tolerance` m if given. A failed
    check does not raise. With `motors` (the twisted-string actuator; the files in volts) (b)-(d)
    are evaluated in volts and (a) is not (`STATICS_IN_VOLTS`)."""
    combos = np.asarray(combos, int).reshape(-1, 2)
    faces = [int(f) for f in faces]
    if motors is None:
        a, a_st = check_statics(params, contacts, combos, tolerance)
    else:
        a, a_st = np.full((len(CONTACTS), len(combos), 3), np.nan), SKIP
    same, other, b_st = check_direct(params, setup, cog, staircase, faces, combos, tolerance, motors)
    sup = superposition(contacts, single, single_tip)
    rows = _verdicts(tolerance, faces, combos, a, a_st, same, other, b_st, sup)
    if motors is not None:
        rows[0] = replace(rows[0], measured=STATICS_IN_VOLTS)
    levels, err, tol_d = next(iter(contacts.values())).levels, None, float("nan")
    if averaging_tolerance is not None:
        tol_d = float(averaging_tolerance)
        err, d_st = tpa.check_averaging(contacts, averaging_tolerance)
        on = {c: n.face for c, n in contacts.items()}
        rows.append(tpa.averaging_verdict(err, d_st, levels, averaging_tolerance, on))
    return TwoPairCheck(rows, a, same, other, sup, combos, faces, levels, tolerance, err, tol_d)
