"""Goal-directed rolling where it can fail (issue 4 item 6, issue 10 item 5). Prints figures;
asserts nothing.

Goals `--distance` m away (default 2 m) in `--directions` evenly spaced directions (default 8;
direction 0 is +x, which is uphill on the slopes) from the robot standing on (9,10,12) at the
origin, on each scenario:
- flat: flat ground;
- terrain: seeded random terrain, height std `--amplitudes` (0.03, 0.05 m) x `--seeds` (1, 2, 3);
- slope: planes rising toward +x by `--slopes` deg (10, 15, 20, 24); the runs are also reported
  per class of goal direction: uphill (within 45 deg of +x), across (+-90 deg), downhill.
Per scenario: arrival rate within the arrival tolerance (config, 0.3 m), outcomes, rolls per
metre (rolls of the arrived runs over their net distance: a tumble is no progress), mean
pressure at which the rolls tipped, wall time (inflated on a busy
machine). A summary table closes the output. All runs of a scenario are one batch
(`locomotion.roll_many`); each equals its single run.

Usage: python benchmarks/bench_locomotion.py [--workspace results/workspace.nc]
       [--two-pair results/workspace_two_pair.nc | none] [--directions 8] [--heading-seed S]
       [--distance 2.0]
       [--only flat terrain slope] [--amplitudes 0.03 0.05] [--seeds 1 2 3]
       [--slopes 10 15 20 24] [--strut-damping 1.0] [--set brake=true escape_attempts=0 ...]
       [--steps]
Without the workspace file, one is computed first with the default configuration (~30 s).
`--runs` is a synonym of `--directions`.
"""

from __future__ import annotations

import argparse
import collections
import dataclasses
import tempfile
import time
from pathlib import Path

import numpy as np
import yaml

from tensegrity import locomotion as lo
from tensegrity.cli import progress
from tensegrity.io import config, formats
from tensegrity.io import settings as io_settings
from tensegrity.locomotion import lookahead
from tensegrity.physics.terrain import Terrain


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


def _cls(heading_deg: float) -> str:
    """uphill / across / downhill for a goal direction (deg from +x, the uphill direction)."""
    a = abs((heading_deg + 180.0) % 360.0 - 180.0)
    return "uphill" if a < 67.5 else ("across" if a <= 112.5 else "downhill")


def _rate(runs: list[lo.Run]) -> str:
    n = sum(r.outcome == "arrived" for r in runs)
    return f"{n}/{len(runs)} = {100 * n / max(len(runs), 1):.0f} %"


def report(name: str, runs: list[lo.Run], headings: np.ndarray, wall: float, tol: float, by_class: bool) -> dict:
    """Print one scenario; return its row of the summary table."""
    n = len(runs)
    rolls = sum(r.rolls for r in runs)
    done = [r for r in runs if r.outcome == "arrived"]
    rpm = sum(r.rolls for r in done) / sum(r.travelled for r in done) if done else float("nan")
    tips = [
        a.tip_pressure for r in runs for st in r.steps for a in st.attempts if a.rolled and np.isfinite(a.tip_pressure)
    ]
    combos = sum(1 for r in runs for st in r.steps if st.rolled and len(st.used.pairs) > 1)
    outcomes = ", ".join(f"{k} {v}" for k, v in collections.Counter(r.outcome for r in runs).most_common())
    tip = float(np.mean(tips)) if tips else float("nan")
    print(f"\n== {name}: {n} runs")
    print(f"arrived within {tol} m: {_rate(runs)}")
    print(f"outcomes: {outcomes}")
    if by_class:
        for c in ("uphill", "across", "downhill"):
            sel = [r for r, h in zip(runs, headings) if _cls(h) == c]
            if sel:
                print(
                    f"  {c:8s}: arrived {_rate(sel)}; "
                    + ", ".join(f"{k} {v}" for k, v in collections.Counter(r.outcome for r in sel).most_common())
                )
    print(
        f"final distance to goal: median {np.median([r.distance_to_goal for r in runs]):.3f} m, "
        f"max {max(r.distance_to_goal for r in runs):.3f} m"
    )
    print(f"rolls: {rolls} ({combos} with two pairs); rolls per metre of the arrived runs {rpm:.2f}")
    moves = [lookahead.moved(st.used) for r in runs for st in r.steps if st.rolled]
    if moves:  # a roll moves the CoG 0.1-0.3 m; more is a slide down a slope, not a controlled roll
        print(
            f"rolls that moved the CoG more than {lookahead.SLIDE} m (slides): "
            f"{sum(m > lookahead.SLIDE for m in moves)} of {len(moves)}, largest {max(moves):.2f} m"
        )
    print(
        f"pressure at which the rolls tipped: mean {tip:.2f} MPa"
        + (f" (min {np.min(tips):.2f}, max {np.max(tips):.2f})" if tips else " (no roll)")
    )
    seen = [st.simulated for r in runs for st in r.steps if st.simulated]
    if seen:  # what the lookahead saw: how far the robot's reach goes from each face
        best = np.array(
            [
                max(
                    (x.cog_after[2] - x.cog_before[2] for x in sim if x.rolled and x.face_after is not None),
                    default=np.nan,
                )
                for sim in seen
            ]
        )
        falls = sum(x.face_after is None for sim in seen for x in sim)
        print(
            f"lookahead: {len(seen)} steps, {sum(map(len, seen))} rolls simulated, "
            f"{100 * falls / sum(map(len, seen)):.0f} % of them tumble; the best height change of a roll "
            f"that lands: median {1e3 * np.nanmedian(best):+.0f} mm, below 0 on "
            f"{np.mean(~(best >= 0)) * 100:.0f} % of the steps"
        )
    print(f"wall {wall:.1f} s for the batch ({wall / n:.2f} s per run)")
    for r, h in [(r, h) for r, h in zip(runs, headings) if r.outcome != "arrived"][:8]:
        print(f"  not arrived: goal at {h:.0f} deg -> {r.outcome} after {r.rolls} rolls: {r.message}")
    return dict(name=name, rate=_rate(runs), outcomes=outcomes, rpm=rpm, tip=tip)


def steps(runs: list[lo.Run], headings: np.ndarray) -> None:
    """Every step of every run: the face and its type, the heading of +x (uphill on the slopes)
    in its support frame when the roll began, the action, the tip pressure and the CoG's change."""
    from tensegrity.physics import topology as topo
    from tensegrity.workspace.slopes import heading_of

    for r, h in zip(runs, headings):
        print(f"  goal at {h:.0f} deg: {r.outcome}, faces {r.faces}")
        for st in r.steps:
            a = st.used
            k = min(int(np.searchsorted(r.record.t, a.t_start)), len(r.record.t) - 1)
            d = 1e3 * (np.asarray(a.cog_after) - np.asarray(a.cog_before))
            print(
                f"    {topo.face_label(st.face)} {topo.FACE_TYPES[st.face - 1]:11s} +x at "
                f"{float(heading_of(r.record.nodes[k], st.face)):6.1f} deg -> "
                f"{topo.face_label(st.face_after) if st.face_after else 'no face'} by "
                f"{'+'.join(f'#{p}' for p in a.pairs)}, tip {a.tip_pressure:.2f} MPa; CoG "
                f"{d[2]:+.0f} mm up, {d[0]:+.0f} mm along +x"
            )


def scenarios(a: argparse.Namespace) -> list[tuple[str, Terrain, bool]]:
    """(name, terrain, report per direction class) of every scenario asked for."""
    size = 2 * a.distance + 4.0
    out = []
    if "flat" in a.only:
        out.append(("flat ground", Terrain.flat(), False))
    if "terrain" in a.only:
        out += [
            (f"terrain std {amp} m seed {seed}", Terrain.random(seed, size=size, amplitude=amp), False)
            for amp in a.amplitudes
            for seed in a.seeds
        ]
    if "slope" in a.only:
        out += [(f"slope {s:g} deg", Terrain.slope(s, 0.0), True) for s in a.slopes]
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--workspace", default="results/workspace.nc")
    ap.add_argument(
        "--two-pair",
        default="results/workspace_two_pair.nc",
        help="two-pair workspace, as the pipeline's demonstration runs plan with (default, if "
        "the file exists); 'none' or a missing file: combinations are superposed",
    )
    ap.add_argument("--directions", "--runs", type=int, default=8, help="number of goal directions")
    ap.add_argument(
        "--heading-seed",
        type=int,
        default=None,
        help="draw the goal directions at random, uniform in [0, 360) deg, from this seed "
        "(default: evenly spaced from 0 deg)",
    )
    ap.add_argument("--distance", type=float, default=2.0, help="goal distance, m")
    ap.add_argument("--only", nargs="+", choices=["flat", "terrain", "slope"], default=["flat", "terrain", "slope"])
    ap.add_argument("--amplitudes", nargs="+", type=float, default=[0.03, 0.05], help="terrain height std, m")
    ap.add_argument("--seeds", nargs="+", type=int, default=[1, 2, 3], help="terrain seeds")
    ap.add_argument("--slopes", nargs="+", type=float, default=[10, 15, 20, 24], help="slope angles, deg")
    ap.add_argument(
        "--set",
        nargs="+",
        default=[],
        metavar="KEY=VALUE",
        help="override locomotion settings (RollSettings), e.g. brake=true escape_attempts=0",
    )
    ap.add_argument(
        "--steps",
        action="store_true",
        help="print every step of every run: face, heading of +x in its frame, action, CoG change",
    )
    ap.add_argument(
        "--strut-damping",
        type=float,
        default=None,
        help="strut damping of the rolling simulations, 1/s (default: config locomotion.strut_damping)",
    )
    a = ap.parse_args()
    cfg = config.load()
    params = io_settings.params(cfg)
    if a.distance < float(params.strut_length):  # roll_many refuses goals closer than the robot
        ap.error(f"--distance {a.distance} m is less than the robot's size (strut length {params.strut_length} m)")
    if a.directions < 1:
        ap.error(f"--directions {a.directions}: at least one direction")
    cases = scenarios(a)  # bad slopes etc. raise here, before any work
    try:
        over = {k: yaml.safe_load(v) for k, v in (kv.split("=", 1) for kv in a.set)}
        settings = io_settings.build(lo.RollSettings, config.merge(cfg, {"locomotion": over}))
    except (ValueError, KeyError) as e:
        ap.error(f"--set {' '.join(a.set)}: {e}")
    unknown = set(over) - set(lo.RollSettings.__dataclass_fields__)
    if unknown:
        ap.error(f"--set: unknown locomotion setting(s) {sorted(unknown)}")
    if a.two_pair and (a.two_pair.lower() == "none" or not Path(a.two_pair).is_file()):
        a.two_pair = None
    ws = workspace(a.workspace, a.two_pair)
    if a.strut_damping is not None:
        settings = dataclasses.replace(settings, strut_damping=a.strut_damping)
    headings = (
        np.arange(a.directions) * 360.0 / a.directions
        if a.heading_seed is None
        else np.sort(np.random.default_rng(a.heading_seed).uniform(0.0, 360.0, a.directions))
    )
    goals = a.distance * np.stack([np.cos(np.radians(headings)), np.sin(np.radians(headings))], axis=1)
    print(
        f"{a.directions} goals {a.distance} m away at {', '.join(f'{h:.0f}' for h in headings)} deg "
        f"from +x (uphill on slopes); start on (9,10,12) at the origin; ramp {settings.ramp_rate} "
        f"MPa/s; strut damping {settings.strut_damping} 1/s; dt {settings.dt} s; combinations "
        + ("from the two-pair workspace" if a.two_pair else "superposed")
        + (f"; settings {' '.join(a.set)}" if a.set else "")
    )
    rows = []
    for name, terrain, by_class in cases:
        t0 = time.perf_counter()
        with progress.bar(None, name, leave=False) as bar:
            runs = lo.roll_many(ws, goals, params, terrain, settings=settings, progress=bar.update)
        rows.append(report(name, runs, headings, time.perf_counter() - t0, settings.arrive_tolerance, by_class))
        if a.steps:
            steps(runs, headings)
    print("\n| scenario | arrived | outcomes | rolls/m | mean tip MPa |\n|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['name']} | {r['rate']} | {r['outcomes']} | {r['rpm']:.2f} | {r['tip']:.2f} |")


if __name__ == "__main__":
    main()
