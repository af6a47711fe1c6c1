"""The `tensegrity` command: simulate, query the workspace, plan a roll, render, run a stage.

Exit codes: 0 success; 2 bad command-line usage; 3 invalid input (bad config, value, face,
pair, pressure or file); 4 the simulation failed (non-finite, exploded, off the terrain);
1 anything else, including a `roll` that did not arrive (its outcome is printed).
"""
from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence

import numpy as np

from . import cli_args, progress

EXIT_USAGE, EXIT_INPUT, EXIT_SIM = 2, 3, 4


def _load_cfg(args):
    from .io import config
    return config.load(args.config, overrides=args.set or None)


def cmd_simulate(args: argparse.Namespace) -> int:
    """One actuation on one robot -> a netCDF with the CoG, nodes and pressures."""
    import xarray as xr
    from .io import datasets
    from .physics import dynamics as d
    from .physics import frames, topology as topo
    from .workspace import sweep
    from .physics.schedule import Schedule
    from .io.config import params_from_config
    cfg = _load_cfg(args)
    params, terrain = sweep.setup(params_from_config(cfg), args.mode)
    if args.terrain is not None:
        if args.mode == "free":
            raise ValueError("--terrain needs --mode grounded (the free mode has no ground)")
        terrain = args.terrain
    face = topo.face_number(args.face)
    pairs = [topo.check_pair(p) for p in args.pair]
    dt, every = cfg["sim"]["dt"], cfg["sim"]["record_every"]
    state = d.stand_on(params, face, terrain)
    chunk = dt * every * max(1, round(0.05 / (dt * every)))
    n = max(1, round(args.duration / chunk))
    ramp_n = round(args.ramp / chunk)
    xs, qs, ts, ps = [], [], [], []
    with progress.bar(n * chunk, "simulate") as bar:
        for k in range(n):
            level = args.pressure * min(1.0, (k + 1) / ramp_n) if ramp_n else args.pressure
            pres = np.zeros(12)
            pres[np.array(pairs) - 1] = level
            state, tr = d.simulate(params, state, Schedule.constant(pres, chunk), terrain, dt, every)
            xs.append(tr.x[0]), qs.append(tr.q[0]), ts.append(tr.t), ps.append(tr.pressure[0])
            bar.update(chunk)
    x, q = np.concatenate(xs), np.concatenate(qs)
    nodes = d.nodes(x, q, params.strut_length)
    cog, sup = frames.in_support_frame(nodes, face)
    var = datasets.var
    ds = xr.Dataset(
        {"cog": var(("time", "axis"), cog, "m", "centre of gravity in the start face's support frame"),
         "cog_world": var(("time", "axis"), d.cog(x), "m", "centre of gravity, world frame"),
         "support": var(("time", "corner", "axis"), sup, "m", "start face corners in its support frame"),
         "nodes": var(("time", "node", "axis"), nodes, "m", "node positions, world frame"),
         "pressure_cmd": var(("time", "pair"), np.concatenate(ps), "MPa", "pair pressures commanded")},
        coords={"time": ("time", np.concatenate(ts), {"units": "s", "long_name": "time"}),
                "axis": ("axis", ["x", "y", "z"], {"units": "1", "long_name": "axis"}),
                "corner": ("corner", [1, 2, 3], {"units": "1", "long_name": "support triangle corner"}),
                "node": ("node", np.arange(1, 13), {"units": "1", "long_name": "node number"}),
                "pair": ("pair", np.arange(1, 13), {"units": "1", "long_name": "actuator pair number"})},
        attrs={"face": face, "face_nodes": topo.FACES[face - 1] + 1, "mode": args.mode,
               "pairs": pairs, "pressure_mpa": args.pressure, "ramp_s": args.ramp})
    datasets.write(ds, args.out, cfg, f"Simulation of pairs {pairs} at {args.pressure} MPa on "
                   f"{topo.face_label(face)}", stage="simulate")
    print(f"wrote {args.out}: {len(ts) and ds.sizes['time']} samples, final CoG (support frame) "
          f"{np.round(cog[-1] * 1000, 2).tolist()} mm")
    return 0


def cmd_query(args: argparse.Namespace) -> int:
    """Nominal CoG and margin for a face, pair and pressure from the fitted curves."""
    from .io import datasets
    from .workspace import query
    ans = query.query(query.load_curves(args.curves), datasets.read(args.workspace),
                      args.face, args.pair, args.pressure)
    out = {"face": ans.face, "pair": ans.pair, "pressure_mpa": ans.pressure,
           "cog_m": ans.cog.round(7).tolist(), "margin_m": round(ans.margin, 7),
           "stands": ans.margin > 0, "support_m": ans.support.round(7).tolist(),
           "contact": ans.contact, "canonical_pair": ans.source_pair}
    if args.json:
        print(json.dumps(out))
    else:
        print(f"face {ans.face} ({ans.contact}), pair #{ans.pair} at {ans.pressure} MPa: "
              f"CoG {np.round(ans.cog * 1000, 2).tolist()} mm (support frame), margin "
              f"{ans.margin * 1000:.2f} mm -> {'stands' if ans.margin > 0 else 'rolls'}")
    return 0


def cmd_stage(args: argparse.Namespace) -> int:
    """Run one workflow stage with the same function the Snakemake rule calls."""
    from . import stages
    # the config sections the stage depends on, as the Snakemake rule passes them (provenance)
    cfg = stages.stage_config(_load_cfg(args), args.stage)
    if args.stage == "sweep":
        if args.contact is None:
            raise ValueError("--contact is required for the sweep stage")
        for p in stages.run_sweep(cfg, args.contact, args.out):
            print(p)
    elif args.stage == "nominal":
        print(stages.run_nominal(cfg, args.inputs, args.out))
    elif args.stage == "fit":
        print(stages.run_fit(cfg, args.inputs[0], args.out))
    elif args.stage == "map":
        print(stages.run_map(cfg, args.inputs, args.out))
    return 0


def cmd_config(args: argparse.Namespace) -> int:
    """`config show`: the resolved, validated configuration (defaults filled in) as YAML;
    `config check FILE`: validate a file, naming every bad key (exit 3)."""
    import yaml
    from .io import config
    if args.action == "check":
        if not args.file:
            raise ValueError("config check needs a FILE")
        config.load(args.file, overrides=args.set or None)
        print(f"{args.file}: valid")
        return 0
    cfg = config.load(args.file or args.config, overrides=args.set or None)
    print(yaml.safe_dump(cfg, sort_keys=False, default_flow_style=False), end="")
    return 0


def cmd_render(args: argparse.Namespace) -> int:
    """Render a dataset of the toolkit (sweep, nominal, workspace, locomotion run, simulation)
    to a PNG, off-screen."""
    from . import stages
    what = stages.render_dataset(args.dataset, args.out, args.face)
    print(f"wrote {args.out}: {what}")
    return 0


def _locomotion_setup(args):
    """Configuration, start face, terrain, parameters, settings and workspace of plan and roll."""
    from .io.formats import read_workspace
    from .locomotion.control import RollSettings
    from .locomotion.demos import locomotion_params
    from .physics.topology import face_number
    cfg = _load_cfg(args)
    face = face_number(args.face)
    settings = RollSettings.from_config(cfg["locomotion"], cfg["sim"]["dt"])
    ws = read_workspace(args.workspace)
    if args.two_pair:  # measured two-pair curves instead of superposed ones
        from .io.two_pair_formats import read_two_pair
        ws = ws.with_two_pair(*read_two_pair(args.two_pair))
    return cfg, face, args.terrain, locomotion_params(cfg), settings, ws


def cmd_plan(args: argparse.Namespace) -> int:
    """Choose the pair(s) and pressure that roll the robot toward a target, from the workspace."""
    from .locomotion.control import settle
    from .locomotion.plan import plan
    from .physics import contact as ct, dynamics as d
    cfg, face, terrain, params, s, ws = _locomotion_setup(args)
    state, _ = settle(params, d.stand_on(params, face, terrain, yaw_deg=args.yaw), terrain, s)
    nodes = d.nodes(state.x, state.q, params.strut_length)[0]
    here = ct.face_from_gaps(ct.clearance(nodes, terrain, float(params.strut_radius)), s.contact_tolerance)
    target = {"goal": args.goal} if args.goal is not None else {"direction": args.direction}
    print(plan(ws, here, nodes, terrain=terrain, combine=s.combine, min_alignment=s.min_alignment,
               **target))
    return 0


def cmd_roll(args: argparse.Namespace) -> int:
    """Roll the robot toward a goal in the dynamic simulator; exit 1 if it did not arrive."""
    from .io import datasets
    from .io.run_formats import RUN_ALLOW_NAN, run_dataset
    from .locomotion.outcome import describe
    from .locomotion.runs import roll_to
    cfg, face, terrain, params, s, ws = _locomotion_setup(args)
    with progress.simulated("roll"):
        run = roll_to(ws, args.goal, params, terrain, face=face, settings=s, yaw_deg=args.yaw)
    print(describe(run, "roll"))
    if args.out:
        datasets.write(run_dataset(run, terrain, "roll"), args.out, cfg,
                       f"Rolling locomotion run: {run.outcome}", stage="locomotion",
                       allow_nan=RUN_ALLOW_NAN)
    return 0 if run.outcome == "arrived" else 1


def cmd_study(args: argparse.Namespace) -> int:
    """Run a design study (config/studies/NAME.yaml or a YAML path) without Snakemake: every chunk
    not yet written, the merge and the analysis, into results/studies/NAME (docs/datasets.md)."""
    from . import study_stages
    return study_stages.cmd_study(_load_cfg(args), args.study, args.out, args.limit)


def build_parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="tensegrity", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="command", required=True, metavar="COMMAND")
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("--config", help="config YAML (default: config/config.yaml)")
    common.add_argument("--set", action="append", metavar="KEY=VALUE",
                        help="override a config key, e.g. --set params.cable_damping=1 (repeatable)")

    p = sub.add_parser("simulate", parents=[common], help="simulate one actuation, write a netCDF",
                       description=cmd_simulate.__doc__)
    p.add_argument("--face", type=cli_args.face, default=(9, 10, 12), help="start face: 1..20 or 'a,b,c' (default 9,10,12)")
    p.add_argument("--pair", type=int, nargs="+", required=True, help="actuator pair(s) 1..12")
    p.add_argument("--pressure", type=float, required=True, help="pressure, MPa")
    p.add_argument("--duration", type=cli_args.positive("--duration"), default=2.0, help="simulated time, s (default 2)")
    p.add_argument("--ramp", type=cli_args.non_negative("--ramp"), default=0.0, help="ramp time from 0 to the pressure, s (default 0: a step)")
    p.add_argument("--mode", choices=["free", "grounded"], default="free", help="free (no gravity/ground) or grounded")
    p.add_argument("--terrain", type=cli_args.terrain, help="grounded terrain: flat, none, slope:ANGLE[:AZIMUTH], random:SEED[:AMPLITUDE]")
    p.add_argument("--out", required=True, help="output netCDF path")
    p.set_defaults(func=cmd_simulate)

    p = sub.add_parser("query", help="nominal CoG and margin from the fitted curves", description=cmd_query.__doc__)
    p.add_argument("--curves", default="results/curves/curves.json", help="curves JSON (default results/curves/curves.json)")
    p.add_argument("--workspace", default="results/workspace.nc", help="workspace netCDF (default results/workspace.nc)")
    p.add_argument("--face", type=cli_args.face, required=True, help="face: 1..20 or 'a,b,c'")
    p.add_argument("--pair", type=int, required=True, help="actuator pair 1..12")
    p.add_argument("--pressure", type=float, required=True, help="pressure, MPa")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_query)

    p = sub.add_parser("render", help="render a dataset to a PNG", description=cmd_render.__doc__)
    p.add_argument("dataset", help="a netCDF written by the workflow or by `tensegrity simulate`")
    p.add_argument("--out", required=True, help="output PNG path")
    p.add_argument("--face", type=cli_args.face, help="face to show, for the workspace (default 9,10,12)")
    p.set_defaults(func=cmd_render)

    p = sub.add_parser("stage", parents=[common], help="run one workflow stage outside Snakemake",
                       description=cmd_stage.__doc__)
    p.add_argument("stage", choices=["sweep", "nominal", "fit", "map"])
    p.add_argument("--contact", choices=["equilateral", "isosceles"], help="contact case (sweep)")
    p.add_argument("--inputs", nargs="*", default=[], help="input files (nominal, fit, map)")
    p.add_argument("--out", required=True, help="output file (directory for sweep)")
    p.set_defaults(func=cmd_stage)

    p = sub.add_parser("config", parents=[common], help="show the resolved configuration or check a file",
                       description=cmd_config.__doc__)
    p.add_argument("action", choices=["show", "check"])
    p.add_argument("file", nargs="?", help="config YAML (show: default config/config.yaml or the "
                                          "schema's defaults; check: required)")
    p.set_defaults(func=cmd_config)

    p = sub.add_parser("study", parents=[common], help="run a design study without Snakemake",
                       description=cmd_study.__doc__)
    p.add_argument("study", help="study name (config/studies/NAME.yaml) or a YAML file")
    p.add_argument("--out", help="output folder (default results/studies/NAME)")
    p.add_argument("--limit", type=int, default=0, help="only the first N designs (default 0: all)")
    p.set_defaults(func=cmd_study)

    for name, func, helptext in (("plan", cmd_plan, "choose the pair and pressure that roll the robot toward a target"),
                                 ("roll", cmd_roll, "roll the robot toward a goal in the dynamic simulator")):
        p = sub.add_parser(name, parents=[common], help=helptext, description=func.__doc__)
        p.add_argument("--workspace", default="results/workspace.nc", help="workspace file (default results/workspace.nc)")
        p.add_argument("--two-pair", help="two-pair workspace file (results/workspace_two_pair.nc): "
                       "combinations from it, not superposed (default: superposed)")
        p.add_argument("--face", type=cli_args.face, default=(9, 10, 12), help="start face: 1..20 or 'a,b,c' (default 9,10,12)")
        p.add_argument("--terrain", type=cli_args.terrain, default="flat",
                       help="flat (default), slope:ANGLE[:AZIMUTH] or random:SEED[:AMPLITUDE]")
        p.add_argument("--yaw", type=float, default=0.0, help="turn of the robot about the terrain normal, deg")
        if name == "plan":
            tgt = p.add_mutually_exclusive_group(required=True)
            tgt.add_argument("--direction", type=cli_args.heading, help="target heading in deg from +x, or a vector x,y")
            tgt.add_argument("--goal", type=cli_args.xy("--goal"), help="goal point x,y in m")
        else:
            p.add_argument("--goal", type=cli_args.xy("--goal"), required=True, help="goal point x,y in m")
            p.add_argument("--out", help="write the run to this netCDF file")
        p.set_defaults(func=func)
    return ap


def main(argv: Sequence[str] | None = None) -> int:
    ap = build_parser()
    args = ap.parse_args(cli_args.join_negative_values(sys.argv[1:] if argv is None else list(argv)))
    from .physics.dynamics import SimulationError
    try:
        return args.func(args)
    except SimulationError as e:
        print(f"tensegrity {args.command}: simulation failed: {e}", file=sys.stderr)
        return EXIT_SIM
    except (ValueError, OSError, KeyError) as e:  # bad value, missing or unreadable file
        print(f"tensegrity {args.command}: {e}", file=sys.stderr)
        return EXIT_INPUT


if __name__ == "__main__":
    sys.exit(main())
