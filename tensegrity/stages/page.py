"""Rule `page` (workflow/rules/page.smk): the interactive 3D page of the workspace and of the runs
(render.page), from the sweeps, the nominal CoGs, the fitted curves and the runs the rule names."""

from __future__ import annotations

import os
from collections.abc import Sequence

import numpy as np

from ..io import datasets
from ..io.formats import actuation
from ..io.formats import run as run_formats
from ..physics import frames
from ..physics import topology as topo
from ..workspace import nominal as nom

TITLE = "Six-strut tensegrity robot: workspace (paper Figs. 6-7 in 3D)"


def _by_contact(paths: Sequence[str | os.PathLike], what: str) -> dict:
    """{contact: dataset} of the files `paths`; ValueError naming a file given twice for a case."""
    out = {}
    for p in paths:
        ds = datasets.read(p)
        c = str(ds.attrs["contact"])
        if c in out:
            raise ValueError(f"{what}: two files of the {c} case ({p})")
        out[c] = ds
    return out


def _workspace(contact: str, nm, cv, sweeps: list, points: int):
    """The render.page.Workspace of one contact case from its nominal and curves datasets and
    its sweeps: each pair's samples at the levels it stood at (none without sweeps, under
    nominal.method statics), its nominal CoGs there, its fitted curve from the unactuated CoG
    and the curve at its tipping pressure (as Fig. 7, stages.render.curve_line and tip_point)."""
    from ..render.page import Workspace
    from ..workspace import fit
    from .render import curve_line, tip_point

    face, length = int(nm.attrs["face"]), datasets.strut_length(nm)
    rest_cog, rest_support = frames.rest_frame(face, length)
    nodes = topo.reference_nodes(length)
    nodes = frames.to_frame(nodes, *frames.face_frame(nodes, face))
    curves = fit.arrays_to_curves({k: cv[k].values for k in fit.ARRAY_DIMS})
    pairs = [int(p) for p in cv["pair"].values]
    lines = {p: curve_line(curves[i], rest_cog, points) for i, p in enumerate(pairs)}
    tips = {p: tip_point(curves[i], float(nm["tip_pressure"].sel(pair=p))) for i, p in enumerate(pairs)}
    clouds, nominal = {}, {}
    for pair in sorted({int(p) for p in nm["pair"].values} | {int(sw.attrs["pair"]) for sw in sweeps}):
        cog = nm["cog"].sel(pair=pair).values
        nominal[pair] = cog[: nom.levels_stood(cog, nm["rolled"].sel(pair=pair).values if "rolled" in nm else None)]
    for sw in sweeps:  # none under nominal.method statics: nothing oscillated
        pair = int(sw.attrs["pair"])
        level = sw["level"].values
        clouds[pair] = sw["cog"].values[(level >= 0) & (level < len(nominal[pair]))]
    tips = {p: t for p, t in tips.items() if t is not None}
    unit = actuation.units(actuation.kind_of(nm))
    return Workspace(contact, face, nodes, rest_support, clouds, lines, nominal, tips, unit)


def _run(path: str | os.PathLike):
    from ..render.page import Run

    ds = datasets.read(path)
    t = ds["time"].values
    name = str(ds.attrs.get("run", os.path.basename(os.fspath(path)).removesuffix(".nc")))
    return Run(
        name,
        f"run '{name}': {ds.attrs['outcome']}, {int(ds.attrs['rolls'])} rolls",
        ds["nodes"].values,
        ds["next_face"].values,
        np.clip(np.searchsorted(t, ds["t_end"].values), 0, len(t) - 1),
        ds["goal"].values,
        run_formats.terrain_from_dataset(ds),
    )


def page(
    cfg: dict,
    sweeps: Sequence[str | os.PathLike],
    nominal: Sequence[str | os.PathLike],
    curves: Sequence[str | os.PathLike],
    out: str | os.PathLike,
    runs: Sequence[str | os.PathLike] = (),
    points: int = 60,
) -> dict:
    """Stage `page`: the interactive page (render.page) of every contact case with a nominal and
    a curves file (results/nominal/{contact}.nc, results/curves/{contact}.nc), the sweeps of
    its pairs (results/sweeps/{contact}/pairNN.nc) and the runs (results/locomotion/{run}.nc),
    written to the HTML file `out`. Returns what was drawn (render.page.write_page)."""
    from ..render.page import write_page

    nms, cvs = _by_contact(nominal, "nominal"), _by_contact(curves, "curves")
    if set(nms) != set(cvs):
        raise ValueError(f"nominal files of {sorted(nms)} but curves files of {sorted(cvs)}: give both per case")
    by_case: dict = {c: [] for c in nms}
    for p in sweeps:
        sw = datasets.read(p)
        c = str(sw.attrs["contact"])
        if c not in by_case:
            raise ValueError(f"sweep {p} is of the {c} case, which has no nominal and curves file")
        by_case[c].append(sw)
    order = [c for c in topo.CONTACTS if c in nms]
    workspaces = [_workspace(c, nms[c], cvs[c], by_case[c], points) for c in order]
    return write_page(workspaces, [_run(p) for p in runs], out, TITLE + (" and rolling runs" if runs else ""))
