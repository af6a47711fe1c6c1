"""Can the robot roll uphill at all on a steep slope? (issue 10 items 4-5: where a direction is
out of the robot's physical reach, the simulations that confirm it). Prints figures; asserts
nothing.

On planes of each `--slopes` angle, the robot stands on each contact case (the equilateral face
(9,10,12) and the isosceles face (10,11,12)) turned so that the uphill direction has each of
`--headings` headings in the face's support frame (as in results/slope_limit.nc), settles with
the run's brake, then makes one controlled roll (`locomotion.control`, the runs' controller
with the configured settings: ramp, hold, release, brake) with every single pair and every
two-pair combination, up to the workspace's highest pressure. A roll counts as uphill when the
robot then rests on another face with its CoG at least `--gain` m higher up the slope (along
+x), downhill when at least `--gain` m lower, across otherwise. Per slope: how many poses stand
(braked), from how many some single pair or some combination rolls the robot uphill, from how
many some action rolls it across or downhill under control (it then rests on a face), and the
outcomes of all rolls (uphill, across, downhill, not rolled, tumbled: on no face after the
roll). All rolls of a slope are one batch.

Usage: python benchmarks/bench_slope_reach.py [--workspace results/workspace.nc]
       [--slopes 15 20 24] [--headings 8] [--gain 0.05] [--combos / --no-combos]
"""
from __future__ import annotations

import argparse
import collections
import itertools
import time

import numpy as np

from tensegrity import locomotion as lo
from tensegrity.io import config, formats
from tensegrity.locomotion.brake import Brake
from tensegrity.locomotion.control import _roll_gen, _settle_gen
from tensegrity.locomotion.demos import locomotion_params
from tensegrity.locomotion.lockstep import lockstep
from tensegrity.physics import dynamics as d, topology as topo
from tensegrity.physics.terrain import Terrain
from tensegrity.workspace import gravity as gv


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--workspace", default="results/workspace.nc")
    ap.add_argument("--slopes", nargs="+", type=float, default=[15, 20, 24], help="slope angles, deg")
    ap.add_argument("--headings", type=int, default=8, help="headings of the uphill direction per face")
    ap.add_argument("--gain", type=float, default=0.05, help="least uphill CoG gain of a roll, m")
    ap.add_argument("--combos", action=argparse.BooleanOptionalAction, default=True,
                    help="also every two-pair combination (default)")
    a = ap.parse_args()
    if a.headings < 1:
        ap.error(f"--headings {a.headings}: at least one")
    cfg = config.load()
    params = locomotion_params(cfg)
    s = lo.RollSettings.from_config(cfg["locomotion"], cfg["sim"]["dt"])
    for sl in a.slopes:
        Terrain.slope(sl)  # a bad angle stops here, before any work
    ws = formats.read_workspace(a.workspace)
    actions = [(p,) for p in range(1, topo.N_PAIRS + 1)]
    if a.combos:
        actions += list(itertools.combinations(range(1, topo.N_PAIRS + 1), 2))
    headings = np.arange(a.headings) * 360.0 / a.headings
    faces = {k: topo.face_number(v) for k, v in topo.CONTACT_FACES.items()}
    poses = [(k, f, h) for k, f in faces.items() for h in headings]
    print(f"{len(poses)} poses ({', '.join(faces)} x {a.headings} headings) x {len(actions)} actions "
          f"({'singles and two-pair combinations' if a.combos else 'single pairs'}); uphill: resting "
          f"on another face >= {a.gain} m higher; brake {'on' if s.brake else 'off'}, ramp "
          f"{s.ramp_rate} MPa/s, up to {ws.max_pressure} MPa")
    rows = []
    for sl in a.slopes:
        terrain = Terrain.slope(sl)
        state = d.State.concat([gv.place(params, f, terrain, (0.0, 0.0), h, len(actions))
                                for _, f, h in poses])

        def ctl(b, obs):
            brake = Brake(ws, s.brake_margin, terrain=terrain, min_tilt=s.brake_tilt) if s.brake else None
            face, obs = yield from _settle_gen(s, obs, brake)
            if face is None:
                return "fell", None
            res, _ = yield from _roll_gen(params, s, obs, actions[b % len(actions)], ws.max_pressure, brake)
            return face, res

        t0 = time.perf_counter()
        out = lockstep(params, terrain, state, ctl, s)
        wall = time.perf_counter() - t0
        kinds = collections.Counter()
        stood, up_single, up_combo, across, down, best = 0, 0, 0, 0, 0, {}
        for i, (kind, f, h) in enumerate(poses):
            res = [out[i * len(actions) + n][0] for n in range(len(actions))]
            if any(r[0] == "fell" for r in res):
                kinds["fell before the roll"] += len(actions)
                continue
            stood += 1
            ups, ways = [], set()
            for act, (_, r) in zip(actions, res):
                gain = r.cog_after[0] - r.cog_before[0]
                if r.face_after is None:
                    kinds["tumbled"] += 1
                elif not r.rolled:
                    kinds["not rolled"] += 1
                elif gain >= a.gain:
                    kinds["uphill"] += 1
                    ups.append((r.tip_pressure, act, gain))
                else:
                    way = "downhill" if gain <= -a.gain else "across"
                    kinds[way] += 1
                    ways.add(way)
            up_single += any(len(u[1]) == 1 for u in ups)
            up_combo += any(len(u[1]) == 2 for u in ups)
            across += "across" in ways
            down += "downhill" in ways
            if ups:
                best[(kind, h)] = min(ups)
        print(f"\n== slope {sl:g} deg: {state.batch} rolls, wall {wall:.0f} s")
        print(f"poses that stand (braked where the brake acts): {stood}/{len(poses)}")
        print(f"poses with an uphill roll: by a single pair {up_single}, by a combination {up_combo}")
        print(f"poses with a controlled roll (resting on a face after it): across {across}, downhill {down}")
        print("outcomes: " + ", ".join(f"{k} {v}" for k, v in kinds.most_common()))
        for (kind, h), (p, act, g) in sorted(best.items()):
            print(f"  {kind:11s} heading {h:5.1f} deg: least-pressure uphill roll "
                  f"{'+'.join(f'#{q}' for q in act)} at {p:.2f} MPa, {g:.2f} m up")
        rolled = sum(kinds[k] for k in ("uphill", "across", "downhill", "tumbled"))
        rows.append((sl, f"{stood}/{len(poses)}", up_single, up_combo, across, down, kinds["uphill"],
                     f"{kinds['tumbled']} ({100 * kinds['tumbled'] / max(rolled, 1):.0f} %)"))
    print("\n| slope deg | poses standing | uphill by a single pair | uphill by a combination | across "
          "| downhill | uphill rolls | tumbles (of the rolls) |\n|---|---|---|---|---|---|---|---|")
    for r in rows:
        print("| " + " | ".join(str(v) for v in r) + " |")


if __name__ == "__main__":
    main()
