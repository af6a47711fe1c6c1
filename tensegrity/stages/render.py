"""Rule `render` (workflow/rules/render.smk): the paper's Figs. 1, 4, 5, 6, 7 and the two-pair
regions, from the datasets the rule names; and `render_dataset`, any dataset of the toolkit to
a PNG (`tensegrity render`). Only `render` draws; these read the files and hand it arrays."""

from __future__ import annotations

import os
from collections.abc import Sequence

import numpy as np

from .. import paper
from ..io import datasets, settings
from ..io.formats import actuation
from ..physics import frames
from ..physics import topology as topo
from ..workspace import nominal as nom


def robot_figures(cfg: dict, fig1: str | os.PathLike, fig4: str | os.PathLike, fig5: str | os.PathLike) -> list[dict]:
    """Stage `robot_figures`: Figs. 1, 4 and 5: the robot, its actuator pairs, and the support
    frame of (9,10,12). Returns what each figure drew (render.paper)."""
    from ..physics import dynamics as d
    from ..physics.terrain import Terrain
    from ..render import paper as figures

    params = settings.params(cfg)
    nodes = topo.reference_nodes(params.strut_length)
    state = d.stand_on(params, paper.START_FACE, Terrain.flat())
    return [
        figures.fig_robot(nodes, fig1),
        figures.fig_robot(nodes, fig4, highlight_pairs=list(paper.FIG4_PAIRS)),
        figures.fig_support_frame(d.nodes(state.x, state.q, params.strut_length)[0], paper.START_FACE, fig5),
    ]


def _corners(face: int) -> list[int]:
    return (topo.FACES[face - 1] + 1).tolist()


def cog_cloud(
    cfg: dict,
    sweep_path: str | os.PathLike | None,
    nominal_path: str | os.PathLike,
    out: str | os.PathLike,
    max_pressure: float | None = None,
) -> dict:
    """Stage `cog_cloud`: Fig. 6, the CoG point cloud and nominal CoGs of one pair, levels up to
    max_pressure (MPa; default the paper's Fig. 6 range, paper.FIG6_MAX_PRESSURE; every level
    of a sweep in volts, whose unit the files give: `formats.actuation`). A grounded robot that
    rolled off its face (`rolled`) is drawn only at the levels before the roll, and the title
    says so. Without a sweep (nominal.method statics) the nominal CoGs of Fig. 6's pair are the
    equilibria themselves: no cloud, one point per level, and the title says so. Returns what
    the figure drew (render.cog_cloud.fig_cog_cloud)."""
    from ..render import cog_cloud as fig6

    if sweep_path is None:  # statics: pneumatic only (io.cross_checks)
        top = paper.FIG6_MAX_PRESSURE if max_pressure is None else max_pressure
        return _statics_cloud(datasets.read(nominal_path), out, top)
    sw_ds, nm = datasets.read(sweep_path), datasets.read(nominal_path)
    kind = actuation.kind_of(nm)
    unit = actuation.units(kind)
    if max_pressure is None:
        max_pressure = paper.FIG6_MAX_PRESSURE if kind == actuation.PNEUMATIC else np.inf
    pair, face = int(sw_ds.attrs["pair"]), int(sw_ds.attrs["face"])
    levels = nm["pressure"].values
    cog = nm["cog"].sel(pair=pair).values
    rolled = nm["rolled"].sel(pair=pair).values if "rolled" in nm else None
    n_stood = nom.levels_stood(cog, rolled)
    keep = (levels <= max_pressure + 1e-9) & (np.arange(len(levels)) < n_stood)
    if not keep.any():
        raise ValueError(
            f"pair #{pair} on {topo.face_label(face)} rolled off its face at the first "
            f"level ({levels[0]:g} {unit}): no level to draw"
        )
    sel = (sw_ds["level"].values >= 0) & (sw_ds["level"].values < keep.sum())
    title = None
    if n_stood < len(levels) and levels[n_stood] <= max_pressure + 1e-9:
        title = (
            f"Fig. 6  CoG path when #{pair} works, face {topo.face_label(face)}, "
            f"{levels[0]:g}-{levels[keep][-1]:g} {unit}: it rolled off at {levels[n_stood]:g} {unit}"
        )
    return fig6.fig_cog_cloud(
        sw_ds["cog"].values[sel],
        cog[keep],
        levels[keep],
        frames.rest_frame(face, datasets.strut_length(nm))[1],
        out,
        pair=pair,
        face_label=topo.face_label(face),
        sample_pressure=sw_ds["pressure_cmd"].values[sel],
        corner_labels=_corners(face),
        title=title,
        unit=unit,
    )


def _statics_cloud(nm, out: str | os.PathLike, max_pressure: float) -> dict:
    """Fig. 6 of a nominal file made by statics: paper.FIG6_PAIR's equilibria (or the first pair
    of the file) up to max_pressure MPa, each the one sample of its level."""
    from ..render import cog_cloud as fig6

    pairs = [int(p) for p in nm["pair"].values]
    pair, face = (paper.FIG6_PAIR if paper.FIG6_PAIR in pairs else pairs[0]), int(nm.attrs["face"])
    levels = nm["pressure"].values
    keep = levels <= max_pressure + 1e-9
    cog = nm["cog"].sel(pair=pair).values[keep]
    title = (  # no longer than the sweep's title: the figure is 1200 px wide
        f"Fig. 6  Equilibria when #{pair} works, face {topo.face_label(face)}, "
        f"{levels[keep][0]:g}-{levels[keep][-1]:g} MPa (statics: no samples)"
    )
    return fig6.fig_cog_cloud(
        cog,
        cog,
        levels[keep],
        frames.rest_frame(face, datasets.strut_length(nm))[1],
        out,
        pair=pair,
        face_label=topo.face_label(face),
        sample_pressure=levels[keep],
        corner_labels=_corners(face),
        title=title,
    )


def curve_line(curve: Sequence, rest_cog: np.ndarray, points: int) -> np.ndarray:
    """A pair's fitted CoG curve (its three axes, workspace.fit) as a line (points + 1, 3) m: the
    unactuated CoG rest_cog (3,) m, then `points` pressures from its pmin to its pmax (Fig. 7)."""
    from ..workspace import fit

    p = np.linspace(curve[0].pmin, curve[0].pmax, points)
    return np.vstack([rest_cog[None], np.stack([fit.evaluate(curve[a], p) for a in range(3)], axis=-1)])


def tip_point(curve: Sequence, tip_pressure: float) -> np.ndarray | None:
    """The fitted curve (its three axes) at the tipping pressure (MPa), where the CoG projection
    leaves the deformed triangle (Fig. 7's red ring), (3,) m; None if the pair never tips or
    tips beyond the curve's range (a grounded robot that rolled off first)."""
    from ..workspace import fit

    if not np.isfinite(tip_pressure) or tip_pressure > curve[0].pmax + 1e-9:
        return None
    return np.array([float(fit.evaluate(curve[a], tip_pressure)) for a in range(3)])


def workspace_figure(
    cfg: dict, curves_path: str | os.PathLike, nominal_path: str | os.PathLike, out: str | os.PathLike, points: int = 60
) -> dict:
    """Stage `workspace_figure`: Fig. 7, every pair's fitted CoG curve from 0 MPa to the highest
    level it stood at, with the support triangle of the unactuated robot, a red ring where a
    curve leaves its deformed triangle (the curve at the tipping pressure) and that deformed
    triangle, dashed (the nominal support interpolated at the tipping pressure). A grounded robot
    that rolled off its face before its CoG left the triangle gets no ring; the title names those
    pairs. Returns what the figure drew (render.face_workspace.fig_workspace)."""
    from ..render import face_workspace as fig7
    from ..workspace import fit

    cv, nm = datasets.read(curves_path), datasets.read(nominal_path)
    face, unit = int(nm.attrs["face"]), actuation.units(actuation.kind_of(nm))
    rest_cog, rest_support = frames.rest_frame(face, datasets.strut_length(nm))
    curves = fit.arrays_to_curves({k: cv[k].values for k in fit.ARRAY_DIMS if k in cv})
    levels = nm["pressure"].values
    lines, tips, tip_supports, rolled = {}, {}, {}, {}
    for i, pair in enumerate(cv["pair"].values):
        c = curves[i]
        lines[int(pair)] = curve_line(c, rest_cog, points)
        tp = float(nm["tip_pressure"].sel(pair=pair))
        if (tip := tip_point(c, tp)) is not None:
            tips[int(pair)] = tip
            tip_supports[int(pair)] = fig7.at_pressure(levels, nm["support"].sel(pair=pair).values, tp)
        elif np.isfinite(tp):  # grounded: rolled off at tp before its CoG left the triangle
            rolled[int(pair)] = tp
    title = (
        f"Fig. 7  Kinematic workspace, {nm.attrs['contact']} face {topo.face_label(face)}, "
        f"{levels[0]:g}-{levels[-1]:g} {unit}"
    )
    if rolled:
        title += (
            "; "
            + ", ".join(f"#{v}" for v in rolled)
            + f" rolled off at {min(rolled.values()):g}"
            + (f"-{max(rolled.values()):g}" if max(rolled.values()) > min(rolled.values()) else "")
            + f" {unit}"
        )
    return fig7.fig_workspace(
        lines,
        rest_support,
        out,
        tip_points=tips,
        tip_supports=tip_supports,
        title=title,
        corner_labels=_corners(face),
        unit=unit,
    )


def two_pair_figure(
    cfg: dict, nominal_path: str | os.PathLike, contact_path: str | os.PathLike, out: str | os.PathLike
) -> dict:
    """Stage `two_pair_figure`: the CoG projections one pair reaches (results/nominal/{contact}.nc)
    and two pairs reach (results/two_pair/{contact}.nc), with the unactuated support triangle."""
    from ..render import two_pair as draw

    nm, tw = datasets.read(nominal_path), datasets.read(contact_path)
    face = int(tw.attrs["face"])
    _, rest = frames.rest_frame(face, datasets.strut_length(tw))
    one = nm["cog"].values.reshape(-1, 3)
    two = tw["cog"].values.reshape(-1, 3)
    levels, unit = tw["pressure_a"].values, actuation.units(actuation.common_kind([nm, tw]))
    title = (
        f"Two-pair workspace, {tw.attrs['contact']} face {topo.face_label(face)}, CoG projections\n"
        f"one pair {nm['pressure'].values[0]:g}-{nm['pressure'].values[-1]:g} {unit}, "
        f"two pairs {levels[0]:g}-{levels[-1]:g} {unit} each"
    )
    return draw.fig_two_pair(
        one[np.isfinite(one).all(1)], two[np.isfinite(two).all(1)], rest, topo.FACES[face - 1] + 1, out, title
    )


def render_dataset(path: str | os.PathLike, out: str | os.PathLike, face: int | None = None) -> str:
    """Render any dataset of the toolkit to a PNG: a sweep (its CoG cloud), a nominal file or
    the workspace (the workspace of its face, or of `face`), a locomotion run (its path from
    above), a `tensegrity simulate` output (the robot at the end). Returns what was drawn."""
    from ..render import cog_cloud as fig6
    from ..render import paper as figures

    ds = datasets.read(path)
    if "level" in ds and "pair" in ds.attrs:  # a sweep
        face_ = int(ds.attrs["face"])
        sel = ds["level"].values >= 0
        levels = ds["levels"].values
        mean = np.array([ds["cog"].values[ds["level"].values == k].mean(0) for k in range(levels.size)])
        fig6.fig_cog_cloud(
            ds["cog"].values[sel],
            mean,
            levels,
            frames.rest_frame(face_, datasets.strut_length(ds))[1],
            out,
            pair=int(ds.attrs["pair"]),
            face_label=topo.face_label(face_),
            sample_pressure=ds["pressure_cmd"].values[sel],
            corner_labels=_corners(face_),
            unit=actuation.units(actuation.kind_of(ds)),
        )
        return "sweep: CoG cloud and level means"
    if "margin" in ds and "face" in ds.dims:  # the workspace
        face_ = topo.face_number(face) if face is not None else topo.face_number(paper.START_FACE)
        title = f"Workspace of face {face_} {topo.face_label(face_)} (nominal CoG, mapped)"
        return _render_nominal(ds.sel(face=face_), face_, datasets.strut_length(ds), out, title)
    if "margin" in ds and "pair" in ds.dims:  # a nominal file
        face_ = int(ds.attrs["face"])
        return _render_nominal(ds, face_, datasets.strut_length(ds), out, f"Nominal CoG, face {topo.face_label(face_)}")
    if "face_sequence" in ds or "step" in ds.dims:  # a locomotion run
        from .locomotion import _path_figure

        _path_figure(ds, out, "top")
        return "locomotion run: path from above"
    if "nodes" in ds and "time" in ds["nodes"].dims:  # tensegrity simulate
        figures.fig_robot(ds["nodes"].values[-1], out, title=f"{ds.attrs.get('title', 'robot')} (end)")
        return "simulation: the robot at the end"
    raise ValueError(f"{path}: not a dataset this toolkit knows how to render")


def _render_nominal(ds, face: int, strut_length: float, out: str | os.PathLike, title: str) -> str:
    """Fig. 7 drawn from the nominal CoGs of `ds` (a nominal file or one face of the workspace):
    each pair's levels it stood at, a red ring at the tipping pressure (the nominal CoG
    interpolated there) and the deformed support there, dashed."""
    from ..render import face_workspace as fig7

    rest_cog, rest_support = frames.rest_frame(face, strut_length)
    levels = ds["pressure"].values
    lines, tips, tip_supports = {}, {}, {}
    for p in ds["pair"].values:
        cog = ds["cog"].sel(pair=p).values
        n = nom.levels_stood(cog)
        if n == 0:
            continue
        lines[int(p)] = np.vstack([rest_cog[None], cog[:n]])
        tp = float(ds["tip_pressure"].sel(pair=p)) if "tip_pressure" in ds else float("nan")
        if np.isfinite(tp) and tp <= levels[n - 1] + 1e-9:
            tips[int(p)] = fig7.at_pressure(levels[:n], cog[:n], tp)
            tip_supports[int(p)] = fig7.at_pressure(levels[:n], ds["support"].sel(pair=p).values[:n], tp)
    fig7.fig_workspace(
        lines,
        rest_support,
        out,
        title=title,
        tip_points=tips,
        tip_supports=tip_supports,
        corner_labels=_corners(face),
        unit=actuation.units(actuation.kind_of(ds)),
    )
    return "workspace: nominal CoG per pair"
