"""Check 8 (issue 31): the paper's experiment (IV.B) with the prototype's twisted-string actuators,
read from results/validation/prototype.nc (`validation.prototype` runs it): #10 at 11.1 V rolls
(9,10,12) to (10,11,12) (8.1), then #11 at 6 V rolls on to (6,10,11) (8.2), #10 at 6 V does not
roll (8.3), and the lowest rolling voltages agree with those three runs (8.4). Its numbers
(`Steps`, `PrototypeResult`), its verdicts (`check_prototype`) and its words."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .common import FAIL, PASS, SKIP, Result
from .words import Table, Verdict, label


@dataclass(frozen=True)
class Steps:
    """The experiment's three steps (roll 1, roll 2, the run that must not roll): pair (3,) driven
    at voltage (3,) V from start_face (3,), the face the paper reports after it, paper_face (3,),
    the simulated face (3,) (0: none) and locked (3,) (a strand pair ended it twisted past its
    lock); of the two rolls' pairs: the lowest rolling voltage (2,) V, the top of a multisection
    bracket of width error (2,) V (NaN: none in the span rolls), and the paper's voltage (2,) V;
    searched: whether the lowest voltages were searched at all (prototype.rounds > 0)."""

    pair: np.ndarray
    voltage: np.ndarray
    start_face: np.ndarray
    paper_face: np.ndarray
    face: np.ndarray
    locked: np.ndarray
    lowest: np.ndarray
    error: np.ndarray
    paper_voltage: np.ndarray
    searched: bool = True


@dataclass(frozen=True)
class PrototypeResult(Result):
    """Check 8's numbers (`steps`) and the status of verdicts 8.1-8.4."""

    steps: Steps


def check_prototype(s: Steps) -> PrototypeResult:
    """8.1-8.3: each step ends on the paper's face, no strand pair locked. 8.4: each roll's
    lowest-voltage bracket agrees with the runs at the paper's voltages: its lower end (a voltage
    that did not roll) below the paper's voltage, and the top of that of step 3's pair above step
    3's voltage (which did not roll); nothing in 0-12 V rolling fails it; not evaluated if not
    searched. The bracket, not its top, so that a coarse search (config prototype.points,
    prototype.rounds) does not fail a consistent result."""
    ok = (np.asarray(s.face) == np.asarray(s.paper_face)) & ~np.asarray(s.locked, bool)
    status = {f"8.{k + 1}": PASS if ok[k] else FAIL for k in range(3)}
    if not s.searched:
        status["8.4"] = SKIP
    else:
        top = np.asarray(s.lowest, float)
        lower = top - np.asarray(s.error, float)
        k = int(np.flatnonzero(np.asarray(s.pair[:2]) == s.pair[2])[0])  # the roll of step 3's pair
        agree = np.isfinite(top).all() and bool((lower < np.asarray(s.paper_voltage)).all()) and top[k] > s.voltage[2]
        status["8.4"] = PASS if agree else FAIL
    return PrototypeResult(status=status, steps=s)


def _landed(s: Steps, k: int) -> str:
    face = int(s.face[k])
    where = "rests on no face" if face == 0 else "stays on" if face == s.start_face[k] else "lands on"
    text = f"{where} {label(face)}" if face else where
    return text + (" (a strand pair twisted past its lock: the model's limit)" if s.locked[k] else "")


def _volts(x: float, err: float) -> str:
    return "none up to 12 V" if not np.isfinite(x) else f"{x:.2f} V (bracket {x - err:.2f}-{x:.2f} V)"


def prototype_verdicts(r: PrototypeResult) -> list[Verdict]:
    """Check 8: one row per step of IV.B, and one for the lowest rolling voltages."""
    s, st = r.steps, r.status
    rows = []
    for k, after in enumerate(("", "then ", "")):
        stmt = f"Prototype (IV.B, twisted strings, grounded): {after}#{int(s.pair[k])} at {s.voltage[k]:g} V " + (
            f"rolls {label(s.start_face[k])} to {label(s.paper_face[k])}"
            if s.paper_face[k] != s.start_face[k]
            else f"does not roll {label(s.start_face[k])}"
        )
        ref = "no roll (IV.B)" if s.paper_face[k] == s.start_face[k] else f"{label(s.paper_face[k])} (IV.B, Fig. 12)"
        rows.append(Verdict(f"8.{k + 1}", stmt, _landed(s, k), ref, st[f"8.{k + 1}"]))
    stmt = (
        f"Prototype: the lowest voltage that rolls each step agrees with these runs: below the paper's, "
        f"#{int(s.pair[2])}'s above {s.voltage[2]:g} V (multisection bracket; results/validation/prototype.nc)"
    )
    meas = (
        "not searched (prototype.rounds = 0)"
        if not s.searched
        else "; ".join(f"#{int(p)} {_volts(x, e)}" for p, x, e in zip(s.pair[:2], s.lowest, s.error))
    )
    ref = "drove " + ", ".join(f"#{int(p)} at {v:g} V" for p, v in zip(s.pair[:2], s.paper_voltage))
    rows.append(Verdict("8.4", stmt, meas, ref, st["8.4"]))
    return rows


def prototype_table(r: PrototypeResult) -> Table:
    """The lowest rolling voltages beside the paper's (V)."""
    s = r.steps
    rows = [
        [f"#{int(p)}", label(s.start_face[k]), label(s.paper_face[k]), f"{v:g}", _volts(x, e)]
        for k, (p, v, x, e) in enumerate(zip(s.pair[:2], s.paper_voltage, s.lowest, s.error))
    ]
    return (
        "The prototype's experiment (check 8; V)",
        ["pair", "from", "to", "paper drove", "lowest rolling voltage (simulated)"],
        rows,
    )
