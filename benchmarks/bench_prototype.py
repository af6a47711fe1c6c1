"""The paper's experiment (IV.B) with the prototype's twisted-string actuators, in the grounded
simulation: the faces each roll lands on at the paper's voltages, the lowest rolling voltage of
each roll beside the paper's, and their sensitivity to each assumed parameter (+-20 %). Prints
figures; asserts nothing. docs/design.md §10; the parameters: config/README.md (`actuator`).

Usage: python benchmarks/bench_prototype.py [--drive 30] [--settle 4] [--rounds 2] [--points 8]
       [--names rotor_inertia,string_length,...|none] [--change 0.2]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from tensegrity import paper
from tensegrity.io import config, settings
from tensegrity.physics import topology as topo
from tensegrity.validation import prototype as pt


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--drive", type=float, default=30.0, help="s a roll's voltage is held")
    ap.add_argument("--settle", type=float, default=4.0, help="s at 0 V before the face is read")
    ap.add_argument("--rounds", type=int, default=2, help="multisection rounds of the lowest voltage")
    ap.add_argument("--points", type=int, default=8, help="voltages per round (robots side by side)")
    ap.add_argument("--names", default=",".join(pt.ASSUMED), help="assumed parameters to vary, or none")
    ap.add_argument("--change", type=float, default=0.2, help="relative change of each (0.2: +-20 %%)")
    a = ap.parse_args()
    cfg = config.load()
    cfg["actuator"]["kind"] = "twisted_string"
    params, motors = settings.params(cfg), settings.motors(cfg)
    protocol = pt.Protocol(drive=a.drive, settle=a.settle)
    t0 = time.perf_counter()
    e = pt.experiment(params, motors, protocol, rounds=a.rounds, points=a.points)
    (p1, _, f1), (p2, _, f2) = paper.EXPERIMENT
    label = lambda f: topo.face_label(f) if f else "none"  # noqa: E731
    volts = lambda x: f"{x:>7.2f}" if np.isfinite(x) else f"{'-':>7}"  # noqa: E731  (NaN: none)
    print(f"section IV.B simulated ({time.perf_counter() - t0:.1f} s; drive {a.drive} s, settle {a.settle} s)")
    print(f"{'roll':<34} {'paper':>12} {'simulated':>12}")
    print(f"{'#10 at 11.1 V from (9,10,12)':<34} {label(topo.face_number(f1)):>12} {label(e.face_1):>12}")
    print(f"{'then #11 at 6 V':<34} {label(topo.face_number(f2)):>12} {label(e.face_2):>12}")
    print(f"{'#10 at 6 V from (9,10,12)':<34} {'no roll':>12} {label(e.face_low):>12}")
    res = (span := 12.0) / a.points**a.rounds
    print(f"time from the voltage's start to the landing: {e.time_1:.1f} s (#10), {e.time_2:.1f} s (#11)")
    print(f"lowest rolling voltage (resolution {res:.2f} V over 0-{span:g} V):")
    print(f"  #10 from (9,10,12): {volts(e.lowest_1)} V (paper drove {paper.VOLTAGE[p1]} V)")
    print(f"  #11 from (10,11,12): {volts(e.lowest_2)} V (paper drove {paper.VOLTAGE[p2]} V)")
    print(
        f"  ratio #11/#10: {e.lowest_2 / e.lowest_1:.2f} (paper's voltages {paper.VOLTAGE[p2] / paper.VOLTAGE[p1]:.2f})"
    )
    print(f"strands twisted past their lock: {e.locked}")
    print(f"reproduced: {e.reproduced}")
    names = () if a.names == "none" else tuple(a.names.split(","))
    if not names:
        return
    t0 = time.perf_counter()
    table = pt.sensitivity(params, motors, names, a.change, protocol, rounds=a.rounds, points=a.points)
    pct = round(100 * a.change)
    print(
        f"\nsensitivity: lowest rolling voltage (V) with one value -{pct} % / +{pct} % "
        f"({time.perf_counter() - t0:.1f} s; the second from where the first landed at 11.1 V;\n"
        "-: no roll in 0-12 V, or the first roll failed)"
    )
    print(f"{'parameter':<18} {'default':>10} {'#10 -':>7} {'#10 +':>7} {'#11 -':>7} {'#11 +':>7}")
    for name, v in table.items():
        print(f"{name:<18} {float(np.asarray(getattr(motors, name))):>10.3g} " + " ".join(volts(x) for x in v.ravel()))


if __name__ == "__main__":
    main()
