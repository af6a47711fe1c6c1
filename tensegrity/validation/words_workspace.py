"""The words of the checks of the workspace itself (free mode): 1, its claims in the paper;
2, the nominal CoG against the statics; 3, the mapping by symmetry against direct simulation;
5, the time step. One list of `Verdict` rows per check result."""

from __future__ import annotations

import numpy as np

from .. import paper
from ..physics import topology as topo
from ..physics.topology import CONTACTS
from .checks import MappingResult, StaticsResult, TimestepResult
from .common import SKIP
from .paper import PaperResult
from .words import Verdict, edge_label, label, largest, largest_case, mm

# ------------------------------------------------------------------------ 1. paper


def paper_verdicts(r: PaperResult) -> list[Verdict]:
    """Check 1 (1.1-1.5): the paper's claims about the workspaces of (9,10,12) and (10,11,12)."""
    levels, P = r.levels, r.levels.size
    eq, iso = CONTACTS
    on = {k: f"standing on {label(r.faces[k])}" if k in r.faces else f"{k} case not computed" for k in CONTACTS}
    out = []
    stmt = (
        f"Standing on (9,10,12), pairs #9, #10, #12 move the CoG most and #4, #6, #7 next "
        f"(in-plane distance from the unactuated CoG at {r.ranking_pressure:g} MPa)"
    )
    ref = "#9, #10, #12 large; #4, #6, #7 less (III.A, Fig. 7)"
    if r.status["1.1"] == SKIP:
        meas = (
            on[eq]
            if eq not in r.faces
            else f"not all {topo.N_PAIRS} pairs swept"
            if r.ranking_in_levels
            else f"{r.ranking_pressure:g} MPa is outside the swept levels"
        )
    else:
        mig = r.migration[0]
        order = [int(p) for p in r.ranking]
        groups = [order[:3], order[3:6], order[6:]]
        meas = (
            on[eq]
            + ": "
            + "; ".join(
                ", ".join(f"#{p} {mm(mig[p - 1])}" for p in grp)
                if i < 2
                else f"others {mm(mig[grp[-1] - 1])}..{mm(mig[grp[0] - 1])}"
                for i, grp in enumerate(groups)
            )
        )
    out.append(Verdict("1.1", stmt, meas, ref, r.status["1.1"]))

    def tip_text(c: int, pair: int) -> str:
        p, e = r.tip_pressure[c, pair - 1], r.tip_edge[c, pair - 1]
        if not np.isfinite(p):
            return f"#{pair} keeps it inside up to {levels[-1]:g} MPa"
        return f"#{pair}: {p:.2f} MPa over edge {edge_label(e)} ({on[CONTACTS[c]]})"

    st = r.status["1.2"]
    out.append(
        Verdict(
            "1.2",
            "Standing on (9,10,12), #10 moves the CoG projection out over edge 10-12",
            "#10 not swept " + on[eq] if st == SKIP else tip_text(0, 10),
            f"{paper.TIP_PRESSURE} MPa over edge 10-12 (III.C), within {r.tip_tolerance:g} MPa",
            st,
        )
    )
    st = r.status["1.3"]
    out.append(
        Verdict(
            "1.3",
            "Standing on (10,11,12), #11 moves the CoG projection out over edge 10-11",
            "#11 not swept " + on[iso] if st == SKIP else tip_text(1, 11),
            "over edge 10-11: the robot rolls on to (6,10,11) (IV.B)",
            st,
        )
    )
    st = r.status["1.4"]
    if st == SKIP:
        meas = "#10 or #11 not swept"
    else:
        p10, p11 = r.tip_pressure[0, 10 - 1], r.tip_pressure[1, 11 - 1]
        fmt = lambda p: f"{p:.2f} MPa" if np.isfinite(p) else f"never (up to {levels[-1]:g} MPa)"
        ratio = f" (ratio {p11 / p10:.2f})" if np.isfinite(p10) and np.isfinite(p11) else ""
        meas = f"#11 {fmt(p11)}, #10 {fmt(p10)}{ratio}"
    out.append(
        Verdict(
            "1.4",
            "#11 on (10,11,12) needs a lower pressure than #10 on (9,10,12)",
            meas,
            f"lower: the prototype needed {paper.VOLTAGE[11]:g} V against {paper.VOLTAGE[10]:g} V "
            f"(ratio {paper.VOLTAGE[11] / paper.VOLTAGE[10]:.2f}, IV.B)",
            st,
        )
    )

    st = r.status["1.5"]
    odiff = r.orbit_difference
    if st == SKIP:
        meas = "no complete orbit swept " + on[eq]
    else:
        orbits = [[int(p) for p in row if p] for row in r.orbit_pairs]
        done = np.isfinite(odiff).all(axis=1)
        worst = max(range(len(orbits)), key=lambda i: np.nanmax(odiff[i]) if done[i] else -1)
        k = int(np.nanargmax(odiff[worst]))
        meas = (
            f"largest difference {mm(np.nanmax(odiff))} (orbit "
            f"{', '.join(f'#{p}' for p in orbits[worst])} at {levels[k]:g} MPa; magnitudes differ by "
            f"at most {mm(np.nanmax(r.orbit_magnitude_spread))}) over {int(done.sum())} orbits x {P} levels"
        )
    out.append(
        Verdict(
            "1.5",
            "The pairs of each 3-fold orbit of (9,10,12) move the CoG equally (120 deg apart)",
            meas,
            f"equal (III.A, the symmetry); goal: under {mm(r.orbit_tolerance)}",
            st,
        )
    )
    return out


# --------------------------------------------------------------- 2., 3., 5.


def statics_verdicts(r: StaticsResult) -> list[Verdict]:
    """Check 2: the nominal CoG against the static equilibrium."""
    stmt = (
        f"Nominal CoG = static equilibrium by energy minimisation (scipy), every pair at "
        f"{', '.join(f'{p:g}' for p in r.pressures)} MPa, in the support frame"
    )
    if r.modes != ("free",):
        meas = f"the sweeps ran in the {'/'.join(r.modes)} mode; the statics solve is of the free mode"
    elif r.missing:
        meas = f"{', '.join(f'{p:g}' for p in r.missing)} MPa not among the swept levels"
    elif not np.isfinite(r.difference).any():
        meas = "no pair swept at every level"
    else:
        meas = largest_case(r.difference, r.pressures, r.faces)
    return [Verdict("2", stmt, meas, f"under {mm(r.tolerance)}", r.status["2"])]


def mapping_verdicts(r: MappingResult) -> list[Verdict]:
    """Check 3: the workspace mapped by symmetry against direct simulation."""
    ref = "direct simulation standing on" if r.reference == "simulation" else "static equilibrium (scipy) seen from"
    stmt = (
        f"Workspace mapped by symmetry = {ref} the face "
        "(nominal CoG and deformed triangle), sample faces " + ", ".join(label(f) for f in r.faces)
    )
    ref = f"under {mm(r.tolerance)}; at least {r.min_per_kind} non-canonical faces of each kind"
    if not r.levels_match:
        meas = "the workspace was swept at other levels"
    elif not np.isfinite(r.difference).any():
        meas = "the workspace holds no data for the sample faces"
    else:
        F, n_faces = len(r.faces), r.faces_with_data
        i, p, k = largest(np.fmax(r.difference, r.support_difference))
        meas = (
            f"largest {mm(np.nanmax(r.difference))} (CoG), {mm(np.nanmax(r.support_difference))} "
            f"(triangle), at #{p + 1}, {r.levels[k]:g} MPa on {label(r.faces[i])}; {n_faces} faces "
            f"({r.kinds['equilateral']} equilateral, {r.kinds['isosceles']} isosceles), "
            f"{int(np.isfinite(r.difference).sum())} cases"
        )
        if n_faces < F:
            meas += f"; {F - n_faces} faces without workspace data"
    return [Verdict("3", stmt, meas, ref, r.status["3"])]


def timestep_verdicts(r: TimestepResult) -> list[Verdict]:
    """Check 5: the nominal CoG at the time step dt against dt/2."""
    stmt = f"Nominal CoG at dt = {r.dt:g} s = the same sweep at dt/2 = {r.dt / 2:g} s"
    if r.statics:
        meas = "the nominal files are static equilibria (nominal.method statics): no time step to halve (see check 2)"
    elif r.status["5"] == SKIP:
        meas = "no sweep"
    else:
        meas = largest_case(r.difference, r.levels, r.faces)
    return [Verdict("5", stmt, meas, f"under {mm(r.tolerance)}", r.status["5"])]
