"""Grounded intervals with model discrepancy (issue 32; docs/benchmarks.md, "Grounded intervals
with model discrepancy"): MuJoCo's grounded run of `bench_calibration_independent.py` (noise-free,
the roll included, the prediction check before the ramp) calibrated from the configured defaults,
four parameters with the initial state and the frame, by `tensegrity.calibration.calibrate` with
`windows` K: the misfit drops the classical intervals and K disjoint time windows are refitted
(`calibration.discrepancy`, (W1)). Prints per seed the relative errors, the window estimates, the
intervals relative to the truth and how many hold it; saves per seed and residual an .npz in --out
(truth, estimate, window estimates, intervals, the Jacobian (N, p) in scaled unknowns at the
optimum and the residuals (T, M) m, the roll's time of tipping: MuJoCo's, the fit's).
`--only-windows` refits the windows of saved fits with another K ({residual}_{seed}_w{K}.npz),
to choose K on the tuning seeds 0-5. Asserts nothing.

Usage: python benchmarks/bench_calibration_intervals.py --seeds 0,1,2,3,4,5 [--residual shape]
       [--windows 4] [--only-windows] [--out DIR]
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np
from bench_calibration_independent import CASES, DT, FOUR, RATE, draw, measured_case, roll_of

from tensegrity.calibration import Measurement, calibrate
from tensegrity.calibration import fit as fitmod
from tensegrity.physics.params import Params


def window(m: Measurement, a: int, b: int) -> Measurement:
    """Samples a .. b-1 of m as a measurement of their own (time from their first)."""
    return Measurement(m.t[a:b] - m.t[a], m.nodes[a:b], m.pressure[a:b], m.mode, f"{m.source}[{a}:{b}]", m.command)


def refit_windows(seed: int, residual: str, windows: int, out: Path) -> None:
    """The windows alone, K = `windows`, from the whole-run estimate saved by `one`: saved as
    {residual}_{seed}_w{K}.npz (its `windows` and `edges`)."""
    a = argparse.Namespace(seed=seed, seconds=4.0, hold=0.5, excite=2.0, ramp=2.0, noise=0.5, tiny=False)
    truth, saved = draw(seed), np.load(out / f"{residual}_{seed}.npz")
    m, _, _ = measured_case(a, truth, "grounded", out / "csv")
    start = Params().replace(**{k: getattr(truth, k) for k in ("strut_length", "strut_mass", "muscle_min_length")})
    best = start.replace(**dict(zip(FOUR, map(float, saved["estimate"]), strict=True)))  # as c.params
    edges = np.linspace(0, m.t.size, windows + 1).round().astype(int)
    t0, est = time.perf_counter(), []
    for i in range(windows):
        w = window(m, edges[i], edges[i + 1])
        est.append(calibrate(w, best, FOUR, "grounded", DT, True, check=0.0, residual=residual, windows=0).estimate)
    np.savez(out / f"{residual}_{seed}_w{windows}.npz", windows=np.array(est), edges=edges)
    werr = "; ".join(", ".join(f"{v:+.1%}" for v in e / saved["true"] - 1) for e in est)
    print(f"seed {seed} {residual}, {windows} windows: {werr}; {time.perf_counter() - t0:.0f} s wall", flush=True)


def one(seed: int, residual: str, windows: int, out: Path, tiny: bool = False) -> None:
    """Fit seed's grounded run, then its windows; save the .npz (module docstring). tiny: a smoke
    run (0.5 s of steps, no roll, no check, the initial state from the data; the stiffness alone
    fitted from the default, the rest true)."""
    a = argparse.Namespace(seed=seed, seconds=4.0, hold=0.5, excite=2.0, ramp=2.0, noise=0.5, tiny=tiny)
    if tiny:
        a.excite, a.hold = 0.5, 0.1
    truth = draw(seed)
    start = Params().replace(**{k: getattr(truth, k) for k in ("strut_length", "strut_mass", "muscle_min_length")})
    fit = FOUR[:1] if tiny else FOUR
    start = truth.replace(cable_stiffness=start.cable_stiffness) if tiny else start
    folder = out / "csv"
    folder.mkdir(parents=True, exist_ok=True)
    m, world, ramp = measured_case(a, truth, "grounded", folder)
    t0 = time.perf_counter()
    check = 1 - (ramp + 1) / m.t.size if ramp else 0.0  # as bench_calibration_independent: before the ramp
    c = calibrate(m, start, fit, "grounded", DT, not tiny, check=check, residual=residual, windows=windows)
    wall = time.perf_counter() - t0
    prob = c.problem
    lo, hi = fitmod._bounds(prob)
    J = fitmod._Residuals(prob, lo, hi).jac(c.x)
    R = prob.per_sample(prob.simulate(c.x[None]), c.x[None])[0]
    r = float(truth.strut_radius)
    tips = [roll_of(world, r, ramp)[0], roll_of(c.simulated, r, ramp)[0]] if ramp else [np.nan, np.nan]
    est = c.unc.windows if c.unc.windows is not None else np.zeros((0, len(fit)))
    edges = np.linspace(0, m.t.size, windows + 1).round().astype(int) if windows else np.zeros(0, int)
    true = np.array([getattr(truth, k) for k in fit])
    np.savez(
        out / f"{residual}_{seed}.npz",
        true=true,
        estimate=c.estimate,
        windows=np.array(est).reshape(-1, len(fit)),
        edges=edges,
        J=J,
        R=R,
        valid=prob.valid,
        units=prob.units,
        n=prob.n_params,
        rms_mm=c.rms_mm,
        tips=np.array(tips),
        lower=c.unc.lower,
        upper=c.unc.upper,
        method=np.array(c.unc.method),
        wall=np.array([wall, time.perf_counter() - t0]),
    )
    err = ", ".join(f"{v:+.1%}" for v in c.estimate / true - 1)
    werr = "; ".join(", ".join(f"{v:+.1%}" for v in e / true - 1) for e in est)
    true_in = (c.unc.lower <= true) & (true <= c.unc.upper)
    iv = ", ".join(
        f"[{lo_ / t_ - 1:+.1%}, {hi_ / t_ - 1:+.1%}]" for lo_, hi_, t_ in zip(c.unc.lower, c.unc.upper, true)
    )
    print(f"seed {seed} {residual}: {err}; RMS {c.rms_mm:.3g} mm; tips {tips[0]:.2f}/{tips[1]:.2f} s; windows {werr}")
    print(f"  intervals (relative to the truth) {iv} ({'; '.join(c.unc.method)}); inside {true_in.sum()} of {len(fit)}")
    print(f"  {wall:.0f} s wall with the {windows} windows", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seeds", default="0,1,2,3,4,5", help="comma-separated named seeds (draw)")
    ap.add_argument("--residual", choices=["positions", "shape"], default="shape")
    ap.add_argument("--windows", type=int, default=4, help="disjoint time windows refitted (0: none)")
    ap.add_argument("--only-windows", action="store_true", help="refit the windows of saved fits only")
    ap.add_argument("--tiny", action="store_true", help="a smoke run (`one`): 0.5 s, no roll, the stiffness only")
    ap.add_argument("--out", type=Path, help="folder of the .npz files (default: a temporary one, not kept)")
    a = ap.parse_args()
    assert CASES["grounded"][0] == "grounded" and RATE == 100.0
    with tempfile.TemporaryDirectory() as tmp:
        out = a.out or Path(tmp)
        out.mkdir(parents=True, exist_ok=True)
        for s in (int(v) for v in a.seeds.split(",") if v.strip()):
            if a.only_windows:
                refit_windows(s, a.residual, a.windows, out)
            else:
                one(s, a.residual, a.windows, out, a.tiny)


if __name__ == "__main__":
    main()
