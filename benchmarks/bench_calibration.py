"""Time of a calibration from a trajectory (issue 32): four parameters (cable stiffness,
pretension, damping, muscle gain) from a free-mode trajectory made by our own simulator, by
default 8 s sampled at 100 Hz with 0.5 mm of noise, the fit starting 10-20 % off, the initial
state fitted too. Prints the wall and CPU time of the calibration (the fit and its prediction
check) and the recovered values with their 95 % intervals and what gave each (linearised or
profile); asserts nothing. Target: under 60 s
on 2 cores.

Usage: python benchmarks/bench_calibration.py [--seconds 8] [--rate 100] [--noise 0.5] [--seed 1]
       [--check 0.25] [--initial fit|data]
"""

from __future__ import annotations

import argparse
import os
import resource
import time

import numpy as np

from tensegrity.calibration import calibrate
from tensegrity.calibration import synthetic as syn
from tensegrity.physics.params import Params

FOUR = ("cable_stiffness", "cable_pretension", "cable_damping", "muscle_gain")


def _cpu_seconds() -> float:
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seconds", type=float, default=8.0, help="length of the trajectory, s")
    ap.add_argument("--rate", type=float, default=100.0, help="sampling rate, Hz")
    ap.add_argument("--noise", type=float, default=0.5, help="Gaussian noise on every coordinate, mm")
    ap.add_argument("--seed", type=int, default=1, help="seed of the noise")
    ap.add_argument("--check", type=float, default=0.25, help="fraction predicted in the check (0: none)")
    ap.add_argument("--initial", choices=["fit", "data"], default="fit", help="initial state fitted or from the data")
    a = ap.parse_args()
    truth, hold = Params(), 0.5 if a.seconds >= 2 else 0.1
    start = truth.replace(cable_stiffness=1150.0, cable_pretension=17.0, cable_damping=2.4, muscle_gain=530.0)
    m = syn.measure(truth, syn.excitation(a.seconds, hold), hold, "free", a.rate, noise=a.noise * 1e-3, seed=a.seed)
    calibrate(m.head(4), start, FOUR[:1], "free", 1e-4, fit_initial=False, check=0.0)  # compile or load the kernel
    t0, c0 = time.perf_counter(), _cpu_seconds()
    c = calibrate(m, start, FOUR, "free", 1e-4, fit_initial=a.initial == "fit", check=a.check)
    wall, cpu = time.perf_counter() - t0, _cpu_seconds() - c0
    print(f"cores: {os.cpu_count()}, {m.t.size} samples ({a.seconds:g} s at {a.rate:g} Hz), noise {a.noise:g} mm")
    print(
        f"unknowns: {len(c.problem.names)} (4 parameters, initial state {a.initial}); residuals: {c.unc.dof + len(c.x)}"
    )
    print(
        f"calibration (fit and prediction check): {wall:.1f} s wall, {cpu:.1f} s CPU; the fit: {c.nfev} "
        f"evaluations, {c.njev} Jacobians (batches of {len(c.x)} robots)"
    )
    print(f"{'parameter':<18} {'true':>9} {'estimate':>12} {'95 % interval':>28} {'error/se':>9}  interval by")
    rows = zip(c.names, c.estimate, c.unc.lower, c.unc.upper, c.unc.se, c.unc.method, strict=True)
    for k, e, lo, hi, se, how in rows:
        tv = getattr(truth, k)
        print(f"{k:<18} {tv:>9.4g} {e:>12.6g} {f'[{lo:.6g}, {hi:.6g}]':>28} {(e - tv) / se:>9.2f}  {how}")
    print(f"residual RMS {c.rms_mm:.3f} mm")
    if c.prediction:
        p = c.prediction
        print(
            f"prediction check: fitted up to {p['fit_until']:.2f} s (RMS {p['rms_fit_mm']:.3f} mm), "
            f"predicted the rest (RMS {p['rms_predict_mm']:.3f} mm); its estimates "
            f"{np.round(p['estimate'], 4).tolist()}"
        )


if __name__ == "__main__":
    main()
