"""Optimised actions of any set of pairs checked by simulation (issue 30, item 1): on flat ground
and slopes, the robot settles on the equilateral face (9,10,12) turned so that uphill has each
heading in its support frame; `locomotion.actuation.candidates` gives one action per edge (the
least total pressure by the statics and a linear programme); each is rolled (`control.roll`
with its weights, unbraked, up to `--max-pressure`), and so is its strongest pair alone. Prints
per action: the pairs and weights, the predicted tipping scale against the simulated one, whether
it landed on the face across its edge, and what the single pair did; then the totals and the
CPU time of the candidates. Asserts nothing. The rolls are unbraked (no workspace is read): on
steep slopes some poses do not stand and downhill rolls tumble, with a single pair as with the
optimised action; the runs' brake (`locomotion.brake`) is the planner's.

Usage: .venv/bin/python benchmarks/bench_actuation.py [--slopes 0 20 24] [--headings 0 90 180 270]
       [--max-pressure 5.0]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from tensegrity import locomotion as lo
from tensegrity.io import config
from tensegrity.io import settings as io_settings
from tensegrity.locomotion import actuation, control
from tensegrity.physics import topology as topo
from tensegrity.physics.schedule import MAX_PRESSURE
from tensegrity.physics.terrain import Terrain
from tensegrity.workspace.sensitivity import ActuationSettings
from tensegrity.workspace.slopes import place


def _end(r: control.RollResult) -> str:
    """How a roll that did not land across its edge ended."""
    if r.face_after is None:
        return "tumbled (on no face after it)"
    return f"on face {r.face_after}" if r.rolled else "not rolled"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--slopes", nargs="+", type=float, default=[0.0, 20.0, 24.0], help="deg")
    ap.add_argument("--headings", nargs="+", type=float, default=[0.0, 90.0, 180.0, 270.0], help="deg")
    ap.add_argument("--max-pressure", type=float, default=5.0, help="MPa")
    a = ap.parse_args()
    if not 0 < a.max_pressure <= MAX_PRESSURE:
        ap.error(f"--max-pressure {a.max_pressure}: must be in (0, {MAX_PRESSURE}] MPa")
    for sl in a.slopes:
        Terrain.slope(sl)  # a bad angle stops here, before any work
    cfg = config.load()
    s = io_settings.build(lo.RollSettings, cfg)
    act = io_settings.build(ActuationSettings, cfg)
    params = s.rolling(io_settings.params(cfg))
    face = topo.face_number((9, 10, 12))
    print(f"face (9,10,12), up to {a.max_pressure} MPa, actuation_margin {act.actuation_margin} m, unbraked rolls")
    print(
        "\n| slope deg | heading deg | edge | action | predicted scale MPa | simulated tip MPa | lands across it "
        "| its strongest pair alone |"
    )
    print("|---|---|---|---|---|---|---|---|")
    n, landed, alone_ok, errors, cpu = 0, 0, 0, [], 0.0
    for sl in a.slopes:
        terrain = Terrain.slope(sl) if sl else Terrain.flat()
        for h in a.headings:
            st, on = control.settle(params, place(params, face, terrain, (0.0, 0.0), h), terrain, s)
            if on != face:
                print(f"| {sl:g} | {h:g} | - | does not stand on the face | | | | |")
                continue
            t = time.process_time()
            cands = actuation.candidates(params, terrain, st, face, None, act, a.max_pressure)
            cpu += time.process_time() - t
            for c in cands:
                r = control.roll(params, st, terrain, None, a.max_pressure, s, weights=c.weights)
                q = int(np.argmax(c.weights)) + 1
                r1 = control.roll(params, st, terrain, (q,), a.max_pressure, s)
                ok = r.rolled and r.face_after == c.next_face
                ok1 = r1.rolled and r1.face_after == c.next_face
                n, landed, alone_ok = n + 1, landed + ok, alone_ok + ok1
                if r.rolled and np.isfinite(r.tip_pressure):
                    errors.append(r.tip_pressure - c.scale)
                w = " + ".join(f"{c.weights[i]:.2f} #{i + 1}" for i in np.flatnonzero(c.weights))
                one = f"#{q}: lands across it at {r1.tip_pressure:.2f} MPa" if ok1 else f"#{q}: {_end(r1)}"
                print(
                    f"| {sl:g} | {h:g} | {c.edge} | {w} | {c.scale:.2f} | {r.tip_pressure:.2f} | "
                    f"{'yes' if ok else _end(r)} | {one} |"
                )
    err = np.abs(errors) if errors else np.full(1, np.nan)
    print(
        f"\n{landed} of {n} optimised actions land on the face across their edge, their strongest pair alone "
        f"{alone_ok}; |simulated - predicted| tipping scale where it rolled: median {np.median(err):.2f} MPa, "
        f"largest {err.max():.2f} MPa; candidates: {cpu / max(len(a.slopes) * len(a.headings), 1):.2f} s CPU per pose"
    )


if __name__ == "__main__":
    main()
