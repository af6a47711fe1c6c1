"""The checks' results in words: one `Verdict` row per verdict (what is claimed, what was measured
with units, the paper's value or the goal, the status) and the per-pair tables of summary.md.
Lengths are written in mm, pressures in MPa. `validation.report` lays them out as Markdown, HTML
and the text variables of validation.nc."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from .. import paper
from ..physics import topology as topo
from ..physics.topology import CONTACTS
from .checks import MappingResult, StaticsResult, TimestepResult
from .common import PASS, SKIP, CheckError, Result
from .grounded import GroundedResult
from .paper import PaperResult
from .runs import RunsResult

Table = tuple[str, list[str], list[list[str]]]  # title, header, rows


@dataclass(frozen=True)
class Verdict:
    """One row of the summary table: what is claimed, what was measured (with units), the
    paper's value or the goal, and the status PASS, FAIL or SKIP."""

    id: str
    statement: str
    measured: str
    reference: str
    status: str

    @property
    def passed(self) -> bool:
        return self.status == PASS


def mm(x: float, digits: int = 3) -> str:
    """A length `x` in m written in mm with `digits` significant digits ('n/a' if not finite)."""
    if not np.isfinite(x):
        return "n/a"
    v = 1e3 * float(x)
    return f"{v:.{digits}g} mm" if abs(v) < 10**digits else f"{v:.0f} mm"


def label(face: int) -> str:
    """A face (1..20) by its sorted nodes, e.g. '(9,10,12)'."""
    return topo.face_label(int(face))


def edge_label(edge: Sequence[int] | None) -> str:
    """An edge (two 1-based nodes; 0 or None: none) as '10-12', or 'none'."""
    return "-".join(str(int(n)) for n in sorted(edge)) if edge is not None and min(edge) > 0 else "none"


def _largest_case(difference: np.ndarray, pressures, faces: Mapping) -> str:
    """'largest X mm (#pair at P MPa on face) over N cases' of a (contact, pair, pressure)
    difference in m."""
    c, p, k = _largest(difference)
    return (
        f"largest {mm(np.nanmax(difference))} (#{p + 1} at {pressures[k]:g} MPa on "
        f"{label(faces[CONTACTS[c]])}) over {int(np.isfinite(difference).sum())} cases"
    )


def _largest(values: np.ndarray) -> tuple[int, ...]:
    """Index of the largest finite value."""
    return tuple(int(i) for i in np.unravel_index(int(np.nanargmax(values)), values.shape))


# ------------------------------------------------------------------------ 1. paper


def _paper(r: PaperResult) -> list[Verdict]:
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


def _statics(r: StaticsResult) -> list[Verdict]:
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
        meas = _largest_case(r.difference, r.pressures, r.faces)
    return [Verdict("2", stmt, meas, f"under {mm(r.tolerance)}", r.status["2"])]


def _mapping(r: MappingResult) -> list[Verdict]:
    stmt = (
        "Workspace mapped by symmetry = direct simulation standing on the face "
        "(nominal CoG and deformed triangle), sample faces " + ", ".join(label(f) for f in r.faces)
    )
    ref = f"under {mm(r.tolerance)}; at least {r.min_per_kind} non-canonical faces of each kind"
    if not r.levels_match:
        meas = "the workspace was swept at other levels"
    elif not np.isfinite(r.difference).any():
        meas = "the workspace holds no data for the sample faces"
    else:
        F, n_faces = len(r.faces), r.faces_with_data
        i, p, k = _largest(np.fmax(r.difference, r.support_difference))
        meas = (
            f"largest {mm(np.nanmax(r.difference))} (CoG), {mm(np.nanmax(r.support_difference))} "
            f"(triangle), at #{p + 1}, {r.levels[k]:g} MPa on {label(r.faces[i])}; {n_faces} faces "
            f"({r.kinds['equilateral']} equilateral, {r.kinds['isosceles']} isosceles), "
            f"{int(np.isfinite(r.difference).sum())} cases"
        )
        if n_faces < F:
            meas += f"; {F - n_faces} faces without workspace data"
    return [Verdict("3", stmt, meas, ref, r.status["3"])]


def _timestep(r: TimestepResult) -> list[Verdict]:
    stmt = f"Nominal CoG at dt = {r.dt:g} s = the same sweep at dt/2 = {r.dt / 2:g} s"
    if r.status["5"] == SKIP:
        meas = "no sweep"
    else:
        meas = _largest_case(r.difference, r.levels, r.faces)
    return [Verdict("5", stmt, meas, f"under {mm(r.tolerance)}", r.status["5"])]


# --------------------------------------------------------------------- 4. grounded


def _grounded_text(r: GroundedResult, c: int) -> tuple[str, str]:
    """The shift and roll phrases of one contact case."""
    face, levels = r.faces[CONTACTS[c]], r.levels
    inpl = np.linalg.norm(r.shift[c, ..., :2], axis=-1)
    if np.isfinite(inpl).any():
        p, k = _largest(inpl)
        dz = r.shift[c, ..., 2]
        shift = (
            f"{label(face)}: {mm(inpl[p, k])} (#{p + 1} at {levels[k]:g} MPa); "
            f"normal {mm(np.nanmin(dz))}..{mm(np.nanmax(dz))}"
        )
    else:
        shift = f"{label(face)}: no level without a roll"
    pairs = [int(p) + 1 for p in np.flatnonzero(r.swept[c])]
    bad = [p for p in pairs if not r.agree[c, p - 1]]
    if not bad:
        n_roll = int(np.isfinite(r.roll_pressure[c, np.array(pairs) - 1]).sum())
        return shift, f"{label(face)}: all {len(pairs)} pairs agree ({n_roll} roll)"
    by: dict[tuple[str, str], list[int]] = {}  # pairs with the same outcome share a phrase
    for p in bad:
        a, af = r.roll_pressure[c, p - 1], r.roll_face[c, p - 1]
        b, bf = r.free_roll_pressure[c, p - 1], r.free_roll_face[c, p - 1]
        key = (
            f"rolls at {a:g} MPa onto {label(af) if af else 'an edge'}" if np.isfinite(a) else "does not roll",
            f"{b:g} MPa onto {label(bf)}" if np.isfinite(b) else "never",
        )
        by.setdefault(key, []).append(p)
    return shift, f"{label(face)}: " + "; ".join(
        f"{', '.join(f'#{p}' for p in ps)} {g_} (free workspace: {f_})" for (g_, f_), ps in by.items()
    )


def _grounded(r: GroundedResult) -> list[Verdict]:
    texts = [_grounded_text(r, c) for c, contact in enumerate(CONTACTS) if contact in r.faces]
    return [
        Verdict(
            "4.1",
            f"Gravity and ground contact (grounded mode) barely move the nominal CoG in the "
            f"support plane while the robot stands (against the {'/'.join(r.modes)} mode)",
            "; ".join(t[0] for t in texts),
            f"under {mm(r.tolerance)} (III.A-B: cable forces dominate)",
            r.status["4.1"],
        ),
        Verdict(
            "4.2",
            "The grounded robot rolls first at the level where the free CoG projection "
            "leaves the triangle, over the same edge",
            "; ".join(t[1] for t in texts),
            "same level and edge (III.B)",
            r.status["4.2"],
        ),
    ]


def _grounded_table(r: GroundedResult) -> Table:
    rows = []
    for c, contact in enumerate(CONTACTS):
        if contact not in r.faces:
            continue
        face = label(r.faces[contact])
        for i in np.flatnonzero(r.swept[c]):
            inp = np.linalg.norm(r.shift[c, i, :, :2], axis=-1)
            stood = np.isfinite(inp).any()
            frp, frf = r.free_roll_pressure[c, i], r.free_roll_face[c, i]
            rp, rf = r.roll_pressure[c, i], r.roll_face[c, i]
            rows.append(
                [
                    face,
                    f"#{i + 1}",
                    f"{1e3 * np.nanmax(inp):.2f}" if stood else "n/a",
                    f"{1e3 * np.nanmin(r.shift[c, i, :, 2]):.2f}" if stood else "n/a",
                    f"{1e3 * np.nanmin(r.margin_change[c, i]):.2f}" if stood else "n/a",
                    f"{frp:g} -> {label(frf)}" if np.isfinite(frp) else "-",
                    f"{rp:g} -> {label(rf) if rf else 'edge'}" if np.isfinite(rp) else "-",
                ]
            )
    return (
        "Grounded against free mode, per pair (check 4; mm, MPa)",
        [
            "contact",
            "pair",
            "max in-plane shift",
            "min normal shift",
            "min margin change",
            "free: leaves at -> face",
            "grounded: rolls at -> face",
        ],
        rows,
    )


# --------------------------------------------------------------- 6. demonstration runs


def _run_text(r: RunsResult, i: int) -> str:
    d = r.distance[i]
    far = f", {d:.2f} m from the goal" if np.isfinite(d) else ""
    why = "" if r.arrived[i] else f": {r.message[i]}"
    return f"{r.runs[i]} {r.outcome[i]} ({int(r.rolls[i])} rolls{far}){why}"


def _runs(r: RunsResult) -> list[Verdict]:
    meas = (
        "no demonstration runs configured (locomotion.runs)"
        if not r.runs
        else "; ".join(_run_text(r, i) for i in range(len(r.runs)))
    )
    return [
        Verdict(
            "6",
            "Every demonstration run arrives (results/locomotion/{run}.nc, outcome)",
            meas,
            "outcome 'arrived' (III.C-D: the workspace plans rolls that reach the goal)",
            r.status["6"],
        )
    ]


def _runs_table(r: RunsResult) -> Table:
    rows = [
        [
            name,
            r.outcome[i],
            str(int(r.rolls[i])),
            f"{r.distance[i]:.3f}" if np.isfinite(r.distance[i]) else "-",
            r.message[i],
        ]
        for i, name in enumerate(r.runs)
    ]
    return ("Demonstration runs (check 6; m)", ["run", "outcome", "rolls", "distance to goal", "why it ended"], rows)


# ------------------------------------------------------------------------ any check


def verdicts(result: Result) -> list[Verdict]:
    """The verdict rows of one check's result, in the order of its `status`."""
    if isinstance(result, CheckError):
        return [
            Verdict(
                result.number, f"{result.name} check", f"error: {result.error}", "runs", result.status[result.number]
            )
        ]
    for kind, words in (
        (PaperResult, _paper),
        (StaticsResult, _statics),
        (MappingResult, _mapping),
        (GroundedResult, _grounded),
        (TimestepResult, _timestep),
        (RunsResult, _runs),
    ):
        if isinstance(result, kind):
            return words(result)
    raise TypeError(f"no wording for a {type(result).__name__}")


def tables(result: Result) -> list[Table]:
    """The extra tables (title, header, rows) of one check's result: check 4's per-pair table,
    check 6's per-run table."""
    if isinstance(result, GroundedResult):
        return [_grounded_table(result)]
    if isinstance(result, RunsResult) and result.runs:
        return [_runs_table(result)]
    return []
