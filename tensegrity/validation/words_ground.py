"""The words of the checks of the robot on the ground: 4, the grounded mode against the free
workspace; 6, the demonstration runs. Their `Verdict` rows, and the per-pair (check 4) and
per-run (check 6) tables."""

from __future__ import annotations

import numpy as np

from ..physics.topology import CONTACTS
from .grounded import GroundedResult
from .runs import RunsResult
from .words import Table, Verdict, label, largest, mm

# --------------------------------------------------------------------- 4. grounded


def _grounded_text(r: GroundedResult, c: int) -> tuple[str, str]:
    """The shift and roll phrases of one contact case."""
    face, levels = r.faces[CONTACTS[c]], r.levels
    inpl = np.linalg.norm(r.shift[c, ..., :2], axis=-1)
    if np.isfinite(inpl).any():
        p, k = largest(inpl)
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


def grounded_verdicts(r: GroundedResult) -> list[Verdict]:
    """Check 4 (4.1, 4.2): the grounded mode against the free workspace."""
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


def grounded_table(r: GroundedResult) -> Table:
    """Check 4 per pair: the shifts, the margin change and where each mode leaves or rolls."""
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


def runs_verdicts(r: RunsResult) -> list[Verdict]:
    """Check 6: every demonstration run arrives."""
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


def runs_table(r: RunsResult) -> Table:
    """Check 6 per run: outcome, rolls, distance to the goal and why it ended."""
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
