"""Rule `fit` (workflow/rules/fit.smk): a cross-validated curve of the nominal CoG against
pressure per pair and axis (results/curves/{contact}.nc, curves.json), and the fitted two-pair
surfaces (results/curves/two_pair.json)."""

from __future__ import annotations

import json
import os
from collections.abc import Iterable, Sequence
from pathlib import Path

import numpy as np

from .. import atomic
from ..io import datasets, formats
from ..io.formats import actuation
from ..io.formats import two_pair as tpf
from ..physics import topology as topo
from . import provenance


def curves(cfg: dict, nominal_path: str | os.PathLike, out_path: str | os.PathLike) -> Path:
    """Stage `curves`: a curve per pair and axis of one contact case's nominal CoG (models up to
    fit.max_degree and splines of fit.spline_knots, chosen by fit.folds-fold cross-validation)."""
    from ..workspace import fit

    src = datasets.read(nominal_path)
    f, kind = cfg["fit"], actuation.kind_of(src)
    p, cog = src["pressure"].values, src["cog"].values
    ok = np.isfinite(cog).all(axis=-1)  # levels before a grounded robot rolled off its face
    for i, pair in enumerate(src["pair"].values):
        if ok[i].sum() < 2:
            raise ValueError(
                f"pair #{pair} on {topo.face_label(int(src.attrs['face']))} stood at fewer than 2 "
                f"levels (it rolled off at {float(src['tip_pressure'][i]):g} {actuation.units(kind)}): "
                f"nothing to fit; sweep lower {actuation.words('pressures', kind)} or use the free mode"
            )
    found = [
        [
            fit.fit_curve(
                p[ok[i]],
                cog[i, ok[i], a],
                max_degree=f["max_degree"],
                spline_knots=tuple(f["spline_knots"]),
                folds=f["folds"],
            )
            for a in range(3)
        ]
        for i in range(cog.shape[0])
    ]
    ds = formats.curves_dataset(
        fit.curves_to_arrays(found),
        src["pair"],
        src["axis"],
        {k: src.attrs[k] for k in ("contact", "face", "face_nodes", "mode")},
    )
    return datasets.write(
        actuation.relabel(ds, kind),
        out_path,
        provenance(cfg, nominal_path),
        f"Fitted CoG curves of the {src.attrs['contact']} contact case",
        stage="fit",
        allow_nan=formats.CURVES_ALLOW_NAN,
    )


def curves_json(cfg: dict, curve_paths: Iterable[str | os.PathLike], out_path: str | os.PathLike) -> Path:
    """Stage `curves_json`: all contact cases' curves as one JSON file (plain numbers, evaluable
    in any language; `formats.curves_document`), naming the configuration of the curve files."""
    from ..workspace import fit

    contacts, read = {}, []
    for path in curve_paths:
        ds = datasets.read(path)
        read.append(ds)
        contacts[ds.attrs["contact"]] = (
            ds.attrs["face_nodes"],
            ds["pair"].values,
            fit.arrays_to_curves({k: ds[k].values for k in fit.ARRAY_DIMS if k in ds}),
        )
    curve_paths = list(curve_paths)
    doc = formats.curves_document(contacts, provenance(cfg, *curve_paths), actuation.common_kind(read))
    return atomic.write_text(out_path, json.dumps(doc, indent=1, sort_keys=True, allow_nan=False))


def two_pair_surfaces(cfg: dict, contact_paths: Sequence[str | os.PathLike], out_path: str | os.PathLike) -> Path:
    """Stage `two_pair_surfaces`: a surface per combination with data and axis of each contact
    case (a polynomial of degree up to fit.max_degree by fit.folds-fold cross-validation, or the
    spline interpolating the grid where the polynomial misses a point by more than
    `workspace.surfaces.MAX_RESIDUAL`; each with its largest residual) as
    results/curves/two_pair.json (plain numbers; `io.formats.two_pair.evaluate_surface`), naming
    the configuration it was made with."""
    from ..workspace.surfaces import fit_surface

    levels, src = tpf.read_contacts(contact_paths)
    f = cfg["fit"]
    pa, pb = np.meshgrid(levels, levels, indexing="ij")
    contacts = {}
    for contact, ds in sorted(src.items()):
        cog = ds["cog"].values
        rows = [c for c in range(cog.shape[0]) if np.isfinite(cog[c]).all()]
        surf = [[fit_surface(pa, pb, cog[c, ..., a], f["max_degree"], f["folds"]) for a in range(3)] for c in rows]
        contacts[contact] = (ds.attrs["face_nodes"], ds["combo_pairs"].values[rows], surf)
    doc = tpf.surfaces_document(contacts, provenance(cfg, *contact_paths), actuation.common_kind(src.values()))
    return atomic.write_text(out_path, json.dumps(doc, indent=1, sort_keys=True, allow_nan=False))
