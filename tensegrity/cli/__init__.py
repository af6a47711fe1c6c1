"""The `tensegrity` command: simulate, query the workspace, plan a roll, roll, render, run a stage
or a design study, show or check the configuration, export the robot (a MuJoCo model), calibrate
from a measured trajectory.

Configuration: config/config.yaml of the current directory (as Snakemake reads it), else of the
checkout holding this package, else the schema's defaults; --config FILE is merged over it as
`snakemake --configfile FILE` merges it, and --set KEY=VALUE over that (`tensegrity config show`).

Exit codes: 0 success; 2 bad command-line usage; 3 invalid input (bad config, value, face,
pair, pressure or file); 4 the simulation failed (non-finite, exploded, off the terrain);
1 anything else, including a `roll` that did not arrive (its outcome is printed).
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from . import args as cli_args
from . import progress
from .calibrate import add_parser as add_calibrate
from .configuration import cmd_config
from .export import add_parser as add_export_parser
from .locomotion import cmd_plan, cmd_roll
from .workspace import cmd_faces, cmd_query, cmd_table

EXIT_USAGE, EXIT_INPUT, EXIT_SIM = 2, 3, 4
START = "9,10,12"  # the paper's start face (paper.START_FACE), as the command line writes it


def cmd_simulate(args: argparse.Namespace) -> int:
    """One actuation on one robot -> a netCDF with the CoG, nodes and pressures (with
    actuator.kind twisted_string: --voltage, and the voltages, voltage_cmd in V)."""
    from ..io import datasets, settings
    from ..stages.simulate import simulate

    cfg = cli_args.stage_cfg(args, "simulate")
    volts = "actuator" in cfg and settings.motors(cfg) is not None
    if volts != (args.voltage is not None):
        raise ValueError(
            "--voltage drives the twisted strings: set actuator.kind: twisted_string"
            if args.voltage is not None
            else "--pressure drives the pneumatic muscles, but actuator.kind is twisted_string: give --voltage V"
        )
    with progress.bar(args.duration, "simulate") as bar:
        path = simulate(
            cfg,
            args.face,
            args.pair,
            args.voltage if volts else args.pressure,
            args.duration,
            args.out,
            ramp=args.ramp,
            mode=args.mode,
            terrain=args.terrain,
            progress=bar.update,
        )
    ds = datasets.read(path)
    print(
        f"wrote {path}: {ds.sizes['time']} samples, final CoG (support frame) "
        f"{np.round(ds['cog'].values[-1] * 1000, 2).tolist()} mm"
    )
    return 0


def cmd_stage(args: argparse.Namespace) -> int:
    """Run one stage of the workflow with the function its Snakemake rule calls, the
    configuration keys its rule passes (so the files' provenance is the same) and the files
    named by ARG=PATH (a parameter of the stage function; repeat it for a list). `tensegrity
    stage NAME` alone lists the stage's arguments."""
    from .stage import call, describe

    if not args.arguments:
        print(describe(args.stage))
        return 0
    out = call(args.stage, cli_args.stage_cfg(args, args.stage), args.arguments)
    for p in out if isinstance(out, list) else [out]:
        print(p if isinstance(p, (str, Path)) else json.dumps(p, default=str))
    return 0


def cmd_render(args: argparse.Namespace) -> int:
    """Render a dataset of the toolkit (sweep, nominal, workspace, locomotion run, simulation)
    to a PNG, off-screen."""
    from ..stages.render import render_dataset

    what = render_dataset(args.dataset, args.out, args.face)
    print(f"wrote {args.out}: {what}")
    return 0


def cmd_study(args: argparse.Namespace) -> int:
    """Run a design study (config/studies/NAME.yaml or a YAML path) without Snakemake: every chunk
    not yet written, the merge and the analysis, into results/studies/NAME (docs/datasets.md)."""
    from ..stages.config import actuator_error
    from .study import run

    cfg = cli_args.load_cfg(args)
    if why := actuator_error(cfg, "study_chunk"):
        raise ValueError(why)
    return run(cfg, args.study, args.out, args.limit)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of every command."""
    from ..stages.config import STAGES

    ap = argparse.ArgumentParser(
        prog="tensegrity", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    from ..version import __version__

    ap.add_argument("--version", action="version", version=f"tensegrity {__version__}")
    sub = ap.add_subparsers(dest="command", required=True, metavar="COMMAND")
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument(
        "--config",
        metavar="FILE",
        help="config YAML merged over config/config.yaml of the current directory (else of the checkout, "
        "else the schema's defaults), as snakemake --configfile merges it (default: that file alone)",
    )
    common.add_argument(
        "--set",
        action="append",
        metavar="KEY=VALUE",
        help="override a config key, e.g. --set params.cable_damping=1 (repeatable)",
    )
    face_help = f"start face: 1..20 or 'a,b,c' (default {START})"

    p = sub.add_parser(
        "simulate", parents=[common], help="simulate one actuation, write a netCDF", description=cmd_simulate.__doc__
    )
    p.add_argument("--face", type=cli_args.face, default=cli_args.face(START), help=face_help)
    p.add_argument("--pair", type=int, nargs="+", required=True, help="actuator pair(s) 1..12")
    level = p.add_mutually_exclusive_group(required=True)
    level.add_argument("--pressure", type=float, help="pressure, MPa")
    level.add_argument("--voltage", type=float, help="motor voltage, V (actuator.kind: twisted_string)")
    p.add_argument(
        "--duration", type=cli_args.positive("--duration"), default=2.0, help="simulated time, s (default 2)"
    )
    p.add_argument(
        "--ramp",
        type=cli_args.non_negative("--ramp"),
        default=0.0,
        help="ramp time from 0 to the pressure, s (default 0: a step)",
    )
    p.add_argument("--mode", choices=["free", "grounded"], default="free", help="free (no gravity/ground) or grounded")
    p.add_argument(
        "--terrain",
        type=cli_args.terrain,
        help="grounded terrain: flat, none, slope:ANGLE[:AZIMUTH], random:SEED[:AMPLITUDE]",
    )
    p.add_argument("--out", required=True, help="output netCDF path")
    p.set_defaults(func=cmd_simulate)

    p = sub.add_parser("query", help="nominal CoG and margin from the fitted curves", description=cmd_query.__doc__)
    p.add_argument(
        "--curves", default="results/curves/curves.json", help="curves JSON (default results/curves/curves.json)"
    )
    p.add_argument(
        "--workspace", default="results/workspace.nc", help="workspace netCDF (default results/workspace.nc)"
    )
    p.add_argument("--face", type=cli_args.face, required=True, help="face: 1..20 or 'a,b,c'")
    p.add_argument("--pair", type=int, required=True, help="actuator pair 1..12")
    p.add_argument("--pressure", type=float, required=True, help="pressure, MPa")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_query)

    add_calibrate(sub, common)

    p = sub.add_parser("render", help="render a dataset to a PNG", description=cmd_render.__doc__)
    p.add_argument("dataset", help="a netCDF written by the workflow or by `tensegrity simulate`")
    p.add_argument("--out", required=True, help="output PNG path")
    p.add_argument("--face", type=cli_args.face, help=f"face to show, for the workspace (default {START})")
    p.set_defaults(func=cmd_render)

    p = sub.add_parser(
        "stage", parents=[common], help="run one workflow stage outside Snakemake", description=cmd_stage.__doc__
    )
    p.add_argument("stage", choices=sorted(STAGES), metavar="NAME", help=", ".join(sorted(STAGES)))
    p.add_argument(
        "arguments",
        nargs="*",
        metavar="ARG=VALUE",
        help="a parameter of the stage function, e.g. out_path=results/workspace.nc",
    )
    p.set_defaults(func=cmd_stage)

    p = sub.add_parser("faces", help="the 20 faces: nodes, kind, reference vertex", description=cmd_faces.__doc__)
    p.set_defaults(func=cmd_faces)
    p = sub.add_parser("table", help="one face's workspace as a CSV table", description=cmd_table.__doc__)
    p.add_argument("--face", type=cli_args.face, required=True, help="face: 1..20 or 'a,b,c'")
    p.add_argument(
        "--workspace", default="results/workspace.nc", help="workspace netCDF (default results/workspace.nc)"
    )
    p.add_argument("--out", help="write the CSV to this file (default: print it)")
    p.set_defaults(func=cmd_table)

    p = sub.add_parser(
        "config",
        parents=[common],
        help="show the resolved configuration or check a file",
        description=cmd_config.__doc__,
    )
    p.add_argument("action", choices=["show", "check"])
    p.add_argument(
        "file",
        nargs="?",
        help="config YAML merged over config/config.yaml of the current directory (else of the checkout, else "
        "the schema's defaults), as snakemake --configfile merges it (show: default that file alone; check: "
        "required; an empty file is refused, as Snakemake refuses it: write {} for no change)",
    )
    p.set_defaults(func=cmd_config)

    p = sub.add_parser(
        "study", parents=[common], help="run a design study without Snakemake", description=cmd_study.__doc__
    )
    p.add_argument("study", help="study name (config/studies/NAME.yaml) or a YAML file")
    p.add_argument("--out", help="output folder (default results/studies/NAME)")
    p.add_argument("--limit", type=int, default=0, help="only the first N designs (default 0: all)")
    p.set_defaults(func=cmd_study)
    add_export_parser(sub, common, cli_args.face, START)

    for name, func, helptext in (
        ("plan", cmd_plan, "choose the pair and pressure that roll the robot toward a target"),
        ("roll", cmd_roll, "roll the robot toward a goal in the dynamic simulator"),
    ):
        p = sub.add_parser(name, parents=[common], help=helptext, description=func.__doc__)
        p.add_argument(
            "--workspace", default="results/workspace.nc", help="workspace file (default results/workspace.nc)"
        )
        p.add_argument(
            "--two-pair",
            help="two-pair workspace file: combinations from its measured curves "
            "(default: workspace_two_pair.nc beside --workspace if it exists, as the pipeline's runs "
            "use it; 'none': superposed single-pair curves)",
        )
        if name == "plan":
            p.add_argument("--face", type=cli_args.face, default=cli_args.face(START), help=face_help)
        else:  # roll: a start pose that stands (locomotion.start)
            p.add_argument(
                "--face",
                type=cli_args.face,
                help=f"start face: 1..20 or 'a,b,c' (default: {START} if it stands at the yaw and a first roll "
                "from it toward the goal is acceptable, else a standing face from which one is; a face that "
                "cannot stand stops the run, naming one that can)",
            )
        p.add_argument(
            "--terrain",
            type=cli_args.terrain,
            default="flat",
            help="flat (default), slope:ANGLE[:AZIMUTH] or random:SEED[:AMPLITUDE]",
        )
        p.add_argument(
            "--yaw",
            type=float,
            default=0.0 if name == "plan" else None,
            help="turn of the robot about the terrain normal, deg (default 0"
            + ("" if name == "plan" else " if the start face stands there, else a yaw at which it does")
            + ")",
        )
        if name == "plan":
            tgt = p.add_mutually_exclusive_group(required=True)
            tgt.add_argument(
                "--direction", type=cli_args.heading, help="target heading in deg from +x, or a vector x,y"
            )
            tgt.add_argument("--goal", type=cli_args.xy("--goal"), help="goal point x,y in m")
        else:
            p.add_argument("--goal", type=cli_args.xy("--goal"), required=True, help="goal point x,y in m")
            p.add_argument("--out", help="write the run to this netCDF file")
        p.set_defaults(func=func)
    return ap


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command of `argv` (default sys.argv[1:]); returns the exit code."""
    ap = build_parser()
    argv = cli_args.join_negative_values(sys.argv[1:] if argv is None else list(argv))
    args = ap.parse_args(cli_args.stage_arguments_first(argv))
    from ..physics.dynamics import SimulationError

    try:
        return args.func(args)
    except SimulationError as e:
        print(f"tensegrity {args.command}: simulation failed: {e}", file=sys.stderr)
        return EXIT_SIM
    except (ValueError, OSError, KeyError) as e:  # bad value, missing or unreadable file
        print(f"tensegrity {args.command}: {e}", file=sys.stderr)
        return EXIT_INPUT
