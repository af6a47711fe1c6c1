"""Goal-directed rolling (issue 4, item 6). Prints figures; asserts nothing.

Over N seeded random goal directions `--distance` m away (default 50 directions, 2 m), on flat
ground and on a seeded uneven terrain: the fraction of runs that arrive within the arrival
tolerance (default 0.3 m), the outcomes, distance per roll, rolls per metre, the mean pressure
of the rolls, and wall time per metre travelled. All runs of a terrain are simulated as one
batch (`locomotion.roll_many`); each run equals its single run.

Usage: python benchmarks/bench_locomotion.py [--workspace results/workspace.nc] [--runs 50]
       [--distance 2.0] [--seed 0] [--terrain-seed 1] [--amplitude 0.03] [--only flat|terrain]
       [--strut-damping 1.0]
Without the workspace file, one is computed first with the default configuration (~30 s).
"""
from __future__ import annotations

import argparse
import collections
import contextlib
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from tensegrity import locomotion as lo
from tensegrity.io import config, formats
from tensegrity.locomotion.demos import locomotion_params
from tensegrity.physics.terrain import Terrain


def workspace(path: str) -> lo.Workspace:
    if Path(path).is_file():
        return formats.read_workspace(path)
    from tensegrity import stages
    print(f"{path} not found: computing the workspace with the default configuration")
    cfg = config.load()
    with tempfile.TemporaryDirectory() as tmp:
        nominal = [stages.run_nominal(cfg, stages.run_sweep(cfg, c, f"{tmp}/{c}"), f"{tmp}/{c}.nc")
                   for c in cfg["sweep"]["contacts"]]
        return formats.read_workspace(stages.run_map(cfg, nominal, f"{tmp}/workspace.nc"))


@contextlib.contextmanager
def progress(desc: str):
    """A count of the simulated seconds on stderr (tqdm) while the batch runs; shown only when
    stderr is a terminal."""
    from tqdm import tqdm

    from tensegrity.physics import dynamics
    simulate = dynamics.simulate

    def counted(params, state, schedule, *a, **k):
        out = simulate(params, state, schedule, *a, **k)
        bar.update(schedule.duration)
        return out
    with tqdm(desc=desc, unit="s sim", disable=None, file=sys.stderr, leave=False,
              bar_format="{desc}: {n:.1f} s simulated per run [{elapsed}, {rate_fmt}]") as bar:
        dynamics.simulate = counted
        try:
            yield
        finally:
            dynamics.simulate = simulate


def report(name: str, runs: list[lo.Run], wall: float, tol: float) -> None:
    n = len(runs)
    arrived = [r for r in runs if r.outcome == "arrived"]
    rolls = sum(r.rolls for r in runs)
    travelled = sum(r.travelled for r in runs)
    path = sum(float(np.sum(np.linalg.norm(np.diff(np.array([r.start] + [
        st.used.cog_after for st in r.steps if st.rolled])[:, :2], axis=0), axis=1))) for r in runs)
    tips = [a.tip_pressure for r in runs for st in r.steps for a in st.attempts
            if a.rolled and np.isfinite(a.tip_pressure)]
    combos = sum(1 for r in runs for st in r.steps if st.rolled and len(st.used.pairs) > 1)
    sim = sum(float(r.record.t[-1] - r.record.t[0]) for r in runs if len(r.record.t))
    print(f"\n== {name}: {n} runs")
    print(f"arrived within {tol} m: {len(arrived)}/{n} = {100 * len(arrived) / n:.0f} %")
    print("outcomes: " + ", ".join(f"{k} {v}" for k, v in collections.Counter(r.outcome for r in runs).most_common()))
    print(f"final distance to goal: median {np.median([r.distance_to_goal for r in runs]):.3f} m, "
          f"max {max(r.distance_to_goal for r in runs):.3f} m")
    print(f"rolls: {rolls} ({combos} with two pairs); distance per roll "
          f"{travelled / max(rolls, 1):.3f} m net, {path / max(rolls, 1):.3f} m along the path; "
          f"rolls per metre {rolls / max(travelled, 1e-9):.2f}")
    print(f"pressure at which the rolls tipped: mean {np.mean(tips):.2f} MPa "
          f"(min {np.min(tips):.2f}, max {np.max(tips):.2f})")
    print(f"simulated {sim:.0f} s; wall {wall:.1f} s for the batch = {wall / max(travelled, 1e-9):.3f} s "
          f"per metre travelled ({wall / n:.2f} s per run)")
    bad = [r for r in runs if r.outcome != "arrived"]
    for r in bad[:10]:
        print(f"  not arrived: goal ({r.goal[0]:+.2f}, {r.goal[1]:+.2f}) -> {r.outcome}: {r.message}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--workspace", default="results/workspace.nc")
    ap.add_argument("--runs", type=int, default=50)
    ap.add_argument("--distance", type=float, default=2.0, help="goal distance, m")
    ap.add_argument("--seed", type=int, default=0, help="seed of the goal directions")
    ap.add_argument("--terrain-seed", type=int, default=1)
    ap.add_argument("--amplitude", type=float, default=0.03, help="terrain height std, m")
    ap.add_argument("--only", choices=["flat", "terrain"])
    ap.add_argument("--strut-damping", type=float, default=None,
                    help="strut damping of the rolling simulations, 1/s (default: config locomotion.strut_damping)")
    a = ap.parse_args()
    cfg = config.load()
    params = locomotion_params(cfg)
    if a.distance < float(params.strut_length):  # roll_many refuses goals closer than the robot
        ap.error(f"--distance {a.distance} m is less than the robot's size (strut length "
                 f"{params.strut_length} m)")
    ws = workspace(a.workspace)
    if a.strut_damping is not None:
        params = params.replace(strut_damping=a.strut_damping)
    settings = lo.RollSettings.from_config(cfg["locomotion"], cfg["sim"]["dt"])
    heading = np.random.default_rng(a.seed).uniform(0, 2 * np.pi, a.runs)
    goals = a.distance * np.stack([np.cos(heading), np.sin(heading)], axis=1)
    cases = {"flat": ("flat ground", Terrain.flat()),
             "terrain": (f"uneven terrain (seed {a.terrain_seed}, height std {a.amplitude} m)",
                         Terrain.random(a.terrain_seed, size=2 * a.distance + 4.0, amplitude=a.amplitude))}
    if a.only:
        cases = {a.only: cases[a.only]}
    print(f"{a.runs} goals {a.distance} m away (directions seeded {a.seed}); start on (9,10,12) "
          f"at the origin; ramp {settings.ramp_rate} MPa/s; strut damping "
          f"{params.strut_damping} 1/s; dt {settings.dt} s")
    for name, terrain in cases.values():
        t0 = time.perf_counter()
        with progress(name):
            runs = lo.roll_many(ws, goals, params, terrain, settings=settings)
        report(name, runs, time.perf_counter() - t0, settings.arrive_tolerance)


if __name__ == "__main__":
    main()
