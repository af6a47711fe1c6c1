"""Rule `two_pair` (workflow/rules/two_pair.smk): the two-pair workspace, pairs of actuator pairs
over a 2-D pressure grid swept once per stabiliser orbit on each canonical face
(results/two_pair/{contact}.nc), mapped to all 20 faces (results/workspace_two_pair.nc)."""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path

from ..io import datasets, settings
from ..io.formats import actuation
from ..io.formats import two_pair as tpf
from ..physics import topology as topo
from ..workspace import two_pair as tp
from ..workspace.two_pair import TwoPairSetup
from . import provenance


def two_pair(cfg: dict, contact: str, out_path: str | os.PathLike) -> Path:
    """Stage `two_pair`: sweep one combination of two_pair.pairs per stabiliser orbit on the
    canonical face of `contact` (free mode, one batched run), map to the other combinations of
    that face, write results/two_pair/{contact}.nc (in volts with the twisted-string actuator)."""
    if contact not in topo.CONTACT_FACES:
        raise ValueError(f"unknown contact {contact!r}: use one of {list(topo.CONTACT_FACES)}")
    setup = settings.build(TwoPairSetup, cfg)
    face = topo.face_number(topo.CONTACT_FACES[contact])
    reps = tp.representatives(face, tp.combos_of(cfg["two_pair"]["pairs"]))
    print(
        f"{topo.face_label(face)}: {len(reps)} combinations swept (one per stabiliser orbit) over "
        f"{len(setup.levels)}x{len(setup.levels)} levels",
        flush=True,
    )
    motors = settings.motors(cfg) if "actuator" in cfg else None
    res = tp.sweep(settings.params(cfg), face, reps, setup, motors)
    ws, swept, std = tp.contact_workspace(face, reps, res, setup.levels)
    attrs = {
        "contact": contact,
        "face": face,
        "face_nodes": topo.FACES[face - 1] + 1,
        "mode": "free",
        "hold_s": float(setup.hold),
        "discard_s": float(setup.discard),
    }
    ds = tpf.contact_dataset(setup.levels, tp.COMBOS, ws, swept, std, attrs, float(settings.params(cfg).strut_length))
    return datasets.write(
        actuation.relabel(ds, actuation.PNEUMATIC if motors is None else actuation.TWISTED),
        out_path,
        cfg,
        f"Two-pair workspace of the {contact} contact case {topo.face_label(face)}",
        stage="two_pair",
        allow_nan=tpf.CONTACT_ALLOW_NAN,
    )


def two_pair_map(cfg: dict, contact_paths: Sequence[str | os.PathLike], out_path: str | os.PathLike) -> Path:
    """Stage `two_pair_map`: results/workspace_two_pair.nc, every face from the contact files."""
    levels, src = tpf.read_contacts(contact_paths)
    ws = tp.map_workspace(
        levels,
        {
            c: (ds["combo_pairs"].values, ds["cog"].values, ds["support"].values, ds["staircase_pairs"].values)
            for c, ds in src.items()
        },
    )
    ds = tpf.workspace_dataset(levels, tp.COMBOS, ws, {"mode": "free"}, datasets.strut_length(next(iter(src.values()))))
    return datasets.write(
        actuation.relabel(ds, actuation.common_kind(src.values())),
        out_path,
        provenance(cfg, *contact_paths),
        "Two-pair workspace of all 20 contact faces, mapped by symmetry",
        stage="two_pair_map",
        allow_nan=[k for k in tpf.ALLOW_NAN if k != "cog_std"],
    )
