"""Coverage of the calibration's 95 % intervals on runs in volts (issue 32): the case of the slow
test `test_noisy_runs_in_volts_give_intervals_that_hold` (tests/calibration/
test_coverage.py): the twisted strings twisted up and back for 3 s each (`synthetic.twisting`,
6.2 s at 100 Hz), 0.5 mm of noise, the seeds drawn from numpy.random.default_rng(32); the spring
stiffness, pretension and stall torque fitted from 10-17 % off (the damping configured 15 % off),
the initial state fitted. Per seed: each parameter's error, its interval and what gave it
('linearised', 'profile', or none: named), whether the truth is inside, the CPU time and the
profile's refits, the cost |r|^2 of the fit, its restarts from a lower point the profile or the
linearity check found (`minima`) and, with `--starts k`, the cost of each start's fit; then per
parameter the intervals given and the truths inside. `--budget 0` gives no profile (the
intervals that fail `linearity`'s check are dropped, as before the profile). Asserts nothing.

Usage: python benchmarks/bench_calibration_volts.py [--seeds 20] [--only SEED,SEED,...] [--budget 30]
       [--seconds 6.2] [--starts 0]
(`--seconds`: a shorter run than the test's, e.g. the test suite's 0.5 s with one seed; `--only`:
those of the test's seeds, in the test's order, instead of its first N)
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from tensegrity.calibration import calibrate, profile
from tensegrity.calibration import synthetic as syn
from tensegrity.physics.params import Params
from tensegrity.physics.twisted import TwistedString

KEY = "actuator.twisted_string."
FIT = ("spring_stiffness", "pretension", "stall_torque")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seeds", type=int, default=20, help="how many of the test's seeds (its first N)")
    ap.add_argument("--only", default="", help="comma-separated seeds of the test's 20 (default: the first --seeds)")
    ap.add_argument("--budget", type=int, default=profile.BUDGET, help="refits per profile (0: no profile)")
    ap.add_argument("--seconds", type=float, default=6.2, help="run length, s (the test's: 6.2)")
    ap.add_argument("--starts", type=int, default=0, help="extra starts of each fit (calibrate's starts)")
    a = ap.parse_args()
    if not 0.2 < a.seconds <= 60.0:
        ap.error(f"--seconds {a.seconds}: more than 0.2 (the rest before the twist) and at most 60")
    profile.BUDGET = a.budget
    seeds = np.random.default_rng(32).integers(1000, 10**6, 20)[: a.seeds]
    if a.only:
        only = [int(v) for v in a.only.split(",") if v.strip()]
        every = np.random.default_rng(32).integers(1000, 10**6, 20)
        if not set(only) <= set(every.tolist()):
            ap.error(f"--only: {sorted(set(only) - set(every.tolist()))} not among the test's seeds {every.tolist()}")
        seeds = [s for s in every if s in only]
    truth, strings = Params(), TwistedString()
    start = strings.replace(spring_stiffness=1100.0, pretension=17.0, stall_torque=0.0833, damping=2.3)
    true = np.array([getattr(strings, k) for k in FIT])
    given, inside, methods = [], [], []
    print(f"profile budget {a.budget} refits per parameter, {a.starts} extra starts")
    for seed in seeds:
        m = syn.measure(truth, syn.twisting(a.seconds), 0.1, "free", motors=strings, noise=5e-4, seed=int(seed))
        c0 = time.process_time()  # CPU s of the process, every thread
        c = calibrate(m, truth, tuple(KEY + k for k in FIT), "free", 1e-4, check=0.0, motors=start, starts=a.starts)
        cpu = time.process_time() - c0
        ok = np.isfinite(c.unc.lower) & np.isfinite(c.unc.upper)
        hit = ok & (c.unc.lower <= true) & (true <= c.unc.upper)
        given.append(ok)
        inside.append(hit)
        methods.append(c.unc.method)
        cost = c.rms_mm**2 * (c.unc.dof + len(c.x))  # |r|^2, mm^2
        print(
            f"seed {seed}: {cpu:.1f} s CPU, {c.njev} Jacobians, {c.unc.refits} profile refits, cost {cost:.4f} mm^2, "
            f"{len(c.restarts)} restarts{''.join(f' ({w})' for w in c.restarts)}"
            + (f", starts' costs {np.round(c.costs * 1e6, 4).tolist()} mm^2" if len(c.costs) > 1 else "")
        )
        for k, e, lo, hi, me, tv, h in zip(FIT, c.estimate, c.unc.lower, c.unc.upper, c.unc.method, true, hit):
            span = f"[{lo:.6g}, {hi:.6g}]" if np.isfinite(lo) else "none"
            print(f"  {k:<17} error {e / tv - 1:+8.2%}  {span:>26} {me:<22} {'inside' if h else ''}")
    given, inside = np.array(given), np.array(inside)
    print("parameter          given  inside (of given)  methods")
    for j, k in enumerate(FIT):
        kinds = sorted({mm[j] for mm in methods})
        print(f"{k:<18} {given[:, j].sum():>5}  {inside[:, j].sum():>6}             {', '.join(kinds)}")
    print(
        f"pooled: {inside.sum()} of {given.sum()} intervals hold the truth ({inside.sum() / max(given.sum(), 1):.3f})"
    )


if __name__ == "__main__":
    main()
