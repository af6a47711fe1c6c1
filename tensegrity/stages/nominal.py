"""Rule `nominal` (workflow/rules/nominal.smk): each level's CoG samples averaged into the
nominal CoG of every contact case (results/nominal/{contact}.nc), or under nominal.method statics
the static equilibria in their place (`nominal_statics`), and the canonical workspaces mapped to
all 20 faces (results/workspace.nc)."""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ..io import datasets, formats, settings
from ..io.formats import actuation
from ..physics import frames
from ..physics import topology as topo
from ..workspace import mapping
from ..workspace import nominal as nom
from . import provenance


def nominal(cfg: dict, sweep_paths: Sequence[str | os.PathLike], out_path: str | os.PathLike) -> Path:
    """Stage `nominal`: average every sweep file's levels (after nominal.discard s) into the
    nominal CoG dataset of one contact case."""
    sweeps = sorted((datasets.read(p) for p in sweep_paths), key=lambda ds: ds.attrs["pair"])
    first = sweeps[0]
    levels = first["levels"].values
    hold, discard = first.attrs["hold_s"], float(cfg["nominal"]["discard"])
    res = [
        nom.nominal(
            ds["time"].values, ds["level"].values, ds["cog"].values, ds["support"].values, len(levels), hold, discard
        )
        for ds in sweeps
    ]
    cog, std, sup, margin = (np.stack([r[k] for r in res]) for k in range(4))
    err = np.stack(
        [
            nom.averaging_error(ds["time"].values, ds["level"].values, ds["cog"].values, len(levels), hold, discard)
            for ds in sweeps
        ]
    )
    pairs = [int(ds.attrs["pair"]) for ds in sweeps]
    tip = np.array([frames.first_crossing(levels, m)[0] for m in margin])
    # grounded mode: from the level the robot rolled off its face on, the numbers are not of
    # this face any more; they become NaN and the roll counts as the tip
    rolled = np.zeros(margin.shape, np.int8)
    for i, ds in enumerate(sweeps):
        k = nom.first_roll(ds["level"].values, ds["on_face"].values, len(levels))
        rolled[i, k:] = 1
        tip[i] = nom.mask_after_roll(levels, k, tip[i], cog[i], std[i], sup[i], margin[i], err[i])
    kind = actuation.common_kind(sweeps)  # the unit of the levels: the sweeps' (MPa or V)
    locked = [ds["strands_locked"] for ds in sweeps if "strands_locked" in ds]  # twisted strings only
    ds = formats.nominal_dataset(
        pairs,
        levels,
        cog,
        std,
        sup,
        margin,
        tip,
        rolled,
        err,
        {k: first.attrs[k] for k in ("contact", "face", "face_nodes", "mode")} | {"discard_s": discard},
        datasets.strut_length(first),
    )
    if locked:
        ds["strands_locked"] = (("pair", "pressure"), np.stack([v.values for v in locked]), dict(locked[0].attrs))
    return datasets.write(
        actuation.relabel(ds, kind),
        out_path,
        provenance(cfg, *sweep_paths),
        f"Nominal CoG of the {first.attrs['contact']} contact case {topo.face_label(int(first.attrs['face']))}",
        stage="nominal",
        allow_nan=formats.NOMINAL_ALLOW_NAN,
    )


def workspace(cfg: dict, nominal_paths: Sequence[str | os.PathLike], out_path: str | os.PathLike) -> Path:
    """Stage `workspace`: the canonical nominal workspaces mapped to all 20 faces by the
    symmetry group (results/workspace.nc)."""
    src = {ds.attrs["contact"]: ds for ds in (datasets.read(p) for p in nominal_paths)}
    levels = mapping.same_levels([ds["pressure"].values for ds in src.values()])
    ws = mapping.map_workspace(
        levels, {c: (ds["pair"].values, ds["cog"].values, ds["support"].values) for c, ds in src.items()}
    )
    ds = formats.workspace_dataset(levels, ws, datasets.strut_length(next(iter(src.values()))))
    return datasets.write(
        actuation.relabel(ds, actuation.common_kind(src.values())),
        out_path,
        provenance(cfg, *nominal_paths),
        "Kinematic workspace of all 20 contact faces, mapped by symmetry",
        stage="map",
        allow_nan=formats.WORKSPACE_ALLOW_NAN,
    )


def nominal_statics(cfg: dict, contacts: Sequence[str], out_paths: Sequence[str | os.PathLike]) -> list[Path]:
    """Stage `nominal_statics` (rule `nominal` under nominal.method statics): the nominal CoG file
    of each contact case (`contacts`, in the order of `out_paths`) from the free-mode static
    equilibria of sweep.pairs at sweep.levels (`workspace.equilibria`, no sweep): the same
    variables as `nominal`, cog_std and averaging_error 0 (nothing averaged), the tipping
    pressures found by root-finding on the margin."""
    from ..workspace import equilibria

    if cfg["nominal"]["method"] != "statics":
        raise ValueError(f"stage nominal_statics: nominal.method is {cfg['nominal']['method']!r}, not 'statics'")
    if len(contacts) != len(out_paths):
        raise ValueError(f"stage nominal_statics: {len(contacts)} contact cases but {len(out_paths)} output files")
    faces = [topo.face_number(topo.CONTACT_FACES[c]) for c in contacts]  # KeyError: an unknown case
    params, pairs, levels = settings.params(cfg), list(cfg["sweep"]["pairs"]), list(cfg["sweep"]["levels"])
    ws = equilibria.free_workspace([params], faces, pairs, levels)
    out = []
    for c, (contact, face, path) in enumerate(zip(contacts, faces, out_paths)):
        cog, zeros = ws.cog[0, c], np.zeros(ws.margin[0, c].shape)
        attrs = {"contact": contact, "face": face, "face_nodes": topo.FACES[face - 1] + 1, "mode": "free"}
        ds = formats.nominal_dataset(
            pairs,
            levels,
            cog,
            np.zeros(cog.shape),
            ws.support[0, c],
            ws.margin[0, c],
            ws.tip_pressure[0, c],
            zeros.astype(np.int8),
            zeros,
            attrs,
            float(params.strut_length),
            method="statics",
        )
        title = f"Nominal CoG of the {contact} contact case {topo.face_label(face)}, by statics"
        nan = formats.NOMINAL_ALLOW_NAN
        out.append(datasets.write(ds, path, provenance(cfg), title, stage="nominal_statics", allow_nan=nan))
    return out
