"""The averaging-error estimate of the two-pair nominal CoG (issue 34, `workspace.nominal.averaging_error`
on the two-pair staircase of `workspace.two_pair.sweep`) against the distance of each swept grid
point's nominal CoG from the independent static equilibrium (`physics.statics`), free mode, on
one canonical face: the combinations the two_pair stage sweeps (one per stabiliser orbit) among
`--pairs`, over the grid `--levels` MPa held `--hold` s. Prints the largest estimate and
distance, the quantiles of estimate / distance, and the verdict of validation check (d) against
`--tolerance` (validate.averaging_tolerance), which names the grid points above it. The issue's
case: `--levels 1.2 2.4 3.6 4.8 --hold 1` on (10,11,12). Prints figures; asserts nothing.

Usage: python benchmarks/bench_two_pair_averaging.py [--contact isosceles] [--levels 1.2 2.4 3.6 4.8]
       [--hold 1.0] [--discard 0.2] [--pairs 1 ... 12] [--tolerance 5e-5] [--no-statics]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from tensegrity.physics import statics
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.validation import two_pair_averaging as tpa
from tensegrity.workspace import two_pair as tp
from tensegrity.workspace.nominal import TwoPairNominal


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--contact", default="isosceles", choices=list(topo.CONTACT_FACES))
    ap.add_argument("--levels", type=float, nargs="+", default=[1.2, 2.4, 3.6, 4.8], help="MPa of each pair")
    ap.add_argument("--hold", type=float, default=1.0, help="s per grid point")
    ap.add_argument("--discard", type=float, default=0.2, help="s left out at the start of each grid point")
    ap.add_argument("--pairs", type=int, nargs="+", default=list(range(1, 13)))
    ap.add_argument("--tolerance", type=float, default=5e-5, help="m")
    ap.add_argument("--no-statics", action="store_true", help="skip the distance to the static equilibria")
    a = ap.parse_args()
    prm, face = Params(), topo.face_number(topo.CONTACT_FACES[a.contact])
    setup = tp.TwoPairSetup(levels=tuple(a.levels), hold=a.hold, discard=a.discard)
    reps = tp.representatives(face, tp.combos_of(a.pairs))
    t0 = time.perf_counter()
    res = tp.sweep(prm, face, reps, setup)
    ws, _, _ = tp.contact_workspace(face, reps, res, setup.levels)
    lv = np.asarray(setup.levels)
    print(
        f"{topo.face_label(face)}: {len(reps)} combinations over {lv.size}x{lv.size} levels "
        f"({', '.join(f'{x:g}' for x in lv)} MPa), hold {a.hold:g} s, discard {a.discard:g} s: "
        f"swept in {time.perf_counter() - t0:.1f} s",
        flush=True,
    )
    est = res["averaging_error"]  # (R, P, P) m
    if not a.no_statics:
        cog = res["cog"][:, topo.FACE_REFERENCE[face - 1]]
        dist = np.empty(est.shape)
        for r, (pa, pb) in enumerate(reps):
            start = None
            for i in range(lv.size):
                for j in range(lv.size):
                    p = np.zeros(topo.N_PAIRS)
                    p[[pa - 1, pb - 1]] = lv[i], lv[j]
                    start = statics.equilibrium(prm, p, start=start)
                    dist[r, i, j] = np.linalg.norm(cog[r, i, j] - statics.support_cog(start, face)[0])
        q = np.quantile(est / dist, [0.1, 0.5, 0.9])
        print(
            f"estimate max {est.max() * 1e3:.4f} mm, distance to statics max {dist.max() * 1e3:.4f} mm; "
            f"estimate/distance 10/50/90 % {q[0]:.2f}/{q[1]:.2f}/{q[2]:.2f}; distance above "
            f"{a.tolerance * 1e3:g} mm at {int((dist > a.tolerance).sum())} of {dist.size} grid points",
            flush=True,
        )
    nominal = TwoPairNominal(a.contact, face, lv, ws["cog"], ws["tip_pressure"], ws["averaging_error"])
    err, st = tpa.check_averaging({a.contact: nominal}, a.tolerance)
    v = tpa.averaging_verdict(err, st, lv, a.tolerance, {a.contact: face})
    print(f"check (d) {v.status}: {v.measured}", flush=True)


if __name__ == "__main__":
    main()
