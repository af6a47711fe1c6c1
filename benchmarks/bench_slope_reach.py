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
roll). All rolls of a slope are one batch. Then the best repeatable gaits uphill and across
that these rolls suggest (`gaits`: cycles in the graph of poses and the rolls that land; a
candidate to check by simulation, not a proof); `--headings 24` gives the graph enough poses.

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
from tensegrity.io import settings as io_settings
from tensegrity.locomotion import lookahead
from tensegrity.locomotion.brake import Brake
from tensegrity.locomotion.control import roll_controller, settle_controller
from tensegrity.locomotion.lockstep import lockstep
from tensegrity.physics import dynamics as d
from tensegrity.physics import topology as topo
from tensegrity.physics.terrain import Terrain
from tensegrity.workspace import mapping
from tensegrity.workspace.slopes import heading_of, place


def gaits(landings: list, headings: np.ndarray, longest: int = 6) -> None:
    """Print the best repeatable gait uphill (+x) and across (+y) that the rolls of one slope
    suggest: a cycle of at most `longest` rolls in the graph whose states are the contact case,
    the uphill heading in its support frame as settled (to the nearest of `headings`, deg) and
    the parity of the face's map from the canonical face (a mirror image rolls across the other
    way), whose edges are the rolls that land on a face (no slide, `lookahead.lands`), with the
    CoG's move.
    The graph assumes a landing posed like the canonical face at that heading rolls like it;
    a cycle is a candidate gait, to be checked by simulation, not a proof."""
    n = len(headings)
    sid = {key: i for i, key in enumerate(itertools.product(topo.CONTACT_FACES, range(n), (1, -1)))}

    def pose(nodes: np.ndarray, face: int, parity: int) -> int:
        """The state of the robot `nodes` resting on `face`, its pose seen from a start of
        `parity`: the face's kind, the canonical heading of uphill to the nearest sample, parity."""
        diag = mapping.face_map(face)[2]  # x flips (-1) where the face mirrors the canonical one
        h = np.radians(float(heading_of(nodes, face)))
        hc = np.degrees(np.arctan2(np.sin(h) * diag[1], np.cos(h) * diag[0]))  # canonical frame
        b = int(np.round(hc % 360.0 / (360.0 / n))) % n
        return sid[str(topo.FACE_TYPES[face - 1]), b, parity * int(diag[0])]

    edges = []  # (from, to, canonical action, CoG move (3,) m, world)
    for face0, start, act, face, end, move in landings:  # face0: canonical (the pose's)
        for p in (1, -1):
            edges.append((pose(start, face0, p), pose(end, face, p), act, move * [1.0, p, 1.0]))
    for name, axis in (("uphill", 0), ("across", 1)):
        # across: the most across of the cycles that lose no height (mean uphill move >= 0),
        # found by weighting the uphill move more and more
        for lam in (0.0,) if axis == 0 else (0.0, 0.25, 0.5, 1.0, 2.0, 4.0):
            best = _best_cycle(len(sid), edges, np.eye(3)[axis] + [lam, 0.0, 0.0], longest)
            moves = np.array([e[3] for e in best or [(0, 0, (), np.zeros(3))]])  # (rolls, 3) m
            if moves[:, 0].mean() >= 0.0:
                break
        if best is None or moves[:, 0].mean() < 0.0 or moves[:, axis].mean() < 1e-3:
            print(
                f"  no {name} gait: no cycle of landings"
                + ("" if best is None else " that moves that way and keeps its height")
            )
            continue
        acts = ", ".join("+".join(f"#{q}" for q in e[2]) for e in best)
        print(
            f"  best {name} gait ({len(best)} rolls, pairs of the canonical faces: {acts}): per roll "
            f"{1e3 * moves[:, 0].mean():+.0f} mm uphill (x), {1e3 * moves[:, 1].mean():+.0f} mm across (y), "
            f"{1e3 * moves[:, 2].mean():+.0f} mm up"
        )


def _best_cycle(size: int, edges: list, weight: np.ndarray, longest: int) -> list | None:
    """The edges of the cycle of at most `longest` edges with the largest mean of the moves
    (3,) m weighted by `weight` (3,) (max-plus matrix powers), None if there is no cycle."""
    w = np.full((size, size), -np.inf)
    pick: dict = {}
    for a, b, act, move in edges:
        if move @ weight > w[a, b]:
            w[a, b], pick[a, b] = move @ weight, (a, b, act, move)
    walks, back, best = [w], [None], (-np.inf, 0, 0)
    for _ in range(2, longest + 1):
        m = walks[-1][:, :, None] + w[None, :, :]
        back.append(m.argmax(axis=1))
        walks.append(m.max(axis=1))
    for k, wk in enumerate(walks, 1):
        v = int(np.argmax(np.diag(wk)))
        if wk[v, v] / k > best[0] + 1e-12:
            best = (wk[v, v] / k, k, v)
    if not np.isfinite(best[0]):
        return None
    _, k, v = best
    path = [v]
    for j in range(k, 1, -1):
        path.append(int(back[j - 1][v, path[-1]]))
    path = [v] + path[::-1]
    return [pick[path[i], path[i + 1]] for i in range(k)]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--workspace", default="results/workspace.nc")
    ap.add_argument("--slopes", nargs="+", type=float, default=[15, 20, 24], help="slope angles, deg")
    ap.add_argument("--headings", type=int, default=8, help="headings of the uphill direction per face")
    ap.add_argument("--gain", type=float, default=0.05, help="least uphill CoG gain of a roll, m")
    ap.add_argument(
        "--combos",
        action=argparse.BooleanOptionalAction,
        default=True,
        help="also every two-pair combination (default)",
    )
    a = ap.parse_args()
    if a.headings < 1:
        ap.error(f"--headings {a.headings}: at least one")
    cfg = config.load()
    s = io_settings.build(lo.RollSettings, cfg)
    params = s.rolling(io_settings.params(cfg))
    for sl in a.slopes:
        Terrain.slope(sl)  # a bad angle stops here, before any work
    ws = formats.read_workspace(a.workspace)
    actions = [(p,) for p in range(1, topo.N_PAIRS + 1)]
    if a.combos:
        actions += list(itertools.combinations(range(1, topo.N_PAIRS + 1), 2))
    headings = np.arange(a.headings) * 360.0 / a.headings
    faces = {k: topo.face_number(v) for k, v in topo.CONTACT_FACES.items()}
    poses = [(k, f, h) for k, f in faces.items() for h in headings]
    print(
        f"{len(poses)} poses ({', '.join(faces)} x {a.headings} headings) x {len(actions)} actions "
        f"({'singles and two-pair combinations' if a.combos else 'single pairs'}); uphill: resting "
        f"on another face >= {a.gain} m higher; brake {'on' if s.brake else 'off'}, ramp "
        f"{s.ramp_rate} MPa/s, up to {ws.max_pressure} MPa"
    )
    rows = []
    for sl in a.slopes:
        terrain = Terrain.slope(sl)
        state = d.State.concat([place(params, f, terrain, (0.0, 0.0), h, len(actions)) for _, f, h in poses])

        def ctl(b, obs, terrain=terrain):
            brake = Brake(ws, s.brake_margin) if s.brake else None
            face, obs = yield from settle_controller(s, obs, brake)
            if face is None:
                return "fell", None
            act = actions[b % len(actions)]
            res, ob = yield from roll_controller(params, s, obs, act, ws.max_pressure, brake)
            return face, (res, obs.nodes, ob.nodes)

        t0 = time.perf_counter()
        out = lockstep(params, terrain, state, ctl, s)
        wall = time.perf_counter() - t0
        kinds, landings = collections.Counter(), []
        stood, up_single, up_combo, across, down, best = 0, 0, 0, 0, 0, {}
        for i, (kind, f, h) in enumerate(poses):
            res = [out[i * len(actions) + n][0] for n in range(len(actions))]
            if any(r[0] == "fell" for r in res):
                kinds["fell before the roll"] += len(actions)
                continue
            stood += 1
            ups, ways = [], set()
            for act, (_, (r, start, end)) in zip(actions, res):
                gain = r.cog_after[0] - r.cog_before[0]
                if r.rolled and lookahead.lands(r, lookahead.SLIDE) and r.face_before == f:
                    landings.append(
                        (r.face_before, start, act, r.face_after, end, np.subtract(r.cog_after, r.cog_before))
                    )
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
            print(
                f"  {kind:11s} heading {h:5.1f} deg: least-pressure uphill roll "
                f"{'+'.join(f'#{q}' for q in act)} at {p:.2f} MPa, {g:.2f} m up"
            )
        gaits(landings, headings)
        rolled = sum(kinds[k] for k in ("uphill", "across", "downhill", "tumbled"))
        rows.append(
            (
                sl,
                f"{stood}/{len(poses)}",
                up_single,
                up_combo,
                across,
                down,
                kinds["uphill"],
                f"{kinds['tumbled']} ({100 * kinds['tumbled'] / max(rolled, 1):.0f} %)",
            )
        )
    print(
        "\n| slope deg | poses standing | uphill by a single pair | uphill by a combination | across "
        "| downhill | uphill rolls | tumbles (of the rolls) |\n|---|---|---|---|---|---|---|---|"
    )
    for r in rows:
        print("| " + " | ".join(str(v) for v in r) + " |")


if __name__ == "__main__":
    main()
