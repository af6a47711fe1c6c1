"""The commands on the workspace files: `tensegrity query` (a face, pair and pressure from the
fitted curves), `tensegrity faces` (the 20 faces with their nodes and kinds) and `tensegrity
table` (one face's workspace as a CSV table)."""

from __future__ import annotations

import argparse
import json

import numpy as np


def cmd_query(args: argparse.Namespace) -> int:
    """Nominal CoG and margin for a face, pair and pressure from the fitted curves (at 0 MPa: the
    unactuated robot); the curves and the workspace must come from one run. Files in volts (the
    twisted-string actuator) take and print the level in V (JSON key pressure_v)."""
    from ..io import datasets, formats
    from ..io.provenance import check_together
    from ..workspace import query

    curves = formats.read_curves(args.curves)
    workspace = formats.read_workspace(args.workspace)
    kind = formats.actuation.kind_of(curves)  # the unit is the files' (MPa, or V: issue 31)
    formats.actuation.require_kind(datasets.read_attrs(args.workspace), args.workspace, kind)
    check_together({args.curves: curves.get("config"), args.workspace: formats.config_of(args.workspace)})
    unit = formats.actuation.units(kind)
    ans = query.query(curves, workspace, args.face, args.pair, args.pressure, wsname=args.workspace)
    out = {
        "face": ans.face,
        "pair": ans.pair,
        f"pressure_{unit.lower()}": ans.pressure,
        "cog_m": ans.cog.round(7).tolist(),
        "margin_m": round(ans.margin, 7),
        "stands": ans.margin > 0,
        "support_m": ans.support.round(7).tolist(),
        "contact": ans.contact,
        "canonical_pair": ans.source_pair,
    }
    if args.json:
        print(json.dumps(out))
    else:
        print(
            f"face {ans.face} ({ans.contact}), pair #{ans.pair} at {ans.pressure} {unit}: "
            f"CoG {np.round(ans.cog * 1000, 2).tolist()} mm (support frame), margin "
            f"{ans.margin * 1000:.2f} mm -> {'stands' if ans.margin > 0 else 'rolls'}"
        )
    return 0


def cmd_faces(args: argparse.Namespace) -> int:
    """The 20 faces: number, the nodes in support-frame corner order, kind, the reference vertex
    (the support frame's +y), and the canonical face of its kind."""
    from ..physics import topology as topo

    print("face  nodes       kind         reference  canonical")
    for f in range(1, topo.N_FACES + 1):
        nodes = topo.FACES[f - 1] + 1
        kind = str(topo.FACE_TYPES[f - 1])
        ref = int(nodes[topo.FACE_REFERENCE[f - 1]])
        canonical = topo.face_number(topo.CONTACT_FACES[kind])
        print(f"{f:4d}  {topo.face_label(f):10s}  {kind:11s}  {ref:9d}  {canonical:9d}")
    return 0


def cmd_table(args: argparse.Namespace) -> int:
    """One face's workspace as a CSV table: pair, pressure (MPa, 0: the unactuated robot), the
    nominal CoG (m, support frame), the margin (m, positive inside) and the pair's tipping
    pressure (MPa, empty: never), from the workspace file; a workspace in volts (the
    twisted-string actuator) gives V, and the columns say so."""
    from .. import atomic
    from ..io.formats.workspace import face_table
    from ..physics.topology import face_number

    text = face_table(args.workspace, face_number(args.face))
    if args.out:
        atomic.write_text(args.out, text)
        print(f"wrote {args.out}: face {face_number(args.face)}, {text.count(chr(10)) - 1} rows")
    else:
        print(text, end="")
    return 0
