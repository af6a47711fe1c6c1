"""Check (d) of the two-pair workspace (issue 34): every swept grid point's nominal CoG averaged
well enough, i.e. its estimated averaging error (`workspace.nominal.averaging_error`, held by
results/two_pair/{contact}.nc) within validate.averaging_tolerance, as check 7 asks of the
single-pair nominal; a failure names every combination and grid point above it. The mapped
combinations are images of the swept ones' samples: their error is the swept one's."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ..physics.topology import CONTACTS
from ..workspace import two_pair as tp
from ..workspace.nominal import TwoPairNominal
from .common import SKIP, status
from .words import Verdict, label, mm

MAX_NAMED = 12  # grid points named in the verdict; two_pair.nc holds them all


def check_averaging(contacts: Mapping[str, TwoPairNominal], tolerance: float) -> tuple[np.ndarray, str]:
    """(d): the estimated averaging error (C, 66, P, P) m of every contact case (contact ->
    `TwoPairNominal`, C = CONTACTS; NaN: mapped, no such case, or a file made before the
    estimate existed) and the status: every finite one at most `tolerance` m; not evaluated if
    none is finite."""
    P = len(next(iter(contacts.values())).levels)
    err = np.full((len(CONTACTS), len(tp.COMBOS), P, P), np.nan)
    for c, contact in enumerate(CONTACTS):
        n = contacts.get(contact)
        if n is not None and n.averaging_error is not None:
            err[c] = n.averaging_error
    return err, SKIP if not np.isfinite(err).any() else status(bool(np.nanmax(err) <= tolerance))


def above(
    error: np.ndarray, levels: np.ndarray, tolerance: float, faces: Mapping[str, int]
) -> list[tuple[str, int, int, float, float, float]]:
    """(face label, pair a, pair b, pressure of a MPa, of b MPa, error m) of every grid point of
    `error` (C, 66, P, P) m above `tolerance` m at `levels` (P,) MPa, largest first; `faces` maps
    a contact case to its face (1..20)."""
    c, k, i, j = np.nonzero(np.nan_to_num(error, nan=-1.0) > tolerance)
    rows = [
        (label(faces[CONTACTS[x]]), *(int(p) for p in tp.COMBOS[y]), float(levels[a]), float(levels[b]), e)
        for x, y, a, b, e in zip(c, k, i, j, error[c, k, i, j].tolist())
    ]
    return sorted(rows, key=lambda r: -r[5])


def averaging_verdict(
    error: np.ndarray, st: str, levels: np.ndarray, tolerance: float, faces: Mapping[str, int]
) -> Verdict:
    """The verdict row of (d) from `check_averaging`'s error and status, naming the grid points
    above `tolerance` m (`above`)."""
    stmt = (
        "Two-pair nominal CoG averaged well enough: the estimated error of every swept grid point's average "
        "(the oscillation left in its window, results/two_pair/{contact}.nc averaging_error)"
    )
    if st == SKIP:
        meas = "no estimate in the two-pair files (made before issue 34: rerun the two_pair stage)"
    else:
        c, k, i, j = (int(x) for x in np.unravel_index(int(np.nanargmax(error)), error.shape))
        a, b = tp.COMBOS[k]
        meas = (
            f"largest {mm(error[c, k, i, j])} (#{a} at {levels[i]:g} MPa + #{b} at {levels[j]:g} MPa on "
            f"{label(faces[CONTACTS[c]])}) over {int(np.isfinite(error).sum())} grid points"
        )
        bad = above(error, levels, tolerance, faces)
        if bad:
            named = [f"#{a} at {pa:g} + #{b} at {pb:g} MPa on {f} ({mm(e)})" for f, a, b, pa, pb, e in bad[:MAX_NAMED]]
            more = f" and {len(bad) - MAX_NAMED} more" if len(bad) > MAX_NAMED else ""
            meas += f"; {len(bad)} above the tolerance: " + ", ".join(named) + more
    return Verdict("d", stmt, meas, f"under {mm(tolerance)}", st)
