"""`tensegrity plan` and `tensegrity roll`: the locomotion commands, with the configuration, start
face, terrain, settings and workspace of the pipeline's demonstration runs (stage
`locomotion_runs`); the two-pair workspace beside the workspace file unless --two-pair says
otherwise."""

from __future__ import annotations

import argparse
from pathlib import Path

from . import args as cli_args
from . import progress


def _two_pair_file(args: argparse.Namespace) -> str | None:
    """The two-pair workspace of plan and roll: --two-pair FILE, none with --two-pair none, else
    workspace_two_pair.nc beside the workspace file if it exists (the pipeline's runs use it)."""
    if args.two_pair == "none":
        return None
    if args.two_pair:
        return args.two_pair
    beside = Path(args.workspace).with_name("workspace_two_pair.nc")
    return str(beside) if beside.is_file() else None


def _locomotion_setup(args: argparse.Namespace):
    """Configuration keys, start face, terrain, parameters, settings and workspace of plan and
    roll: those of the pipeline's demonstration runs (stage `locomotion_runs`)."""
    from ..io import datasets, formats, settings
    from ..locomotion.settings import RollSettings
    from ..physics.topology import face_number
    from ..stages.config import actuator_kind

    cfg = cli_args.stage_cfg(args, "locomotion_runs")
    face = None if args.face is None else face_number(args.face)  # bad input first, before any file is read
    two_pair = _two_pair_file(args)
    ws = formats.read_workspace(args.workspace, two_pair)  # a missing or corrupted file first
    for path in (args.workspace, two_pair):
        if path and Path(path).is_file():  # levels in the configured actuator's unit (issue 31)
            formats.actuation.require_kind(datasets.read_attrs(path), path, actuator_kind(cfg))
    print(
        f"workspace {args.workspace}; two pairs: "
        + (
            f"measured curves of {two_pair}"
            if two_pair
            else "superposed single-pair curves"
            + (
                " (--two-pair none)"
                if args.two_pair == "none"
                else f" ({Path(args.workspace).with_name('workspace_two_pair.nc')} not found)"
            )
        ),
        flush=True,
    )
    return cfg, face, args.terrain, settings.params(cfg), settings.build(RollSettings, cfg), ws


def cmd_plan(args: argparse.Namespace) -> int:
    """Choose the pair(s) and pressure that roll the robot toward a target, from the workspace
    (in volts: motor voltages, V, with actuator.kind twisted_string)."""
    from ..locomotion.control import settle
    from ..locomotion.plan import plan
    from ..physics import contact as ct
    from ..physics import dynamics as d

    _, face, terrain, params, s, ws = _locomotion_setup(args)
    params = s.rolling(params)
    state, _ = settle(params, d.stand_on(params, face, terrain, yaw_deg=args.yaw), terrain, s)
    nodes = d.nodes(state.x, state.q, params.strut_length)[0]
    here = ct.face_from_gaps(ct.clearance(nodes, terrain, float(params.strut_radius)), s.contact_tolerance)
    target = {"goal": args.goal} if args.goal is not None else {"direction": args.direction}
    print(
        plan(ws, here, nodes, terrain=terrain, combine=s.combine, min_alignment=s.min_alignment, unit=s.unit, **target)
    )
    return 0


def cmd_roll(args: argparse.Namespace) -> int:
    """Roll the robot toward a goal in the dynamic simulator, from a start pose that stands and,
    where the face or yaw is not given, from which a first roll toward the goal is acceptable
    (`locomotion.start.choose`; a given pose that does not stand: exit 3, naming one that does);
    exit 1 if it did not arrive. With actuator.kind twisted_string the prototype's motors, in
    volts (a workspace in volts; the run file's voltage_cmd)."""
    from ..io import datasets
    from ..io.formats.run import RUN_ALLOW_NAN, run_dataset
    from ..locomotion.outcome import describe
    from ..locomotion.runs import roll_to
    from ..locomotion.start import choose
    from ..stages import provenance

    cfg, face, terrain, params, s, ws = _locomotion_setup(args)
    start = choose(ws, params, terrain, s, face, args.yaw, goal=args.goal)  # a pose that cannot stand: ValueError
    print(start.message, flush=True)
    with progress.bar(None, "roll") as bar:
        run = roll_to(
            ws, args.goal, params, terrain, face=start.face, settings=s, yaw_deg=start.yaw_deg, progress=bar.update
        )
    print(describe(run, "roll", s.unit))
    if args.out:
        datasets.write(
            run_dataset(run, terrain, s.rolling(params), "roll", s.unit),
            args.out,
            provenance(cfg, args.workspace),
            f"Rolling locomotion run: {run.outcome}",
            stage="locomotion",
            allow_nan=RUN_ALLOW_NAN,
        )
    return 0 if run.outcome == "arrived" else 1
