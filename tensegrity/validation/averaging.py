"""Check 7 (issue 34): the nominal CoG of every pair at every level averaged well enough, i.e. its
estimated averaging error (`workspace.nominal.averaging_error`, held by the nominal files) within
validate.averaging_tolerance; a failure names every pair and level above it. Its numbers
(`AveragingResult`) and its words (`averaging_verdicts`)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..physics import topology as topo
from ..physics.topology import CONTACTS
from ..workspace.nominal import Nominal
from .common import N_CONTACTS, SKIP, Result, status
from .nominals import common_levels
from .words import Verdict, label, largest_case, mm

MAX_NAMED = 12  # levels named in the verdict; validation.nc holds them all


@dataclass(frozen=True)
class AveragingResult(Result):
    """Numbers of check 7 on the contact cases C = CONTACTS, all N_PAIRS pairs and the P `levels`
    MPa: tolerance m, faces (contact -> face 1..20 of the cases with an estimate) and error
    (C, N_PAIRS, P) m, the estimated averaging error of the nominal files (NaN: not swept, rolled
    off, or a file made before the estimate existed); status of verdict 7."""

    levels: np.ndarray
    tolerance: float
    faces: dict[str, int]
    error: np.ndarray
    statics: bool = False  # the nominal files hold static equilibria: nothing averaged

    def above(self) -> list[tuple[str, int, float, float]]:
        """(contact, pair 1..12, level MPa, error m) of every case above the tolerance, largest
        error first."""
        c, p, k = np.nonzero(np.nan_to_num(self.error, nan=-1.0) > self.tolerance)
        rows = [
            (CONTACTS[i], int(j) + 1, float(self.levels[n]), float(self.error[i, j, n])) for i, j, n in zip(c, p, k)
        ]
        return sorted(rows, key=lambda r: -r[3])


def check_averaging(nominals: Mapping[str, Nominal], tolerance: float) -> AveragingResult:
    """The estimated averaging error of every pair and level of the nominal CoG files (contact ->
    `Nominal`) against `tolerance` m; not evaluated if no file holds an estimate, or if the
    files were made by statics (`Nominal.method`: nothing was averaged, their 0 would pass)."""
    levels = common_levels(nominals)
    err = np.full((N_CONTACTS, topo.N_PAIRS, levels.size), np.nan)
    faces = {}
    statics_made = any(n.method == "statics" for n in nominals.values())
    for c, contact in enumerate(CONTACTS):
        n = nominals.get(contact)
        if n is not None and n.averaging_error is not None and not statics_made:
            err[c], faces[contact] = n.averaging_error, n.face
    ok = SKIP if not np.isfinite(err).any() else status(bool(np.nanmax(err) <= tolerance))
    return AveragingResult(
        status={"7": ok}, levels=levels, tolerance=float(tolerance), faces=faces, error=err, statics=statics_made
    )


def averaging_verdicts(r: AveragingResult) -> list[Verdict]:
    """Check 7: every level's averaging error under the tolerance, naming the levels above it."""
    stmt = (
        "Nominal CoG averaged well enough: the estimated error of every pair's average at every level "
        "(the oscillation left in its window, results/nominal/{contact}.nc averaging_error)"
    )
    if r.statics:
        meas = "the nominal files are static equilibria (nominal.method statics): nothing averaged (see check 2)"
    elif r.status["7"] == SKIP:
        meas = "no estimate in the nominal files (made before issue 34: rerun the nominal stage)"
    else:
        meas = largest_case(r.error, r.levels, r.faces)
        above = r.above()
        if above:
            named = [f"#{p} at {lv:g} MPa on {label(r.faces[c])} ({mm(e)})" for c, p, lv, e in above[:MAX_NAMED]]
            more = f" and {len(above) - MAX_NAMED} more" if len(above) > MAX_NAMED else ""
            meas += f"; {len(above)} above the tolerance: " + ", ".join(named) + more
    return [Verdict("7", stmt, meas, f"under {mm(r.tolerance)}", r.status["7"])]
