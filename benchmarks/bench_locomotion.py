"""Goal-directed rolling judged on cases drawn at random (issue 30 item 4). Prints figures;
asserts nothing.

Every case of a ground draws, from its seed, a goal direction, the slope's uphill azimuth and the
robot's start yaw (about the terrain normal), uniform in [0, 360) deg, and for random terrain the
terrain's own seed; the goal is `--distance` m (default 2 m) from the start. The start pose is
chosen as `tensegrity roll` chooses it when no face is given (`--face auto`, default;
`locomotion.start.choose` at the drawn yaw, given the goal: the paper's (9,10,12) if it stands
there and a first roll from it toward the goal lands and gains, else the first standing face
that has such a roll (else a detour, else one that stands); where none stands, a pose at another
yaw; where no pose stands at all, (9,10,12) at yaw 0, from which the robot settles first; the
CPU of the choice is printed per case, apart from the planning CPU), or
is `--face` at the drawn yaw whether it stands or not (e.g. `--face 9,10,12`, the runs before
issue 30). Seeds come from one of two
disjoint, named sets: TUNING_SEEDS, the only ones any constant of the planner may be tuned on, and
EVALUATION_SEEDS (default), the ones a report quotes, drawn at random once (numpy
default_rng(30).choice(10**6), below) and never looked at while tuning.

Grounds (`--grounds`, default all): flat; terrain0.03/0.05/0.07 (random terrain of that height
std, m); slope10/15/20/24/28 (a plane of that angle, deg); terrain0.03-slope15 (random terrain
0.03 m on a 15 deg slope). A plane slope is simulated with its uphill along +x and the goal
turned by minus the drawn azimuth (a plane's physics does not change under a turn about the
vertical), so that all cases of that ground run as one batch; the yaw passed to `stand_on` is
turned too, which is not exactly a turn of the pose about the vertical (stand_on's yaw 0 depends
on the normal), but the yaw is uniform in [0, 360) either way: the same distribution of cases.

Per ground: arrival rate with its 95 % Wilson score interval (E. B. Wilson, J. Am. Stat. Assoc.
22 (1927) 209; scipy's binomtest(...).proportion_ci(method="wilson")), outcomes, tumbles (runs
in which a roll left the robot on no face, ended on no face or slid its CoG more than
lookahead.SLIDE = 0.5 m), rolls per metre
of the arrived runs, planning CPU seconds per roll (`Step.plan_cpu`: the plan and the rolls
simulated ahead, process time of all threads; with `Run.stuck_cpu`, a last plan that made no
roll) and wall time (inflated on a busy machine). A markdown table closes the output.

A model error (`--world KEY=VALUE ...`, fields of `Params`, e.g. `friction=0.6`): the simulated
robot and ground take these values while the planner (its start choice and every roll it
simulates ahead) keeps the configuration's; without it the planner's model is exact.

Usage: python benchmarks/bench_locomotion.py [--workspace results/workspace.nc]
       [--two-pair results/workspace_two_pair.nc | none] [--cases 8] [--seeds evaluation|tuning]
       [--grounds flat slope15 ...] [--distance 2.0] [--face 9,10,12] [--set key=value ...]
       [--configfile volts.yaml] [--world friction=0.6 ...]
       [--steps] [--tiny]
`--tiny` (the test suite's): one case on flat and on slope15, 0.6 m away.
Without the workspace file, one is computed first with the default configuration (~30 s).
"""

from __future__ import annotations

import argparse
import collections
import dataclasses
import tempfile
import time
import zlib
from pathlib import Path

import numpy as np
import yaml
from scipy.stats import binomtest

from tensegrity import locomotion as lo
from tensegrity.cli import progress
from tensegrity.io import config, formats
from tensegrity.io import settings as io_settings
from tensegrity.locomotion import lookahead, outcome, start
from tensegrity.physics import dynamics as d
from tensegrity.physics import topology as topo
from tensegrity.physics.terrain import Terrain

TUNING_SEEDS = tuple(range(1, 65))  # the planner's constants are tuned on these only
EVALUATION_SEEDS = tuple(int(x) for x in np.random.default_rng(30).choice(np.arange(1000, 10**6), 64, replace=False))
GROUNDS = {  # name: (terrain height std m, slope deg)
    "flat": (0.0, 0.0),
    "terrain0.03": (0.03, 0.0),
    "terrain0.05": (0.05, 0.0),
    "terrain0.07": (0.07, 0.0),
    "slope10": (0.0, 10.0),
    "slope15": (0.0, 15.0),
    "slope20": (0.0, 20.0),
    "slope24": (0.0, 24.0),
    "slope28": (0.0, 28.0),
    "terrain0.03-slope15": (0.03, 15.0),
}


def wilson(k: int, n: int) -> tuple[float, float]:
    """95 % Wilson score interval (low, high) of a proportion k/n (Wilson 1927), by scipy."""
    ci = binomtest(k, n).proportion_ci(0.95, method="wilson")
    return float(ci.low), float(ci.high)


def draw(ground: str, seed: int) -> dict:
    """The case of `ground` drawn from `seed`: goal, azimuth, yaw (deg), terrain seed."""
    rng = np.random.default_rng([seed, zlib.crc32(ground.encode())])
    goal, azimuth, yaw = rng.uniform(0.0, 360.0, 3)
    return dict(goal=goal, azimuth=azimuth, yaw=yaw, terrain_seed=int(rng.integers(2**31)))


def terrain_of(ground: str, case: dict, distance: float) -> tuple[Terrain, float]:
    """The terrain of a case and the turn (deg) applied to its goal and yaw (see the docstring)."""
    amp, slope = GROUNDS[ground]
    if amp == 0.0:
        return (Terrain.flat() if slope == 0.0 else Terrain.slope(slope, 0.0)), -case["azimuth"]
    t = Terrain.random(case["terrain_seed"], size=2 * distance + 4.0, amplitude=amp)
    if slope:
        n, m = t.heights.shape
        x = t.origin[0] + t.spacing * np.arange(n)[:, None]
        y = t.origin[1] + t.spacing * np.arange(m)[None, :]
        a = np.radians(case["azimuth"])
        tilt = np.tan(np.radians(slope)) * (x * np.cos(a) + y * np.sin(a))
        t = Terrain(kind="heightfield", origin=t.origin, spacing=t.spacing, heights=t.heights + tilt)
    return t, 0.0


class NoStart:
    """A case in which no start pose stands (`start.choose` refused it): not arrived."""

    outcome, rolls, steps, travelled, distance_to_goal = "no_start", 0, (), 0.0, float("nan")
    faces, start_face, stuck_cpu = [], None, 0.0

    def __init__(self, message: str):
        self.message = message


def tumbled(run: lo.Run) -> bool:
    """A roll left the robot on no face or slid it more than lookahead.SLIDE m."""
    if run.outcome == "no_contact":
        return True
    return any(a.face_after is None or lookahead.moved(a) > lookahead.SLIDE for st in run.steps for a in st.attempts)


def run_ground(ground, seeds, a, ws, params, settings, face, world=None) -> list[tuple[dict, lo.Run]]:
    """Every case of one ground, batched where they share a terrain; the robot and ground
    simulated with `world` (Params; None: `params`, the planner's model)."""
    world = world or params
    cases = [draw(ground, sd) for sd in seeds]
    groups = collections.defaultdict(list)
    for i, c in enumerate(cases):
        t, turn = terrain_of(ground, c, a.distance)
        groups[id(t) if t.kind == "heightfield" else "plane"].append((i, t, turn))
    out: list = [None] * len(cases)
    for members in groups.values():
        terrain = members[0][1]
        poses = []
        for i, _, turn in members:
            head = np.radians(cases[i]["goal"] + turn)
            goal = a.distance * np.array([np.cos(head), np.sin(head)])
            try:
                st = None
                if face is None:  # the drawn yaw if a face stands there, else any yaw
                    try:
                        st = start.choose(ws, params, terrain, settings, None, cases[i]["yaw"] + turn, goal=goal)
                    except ValueError:  # any yaw; if none stands, it settles from (9,10,12) first
                        st = start.choose(ws, params, terrain, settings, goal=goal)
                    cases[i]["start_cpu"], cases[i]["start"] = st.cpu, st.message
                poses.append((face, cases[i]["yaw"] + turn) if st is None else (st.face, st.yaw_deg))
            except ValueError as e:
                out[i] = (cases[i], NoStart(str(e)))
        members = [m for m in members if out[m[0]] is None]
        if not members:
            continue
        heads = np.radians([cases[i]["goal"] + turn for i, _, turn in members])
        goals = a.distance * np.stack([np.cos(heads), np.sin(heads)], axis=1)
        state = d.State.concat([d.stand_on(world, f, terrain, yaw_deg=y) for f, y in poses])
        with progress.bar(None, ground, leave=False) as bar:
            runs = lo.roll_many(
                ws, goals, world, terrain, state=state, settings=settings, progress=bar.update, model=params
            )
        for (i, _, _), r in zip(members, runs):
            out[i] = (cases[i], r)
    return out


def report(ground: str, res: list[tuple[dict, lo.Run]], wall: float, tol: float) -> dict:
    """Print one ground; return its row of the table."""
    runs = [r for _, r in res]
    n, k = len(runs), sum(r.outcome == "arrived" for r in runs)
    lo_, hi = wilson(k, n)
    done = [r for r in runs if r.outcome == "arrived"]
    starts = collections.Counter(topo.face_label(r.faces[0]) for r in runs if r.faces)
    rpm = sum(r.rolls for r in done) / sum(r.travelled for r in done) if done else float("nan")
    rolls = sum(r.rolls for r in runs)
    cpu = sum(sum(st.plan_cpu for st in r.steps) + r.stuck_cpu for r in runs) / max(rolls, 1)
    outcomes = ", ".join(f"{o} {v}" for o, v in collections.Counter(r.outcome for r in runs).most_common())
    tum = sum(tumbled(r) for r in runs)
    start_cpu = [c.get("start_cpu", 0.0) for c, _ in res]
    print(f"\n== {ground}: {n} cases")
    print(f"arrived within {tol} m: {k}/{n} = {100 * k / n:.0f} % (95 % Wilson {100 * lo_:.0f}-{100 * hi:.0f} %)")
    print(f"outcomes: {outcomes}; runs with a tumble: {tum}")
    print("start faces: " + ", ".join(f"{f} {v}" for f, v in starts.most_common()))
    print(f"rolls {rolls}; rolls per metre of the arrived runs {rpm:.2f}; planning CPU {cpu:.2f} s per roll")
    print(f"start choice CPU {np.mean(start_cpu):.2f} s per case (max {max(start_cpu):.2f} s)")
    print(f"wall {wall:.1f} s")
    for c, r in res:
        if r.outcome != "arrived":
            print(
                f"  goal {c['goal']:.0f} deg, azimuth {c['azimuth']:.0f} deg, yaw {c['yaw']:.0f} deg -> "
                f"{r.outcome} after {r.rolls} rolls, {r.distance_to_goal:.2f} m from the goal: {r.message}"
            )
    return dict(
        ground=ground,
        arrived=f"{k}/{n}",
        ci=f"{100 * lo_:.0f}-{100 * hi:.0f} %",
        outcomes=outcomes,
        tumbles=tum,
        rpm=rpm,
        cpu=cpu,
        start_cpu=float(np.mean(start_cpu)),
    )


def steps(res: list[tuple[dict, lo.Run]], unit: str) -> None:
    """Every step of every run: faces, action, tip level (in `unit`: MPa or V), CoG change,
    planning CPU."""
    for c, r in res:
        print(f"  goal at {c['goal']:.0f} deg: {r.outcome}, faces {r.faces}")
        if "start" in c:
            print(f"    {c['start']}")
        for st in r.steps:
            u = st.used
            dz = 1e3 * (u.cog_after[2] - u.cog_before[2])
            print(
                f"    {topo.face_label(st.face)} -> "
                f"{topo.face_label(st.face_after) if st.face_after else 'no face'} by "
                f"{'+'.join(f'#{p}' for p in u.pairs)}{outcome.action_kind(u)}, tip {u.tip_pressure:.2f} {unit}, "
                f"CoG {dz:+.0f} mm up, planning {st.plan_cpu:.2f} s CPU"
            )
        if r.stuck_cpu:  # the last plan made no roll (none of its simulated rolls acceptable)
            print(f"    no roll from {topo.face_label(r.faces[-1])}: planning {r.stuck_cpu:.2f} s CPU")


def workspace(path: str, two_pair: str | None) -> lo.Workspace:
    if Path(path).is_file():
        return formats.read_workspace(path, two_pair)
    from tensegrity.stages import nominal as nominal_stage
    from tensegrity.stages import sweep as sweep_stage
    from tensegrity.stages.config import stage_config

    print(f"{path} not found: computing the workspace with the default configuration")
    cfg = config.load()
    with tempfile.TemporaryDirectory() as tmp:
        nominal = [
            nominal_stage.nominal(
                stage_config(cfg, "nominal"),
                sweep_stage.sweep(stage_config(cfg, "sweep"), c, f"{tmp}/{c}"),
                f"{tmp}/{c}.nc",
            )
            for c in cfg["sweep"]["contacts"]
        ]
        return formats.read_workspace(nominal_stage.workspace({}, nominal, f"{tmp}/workspace.nc"), two_pair)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--workspace", default="results/workspace.nc")
    ap.add_argument("--two-pair", default="results/workspace_two_pair.nc", help="'none': superposed combinations")
    ap.add_argument("--cases", type=int, default=8, help="cases per ground (the first N seeds of the set)")
    ap.add_argument("--seeds", choices=["evaluation", "tuning"], default="evaluation")
    ap.add_argument("--grounds", nargs="+", choices=list(GROUNDS), default=list(GROUNDS))
    ap.add_argument("--distance", type=float, default=2.0, help="goal distance, m")
    ap.add_argument("--face", default="auto", help="start face a,b,c at the drawn yaw; 'auto' (default): as roll")
    ap.add_argument("--configfile", help="a YAML file merged over config/config.yaml (e.g. the volts table)")
    ap.add_argument("--set", nargs="+", default=[], metavar="KEY=VALUE", help="override RollSettings")
    ap.add_argument("--world", nargs="+", default=[], metavar="KEY=VALUE", help="the simulated robot's Params")
    ap.add_argument("--steps", action="store_true", help="print every step of every run")
    ap.add_argument("--tiny", action="store_true", help="one case on flat and slope15, 0.6 m away")
    a = ap.parse_args()
    if a.tiny:
        a.cases, a.grounds, a.distance = 1, ["flat", "slope15"], 0.6
    try:
        cfg = config.load(a.configfile)
    except (OSError, config.ConfigError) as e:
        ap.error(f"--configfile {a.configfile}: {e}")
    params = io_settings.params(cfg)
    if a.distance < float(params.strut_length):
        ap.error(f"--distance {a.distance} m is less than the robot's size (strut length {params.strut_length} m)")
    if not 1 <= a.cases <= 64:
        ap.error(f"--cases {a.cases}: 1 to 64 (the size of each seed set)")
    try:
        face = None if a.face == "auto" else topo.face_number([int(x) for x in a.face.split(",")])
    except ValueError as e:
        ap.error(f"--face {a.face}: {e}")
    try:
        over = {k: yaml.safe_load(v) for k, v in (kv.split("=", 1) for kv in a.set)}
        unknown = set(over) - set(lo.RollSettings.__dataclass_fields__)
        if unknown:
            raise KeyError(f"unknown locomotion setting(s) {sorted(unknown)}")
        settings = io_settings.build(lo.RollSettings, config.merge(cfg, {"locomotion": over}))
    except (ValueError, KeyError) as e:
        ap.error(f"--set {' '.join(a.set)}: {e}")
    try:
        world = dataclasses.replace(params, **{k: yaml.safe_load(v) for k, v in (kv.split("=", 1) for kv in a.world)})
    except (ValueError, TypeError) as e:
        ap.error(f"--world {' '.join(a.world)}: {e}")
    two = None if a.two_pair.lower() == "none" or not Path(a.two_pair).is_file() else a.two_pair
    ws = workspace(a.workspace, two)
    seeds = (EVALUATION_SEEDS if a.seeds == "evaluation" else TUNING_SEEDS)[: a.cases]
    print(
        f"{a.cases} {a.seeds} cases per ground (seeds {', '.join(map(str, seeds))}); goals {a.distance} m away; "
        f"start face {a.face}; combinations "
        + ("from the two-pair workspace" if two else "superposed")
        + (f"; the world's {', '.join(a.world)}, the planner's model the configuration's" if a.world else "")
    )
    rows = []
    for g in a.grounds:
        t0 = time.perf_counter()
        res = run_ground(g, seeds, a, ws, params, settings, face, world)
        rows.append(report(g, res, time.perf_counter() - t0, settings.arrive_tolerance))
        if a.steps:
            steps(res, settings.unit)
    print(
        "\n| ground | arrived | 95 % Wilson | outcomes | runs with a tumble | rolls/m | planning CPU s/roll "
        "| start CPU s/case |\n|---|---|---|---|---|---|---|---|"
    )
    for r in rows:
        print(
            f"| {r['ground']} | {r['arrived']} | {r['ci']} | {r['outcomes']} | {r['tumbles']} | "
            f"{r['rpm']:.2f} | {r['cpu']:.2f} | {r['start_cpu']:.2f} |"
        )


if __name__ == "__main__":
    main()
