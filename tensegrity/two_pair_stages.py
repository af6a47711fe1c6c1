"""The two-pair workspace stages (issue 10, item 1), files to files, as `tensegrity.stages` has
them for single pairs: sweep one contact case, map to all 20 faces, fit the surfaces, validate,
render. The Snakemake rules (workflow/rules/two_pair.smk) call these; `cfg` is the resolved
configuration (sections of STAGE_CONFIG).
"""
from __future__ import annotations

import json
import os
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from .io import datasets, two_pair_formats as tpf
from .io.config import params_from_config
from .io.cross_checks import section_errors
from .physics import topology as topo
from .workspace import two_pair as tp


def check_config(cfg: Mapping) -> dict:
    """The `two_pair` section of `cfg`; ValueError naming the key if it fails the checks the
    schema cannot make (`io.cross_checks.section_errors`)."""
    errors = section_errors(cfg, "two_pair")
    if errors:
        raise ValueError("; ".join(errors))
    return cfg["two_pair"]


def combos_of(pairs: Sequence[int]) -> np.ndarray:
    """The combinations (n, 2) of two distinct pairs among `pairs` (two_pair.pairs)."""
    return tp.COMBOS[np.isin(tp.COMBOS, np.asarray(pairs, int)).all(axis=1)]


def run_two_pair(cfg: dict, contact: str, out_path: str | os.PathLike) -> Path:
    """Stage `two_pair`: sweep one combination per stabiliser orbit on the canonical face of
    `contact` (free mode, one batched run), map to the other combinations of that face, write
    results/two_pair/{contact}.nc."""
    if contact not in topo.CONTACT_FACES:
        raise ValueError(f"unknown contact {contact!r}: use one of {list(topo.CONTACT_FACES)}")
    s = check_config(cfg)
    face = topo.face_number(topo.CONTACT_FACES[contact])
    reps = tp.representatives(face, combos_of(s["pairs"]))
    print(f"{topo.face_label(face)}: {len(reps)} combinations swept (one per stabiliser orbit) over "
          f"{len(s['levels'])}x{len(s['levels'])} levels", flush=True)
    res = tp.sweep(params_from_config(cfg), face, reps, s["levels"], s["hold"], s["discard"],
                   cfg["sim"]["dt"], s["record_every"])
    cog, support, path = tp.map_face(face, face, reps, res["cog"], res["support"])
    ws = {"cog": cog, "support": support, "staircase": path, "margin": tp.margins(cog, support)}
    t = [tp.tips(s["levels"], cog[c], support[c], ws["margin"][c], face) for c in range(len(tp.COMBOS))]
    ws |= {"tip_pressure": np.array([x[0] for x in t]), "tip_edge": np.array([x[1] for x in t], np.int64),
           "tip_boundary": np.array([x[2] for x in t])}
    rows = np.array([tp.combo_index(*c) for c in reps])
    swept = np.isin(np.arange(len(tp.COMBOS)), rows)
    std = np.full(cog.shape, np.nan)
    std[rows] = res["cog_std"][:, topo.FACE_REFERENCE[face - 1]]
    attrs = {"contact": contact, "face": face, "face_nodes": topo.FACES[face - 1] + 1, "mode": "free",
             "hold_s": float(s["hold"]), "discard_s": float(s["discard"])}
    ds = tpf.contact_dataset(s["levels"], tp.COMBOS, ws, swept, std, attrs)
    return datasets.write(ds, out_path, cfg, f"Two-pair workspace of the {contact} contact case {topo.face_label(face)}",
                          stage="two_pair", allow_nan=tpf.ALLOW_NAN)


def _canonical(paths: Sequence[str | os.PathLike]) -> tuple[np.ndarray, dict, dict]:
    src = {str(ds.attrs["contact"]): ds for ds in (datasets.read(p) for p in paths)}
    levels = [ds["pressure_a"].values for ds in src.values()]
    if not levels or any(not np.array_equal(lv, levels[0]) for lv in levels):
        raise ValueError("the two-pair contact files were swept at different levels (or none is given)")
    return levels[0], src, {c: (ds["combo_pairs"].values, ds["cog"].values, ds["support"].values,
                                ds["staircase_pairs"].values) for c, ds in src.items()}


def two_pair_map(cfg: dict, contact_paths: Sequence[str | os.PathLike], out_path: str | os.PathLike) -> Path:
    """Stage `two_pair_map`: results/workspace_two_pair.nc, every face from the contact files."""
    levels, src, canonical = _canonical(contact_paths)
    ws = tp.map_workspace(levels, canonical)
    prov = {}
    for p in contact_paths:
        prov.update(datasets.provenance_config(p))
    ds = tpf.workspace_dataset(levels, tp.COMBOS, ws, {"mode": "free"})
    return datasets.write(ds, out_path, prov | cfg, "Two-pair workspace of all 20 contact faces, mapped by symmetry",
                          stage="two_pair_map", allow_nan=[k for k in tpf.ALLOW_NAN if k != "cog_std"])


def two_pair_curves(cfg: dict, contact_paths: Sequence[str | os.PathLike], out_path: str | os.PathLike) -> Path:
    """Stage `two_pair_curves`: a polynomial surface per combination with data and axis of each
    contact case (degree by cross-validation, fit.max_degree and fit.folds) as
    results/curves/two_pair.json (plain numbers; `io.two_pair_formats.evaluate_surface`)."""
    levels, src, _ = _canonical(contact_paths)
    f = cfg["fit"]
    pa, pb = np.meshgrid(levels, levels, indexing="ij")
    contacts = {}
    for contact, ds in sorted(src.items()):
        cog = ds["cog"].values
        rows = [c for c in range(cog.shape[0]) if np.isfinite(cog[c]).all()]
        surf = [[tp.fit_surface(pa, pb, cog[c, ..., a], f["max_degree"], f["folds"]) for a in range(3)] for c in rows]
        contacts[contact] = (ds.attrs["face_nodes"], ds["combo_pairs"].values[rows], surf)
    doc = tpf.surfaces_document(contacts)
    return datasets.write_text(out_path, json.dumps(doc, indent=1, sort_keys=True, allow_nan=False))


def render_two_pair(nominal_path: str | os.PathLike, contact_path: str | os.PathLike, out: str | os.PathLike) -> dict:
    """Figure stage (rule `render`): the CoG projections one pair reaches (results/nominal/{contact}.nc)
    and two pairs reach (results/two_pair/{contact}.nc), with the unactuated support triangle."""
    from .physics import frames
    from .render import two_pair as draw
    nm, tw = datasets.read(nominal_path), datasets.read(contact_path)
    face = int(tw.attrs["face"])
    _, rest = frames.rest_frame(face, datasets.strut_length(tw))
    one = nm["cog"].values.reshape(-1, 3)
    two = tw["cog"].values.reshape(-1, 3)
    levels = tw["pressure_a"].values
    title = (f"Two-pair workspace, {tw.attrs['contact']} face {topo.face_label(face)}, CoG projections\n"
             f"one pair {nm['pressure'].values[0]:g}-{nm['pressure'].values[-1]:g} MPa, "
             f"two pairs {levels[0]:g}-{levels[-1]:g} MPa each")
    return draw.fig_two_pair(one[np.isfinite(one).all(1)], two[np.isfinite(two).all(1)], rest,
                             topo.FACES[face - 1] + 1, out, title)


def validate_two_pair(cfg: dict, contact_paths: Sequence[str | os.PathLike], two_pair_path: str | os.PathLike,
                      workspace_path: str | os.PathLike, nc_path: str | os.PathLike, md_path: str | os.PathLike,
                      html_path: str | os.PathLike | None = None) -> list[Path]:
    """Stage `validate_two_pair`: statics, direct simulation on other faces, superposition
    (validation.two_pair); writes results/validation/two_pair.nc, .md and .html."""
    from .validation import two_pair as v
    check_config(cfg)
    return v.run_stage(cfg, contact_paths, two_pair_path, workspace_path, nc_path, md_path, html_path)
