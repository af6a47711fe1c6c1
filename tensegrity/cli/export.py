"""`tensegrity export mjcf`: the configured robot as a file another simulator reads (issue 33)."""

from __future__ import annotations

import argparse
from collections.abc import Callable
from typing import Any


def cmd_export(args: argparse.Namespace) -> int:
    """Write the configured design (`params`, `sim.dt`) as a MuJoCo model (MJCF): six struts,
    24 cables as spatial tendons with eq. 1-2, one actuator `cable_A_B` per cable whose control
    is its pair's pressure (MPa); --mode free (no gravity, no contact) or grounded (gravity, the
    plane z = 0, friction). The robot starts at rest on --face. See tensegrity.bridges.mjcf."""
    from ..atomic import write_text
    from ..bridges.mjcf import mjcf
    from ..io import settings
    from ..physics import topology as topo
    from ..physics.state import stand_on
    from ..physics.terrain import Terrain
    from ..stages.config import actuator_error
    from .args import load_cfg

    cfg = load_cfg(args)
    if why := actuator_error(cfg, "the command `tensegrity export`"):  # it writes eq. 1-2 only
        raise ValueError(why)
    params, dt = settings.params(cfg), float(settings.value(cfg, "sim.dt"))
    face = topo.face_number(args.face)  # ValueError (exit 3) naming a bad face, before any work
    state = stand_on(params, face, Terrain.flat() if args.mode == "grounded" else Terrain.none())
    text = mjcf(params, args.mode, dt, state=state)
    write_text(args.out, text)
    print(f"wrote {args.out}: MuJoCo model, {args.mode} mode, dt {dt:g} s, standing on face {face}")
    return 0


def add_parser(sub: Any, common: argparse.ArgumentParser, face_type: Callable[[str], Any], start: str) -> None:
    """The `export` command and its `mjcf` format."""
    p = sub.add_parser("export", help="write the robot for another simulator", description=cmd_export.__doc__)
    fmt = p.add_subparsers(dest="format", required=True, metavar="FORMAT")
    p = fmt.add_parser("mjcf", parents=[common], help="a MuJoCo model (MJCF XML)", description=cmd_export.__doc__)
    p.add_argument("--out", required=True, help="output path, e.g. robot.xml")
    p.add_argument(
        "--mode", choices=["free", "grounded"], default="free", help="free (default: no gravity/ground) or grounded"
    )
    p.add_argument(
        "--face", type=face_type, default=face_type(start), help=f"start face: 1..20 or 'a,b,c' (default {start})"
    )
    p.set_defaults(func=cmd_export)
