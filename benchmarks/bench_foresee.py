"""CPU seconds of `lookahead.foresee` over every candidate of a planner's step (issue 30's
planning cost). Prints figures and a digest of the results; asserts nothing.

From a few fixed states (the robot settled, braked, on (9,10,12) at yaw 0, on 24 deg on
(2,4,11) at yaw 60; goal 2 m up +y): slope 20 and 24 deg, and random terrain of height std
0.07 m (seed 7). Every candidate the step
offers (`lookahead.acts`: 156 on the slopes, 78 on the terrain) is simulated in one `foresee`
call, as `lookahead.choose` does once its horizon reaches all of them. Per state: candidates,
process CPU s (all threads) of each repeat, and a digest (sha256 of every RollResult's fields):
the same digest means the same rolls, bit for bit. Run it against another tree with
`PYTHONPATH=<tree>` to compare before and after on one machine.

With `--runs GROUND ...` it runs those grounds of `bench_locomotion.py` instead (8 evaluation
cases, `--cases`), prints bench_locomotion's report and, per ground, a digest of every run (its
outcome, rolls and distance, and every RollResult of its steps, made and simulated) with the
planning CPU s per roll: the same digest, the same runs, bit for bit; and a digest of the rolls
made alone (each run's outcome, rolls and distance and every attempt's RollResult, not the
candidates simulated ahead): the same rolls made, whatever the candidates' ends. Both modes read the
two-pair workspace as bench_locomotion does (`--two-pair`, default results/workspace_two_pair.nc;
`none` or a missing file: superposed combinations); the runs before 2026-12-06 passed none, which is
why their `--runs` arrivals (5/8 on 20 deg, 3/8 on 24) differed from bench_locomotion's (7/8, 2/8).

Usage: python benchmarks/bench_foresee.py [--workspace results/workspace.nc] [--repeat 2]
       [--two-pair results/workspace_two_pair.nc | none]
       [--grounds slope20 slope24 terrain0.07] [--profile tottime|cumtime]
       [--runs slope20 ... [--cases 8] [--steps]] [--configfile volts.yaml]
Without the workspace file, one is computed first with the default configuration (~30 s).
"""

from __future__ import annotations

import argparse
import copy
import cProfile
import hashlib
import pstats
import sys
import time
from pathlib import Path

import numpy as np

from tensegrity import locomotion as lo
from tensegrity.io import config
from tensegrity.io import settings as io_settings
from tensegrity.locomotion import lookahead
from tensegrity.locomotion.brake import Brake
from tensegrity.locomotion.control import settle_controller
from tensegrity.locomotion.lockstep import lockstep
from tensegrity.locomotion.plan import plan
from tensegrity.physics import dynamics as d
from tensegrity.physics import topology as topo
from tensegrity.physics.terrain import Terrain

sys.path.insert(0, str(Path(__file__).parent))
import bench_locomotion  # noqa: E402

EQUI = topo.face_number(topo.CONTACT_FACES["equilateral"])  # (9,10,12)
GROUNDS = {  # name: (terrain, start face, yaw deg)
    "slope20": (lambda: Terrain.slope(20.0), EQUI, 0.0),
    "slope24": (lambda: Terrain.slope(24.0), 4, 60.0),  # (2,4,11): `start.choose`'s; (9,10,12) tumbles
    "terrain0.07": (lambda: Terrain.random(7, size=8.0, amplitude=0.07), EQUI, 0.0),
}
GOAL = np.array([0.0, 2.0, 0.0])


def start(ws, params, s, terrain, face, yaw):
    """The step's inputs: the settled observation, the candidates, the brake and the expected
    pressures, as `drive.drive` makes them on its first step."""
    brk = Brake(ws, s.brake_margin)

    def ctl(b, obs):
        _, obs = yield from settle_controller(s, obs, copy.deepcopy(brk))
        return obs

    ((obs, _, _),) = lockstep(params, terrain, d.stand_on(params, face, terrain, yaw_deg=yaw), ctl, s)
    target = dict(goal=GOAL)
    pl = plan(ws, obs.face, obs.nodes, combine=s.combine, min_alignment=s.min_alignment, unit=s.unit, **target)
    world = lookahead.World(params, terrain, obs.state, ws.max_pressure, False)
    todo = lookahead.acts(ws, obs.face, obs.nodes, pl, target, brk, world)
    return obs, todo, brk, {c.pairs: c.pressure for c in pl.candidates}


def _update(h, r) -> None:
    for v in (r.pairs, r.rolled, r.face_before, r.face_after, r.tip_pressure, r.peak_pressure, r.t_start, r.t_end):
        h.update(repr(v).encode())
    h.update(np.asarray(r.cog_before, float).tobytes() + np.asarray(r.cog_after, float).tobytes())


def digest(results) -> str:
    """sha256 (first 12 hex digits) of every field of every RollResult."""
    h = hashlib.sha256()
    for r in results:
        _update(h, r)
    return h.hexdigest()[:12]


def runs(grounds, cases, ws, params, s, show_steps=False) -> None:
    """bench_locomotion's grounds (evaluation seeds): its report, then a digest of every run."""
    a = argparse.Namespace(distance=2.0)
    for g in grounds:
        t0 = time.perf_counter()
        res = bench_locomotion.run_ground(g, bench_locomotion.EVALUATION_SEEDS[:cases], a, ws, params, s, None)
        row = bench_locomotion.report(g, res, time.perf_counter() - t0, s.arrive_tolerance)
        if show_steps:
            bench_locomotion.steps(res, s.unit)
        h, m = hashlib.sha256(), hashlib.sha256()  # every roll; the rolls made alone
        for _, r in res:
            for x in (h, m):
                x.update(repr((r.outcome, r.rolls, r.distance_to_goal)).encode())
            for st in r.steps:
                for x in st.attempts:
                    _update(m, x)
                for x in (*st.attempts, *st.simulated):
                    _update(h, x)
        load = open("/proc/loadavg").read().split()[:3]
        print(
            f"DIGEST {g} {h.hexdigest()[:16]} rolls made {m.hexdigest()[:16]} planning CPU {row['cpu']:.3f} s/roll, "
            f"load average {' '.join(load)}"
        )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--workspace", default="results/workspace.nc")
    ap.add_argument("--two-pair", default="results/workspace_two_pair.nc", help="'none': superposed combinations")
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--grounds", nargs="+", choices=list(GROUNDS), default=list(GROUNDS))
    ap.add_argument("--runs", nargs="+", choices=list(bench_locomotion.GROUNDS), help="whole runs instead")
    ap.add_argument("--cases", type=int, default=8, help="with --runs: cases per ground")
    ap.add_argument("--steps", action="store_true", help="with --runs: every step of every run (bench_locomotion's)")
    ap.add_argument("--configfile", help="a YAML file merged over config/config.yaml (e.g. the volts table)")
    ap.add_argument("--profile", choices=["tottime", "cumtime"], help="cProfile the first repeat: the top 30 by that")
    a = ap.parse_args()
    cfg = config.load(a.configfile)
    params = io_settings.params(cfg)
    s = io_settings.build(lo.RollSettings, cfg)
    two = None if a.two_pair.lower() == "none" or not Path(a.two_pair).is_file() else a.two_pair
    ws = bench_locomotion.workspace(a.workspace, two)
    if a.runs:
        return runs(a.runs, a.cases, ws, params, s, a.steps)
    d.warm()
    print(f"foresee from {lo.__file__}")
    for g in a.grounds:
        make, face, yaw = GROUNDS[g]
        terrain = make()
        obs, todo, brk, expect = start(ws, params, s, terrain, face, yaw)
        cpus, dig = [], None
        for k in range(a.repeat):
            prof = cProfile.Profile() if a.profile and k == 0 else None
            t0 = time.process_time()
            if prof:
                prof.enable()
            res = lookahead.foresee(params, terrain, s, obs, todo, ws.max_pressure, brk, expect)
            if prof:
                prof.disable()
            cpus.append(time.process_time() - t0)
            dig = digest(res) if dig is None else dig
            if digest(res) != dig:
                print(f"  {g}: repeat {k} differs from the first")
            if prof:
                pstats.Stats(prof).sort_stats(a.profile).print_stats(30)
        rolled = sum(r.rolled and lookahead.lands(r) for r in res)
        print(
            f"{g}: face {topo.face_label(obs.face)}, {len(todo)} candidates ({rolled} roll and land), "
            f"CPU s {' '.join(f'{c:.2f}' for c in cpus)}, digest {dig}"
        )


if __name__ == "__main__":
    main()
