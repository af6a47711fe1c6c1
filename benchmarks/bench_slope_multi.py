"""The slope limit with actions of any set of pairs beside the single-pair one (issue 30, item 1):
per contact case and heading, the steepest slope found by simulation to roll uphill and downhill
under control with a single pair (results/slope_limit.nc `simulated`) and with the actions
optimised on the statics (`workspace.slope_multi`: bisection from the single-pair limit up to the
stand limit), with the bisection brackets, the optimised action at the limit and the wall time.
Prints figures; asserts nothing.

The single-pair limits are computed as the stage `slope_limit` does (`slope_limit.limits`).

Usage: .venv/bin/python benchmarks/bench_slope_multi.py [--gravity results/workspace_gravity.nc]
       [--workspace results/workspace.nc] [--contacts equilateral isosceles] [--iterations 3]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from tensegrity.io import config, formats
from tensegrity.io import settings as io_settings
from tensegrity.io.formats import gravity as gf
from tensegrity.workspace import slope_limit as sl
from tensegrity.workspace.gravity import GravitySetup
from tensegrity.workspace.sensitivity import ActuationSettings
from tensegrity.workspace.slope_multi import multi_limits


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--gravity", default="results/workspace_gravity.nc")
    ap.add_argument("--workspace", default="results/workspace.nc")
    ap.add_argument("--contacts", nargs="+", default=None, help="contact cases (default: all of the file)")
    ap.add_argument("--iterations", type=int, default=3, help="bisection steps, of both limits")
    a = ap.parse_args()
    if a.iterations < 1:
        ap.error(f"--iterations {a.iterations}: at least one")
    sweeps = gf.read_gravity(a.gravity)
    contacts = list(sweeps) if a.contacts is None else a.contacts
    for c in contacts:
        if c not in sweeps:
            ap.error(f"--contacts {c}: not in {a.gravity} ({', '.join(sweeps)})")
    sweeps = {c: sweeps[c] for c in contacts}
    cfg = config.load()
    setup = io_settings.build(GravitySetup, cfg)
    params = io_settings.params(cfg)
    look = formats.read_workspace(a.workspace)
    t0, c0 = time.perf_counter(), time.process_time()
    lim = sl.limits(look, params, sweeps, setup, a.iterations)  # the stage's single-pair limits
    t1, cpu0 = time.perf_counter(), time.process_time()
    m = multi_limits(look, params, sweeps, lim, setup, ActuationSettings(), a.iterations)
    wall, cpu = time.perf_counter() - t1, time.process_time() - cpu0
    headings = lim.headings
    print(
        f"{len(contacts)} contacts x {len(headings)} headings, {a.iterations} bisection steps, up to "
        f"{setup.max_pressure} MPa: single-pair limits wall {t1 - t0:.0f} s (CPU {cpu0 - c0:.0f} s); with "
        f"optimised actions {wall:.0f} s more (CPU {cpu:.0f} s)"
    )
    print(
        "\n| kind | contact | heading deg | single pair deg (bracket) | any set of pairs deg (bracket) "
        "| action at the limit |"
    )
    print("|---|---|---|---|---|---|")
    gains = []
    for k in (1, 2):
        for c, contact in enumerate(contacts):
            for j, h in enumerate(headings):
                w = m.weights[k, c, j]
                act = (
                    " + ".join(f"{w[q]:.2f} #{q + 1}" for q in np.flatnonzero(w)) + f" at {m.pressure[k, c, j]:.2f} MPa"
                    if w.any()
                    else "-"
                )
                print(
                    f"| {lim.kinds[k]} | {contact} | {h:g} | {lim.simulated[k, c, j]:.1f} "
                    f"({lim.simulated[k, c, j]:.1f}-{lim.simulated_high[k, c, j]:.1f}) | {m.simulated[k, c, j]:.1f} "
                    f"({m.simulated[k, c, j]:.1f}-{m.simulated_high[k, c, j]:.1f}) | {act} |"
                )
                gains.append((k, m.simulated[k, c, j] - lim.simulated[k, c, j]))
    for k in (1, 2):
        g = np.array([v for kk, v in gains if kk == k])
        g = g[np.isfinite(g)]
        if g.size:
            print(
                f"{lim.kinds[k]}: raised at {int(np.sum(g > 0))} of {g.size} poses, by {g.mean():.1f} deg on "
                f"average, at most {g.max():.1f} deg"
            )


if __name__ == "__main__":
    main()
