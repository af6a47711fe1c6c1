"""The figure stages: read the datasets a figure rule names, call `render`, write the PNG/GIF.

The Snakemake rules reach them through `tensegrity.stages` (which re-exports them), as every
other stage; `tensegrity render` uses `render_dataset`.
"""
from __future__ import annotations

import os

import numpy as np
import xarray as xr

from .io import datasets, run_formats
from .io.config import params_from_config
from .physics import frames, topology as topo


def render_robot(cfg: dict, fig1: str | os.PathLike, fig4: str | os.PathLike,
                 fig5: str | os.PathLike) -> list[dict]:
    """Figs. 1, 4 and 5: the robot, its actuator pairs, and the support frame of (9,10,12).
    Returns what each figure drew (render.paper)."""
    from .physics import dynamics as d
    from .render import paper
    from .physics.terrain import Terrain
    params = params_from_config(cfg)
    nodes = topo.reference_nodes(params.strut_length)
    state = d.stand_on(params, topo.CONTACT_FACES["equilateral"], Terrain.flat())
    return [paper.fig_robot(nodes, fig1),
            paper.fig_robot(nodes, fig4, highlight_pairs=[4, 6, 7, 9, 10, 12]),
            paper.fig_support_frame(d.nodes(state.x, state.q, params.strut_length)[0],
                                    topo.CONTACT_FACES["equilateral"], fig5)]


def render_cloud(sweep_path: str | os.PathLike, nominal_path: str | os.PathLike, out: str | os.PathLike,
                 max_pressure: float = 2.4) -> dict:
    """Fig. 6: the CoG point cloud and nominal CoGs of one pair, levels up to max_pressure
    (MPa). A grounded robot that rolled off its face (`rolled`) is drawn only at the levels
    before the roll, and the title says so. Returns what the figure drew
    (render.frame_plots.fig_cog_cloud)."""
    from .render import frame_plots
    sw_ds, nm = datasets.read(sweep_path), datasets.read(nominal_path)
    pair, face = int(sw_ds.attrs["pair"]), int(sw_ds.attrs["face"])
    levels = nm["pressure"].values
    nom = nm["cog"].sel(pair=pair).values
    stood = np.isfinite(nom).all(axis=-1)
    if "rolled" in nm:
        stood &= nm["rolled"].sel(pair=pair).values == 0
    n_stood = int(np.argmin(stood)) if not stood.all() else len(levels)  # levels before the roll
    keep = (levels <= max_pressure + 1e-9) & (np.arange(len(levels)) < n_stood)
    if not keep.any():
        raise ValueError(f"pair #{pair} on {topo.face_label(face)} rolled off its face at the first "
                         f"level ({levels[0]:g} MPa): no level to draw")
    sel = (sw_ds["level"].values >= 0) & (sw_ds["level"].values < keep.sum())
    title = None
    if n_stood < len(levels) and levels[n_stood] <= max_pressure + 1e-9:
        title = (f"Fig. 6  CoG path when #{pair} works, face {topo.face_label(face)}, "
                 f"{levels[0]:g}-{levels[keep][-1]:g} MPa: it rolled off at {levels[n_stood]:g} MPa")
    return frame_plots.fig_cog_cloud(sw_ds["cog"].values[sel], nom[keep], levels[keep],
                               frames.rest_frame(face, datasets.strut_length(nm))[1], out,
                               pair=pair, face_label=topo.face_label(face),
                               sample_pressure=sw_ds["pressure_cmd"].values[sel],
                               corner_labels=(topo.FACES[face - 1] + 1).tolist(), title=title)


def render_workspace(curves_path: str | os.PathLike, nominal_path: str | os.PathLike, out: str | os.PathLike,
                     points: int = 60) -> dict:
    """Fig. 7: every pair's fitted CoG curve from 0 MPa to the highest level it stood at, with
    the support triangle of the unactuated robot, a red ring where a curve leaves its deformed
    triangle (the curve at the tipping pressure) and that deformed triangle, dashed (the
    nominal support interpolated at the tipping pressure). A grounded robot that rolled off its
    face before its CoG left the triangle gets no ring; the title names those pairs.
    Returns what the figure drew (render.frame_plots.fig_workspace)."""
    from .workspace import fit
    from .render import frame_plots
    cv, nm = datasets.read(curves_path), datasets.read(nominal_path)
    face = int(nm.attrs["face"])
    rest_cog, rest_support = frames.rest_frame(face, datasets.strut_length(nm))
    curves = fit.arrays_to_curves({k: cv[k].values for k in fit.ARRAY_DIMS})
    levels = nm["pressure"].values
    lines, tips, tip_supports, rolled = {}, {}, {}, {}
    for i, pair in enumerate(cv["pair"].values):
        c = curves[i]
        p = np.linspace(c[0].pmin, c[0].pmax, points)
        xyz = np.stack([fit.evaluate(c[a], p) for a in range(3)], axis=-1)
        lines[int(pair)] = np.vstack([rest_cog[None], xyz])
        tp = float(nm["tip_pressure"].sel(pair=pair))
        if np.isfinite(tp) and tp <= c[0].pmax + 1e-9:
            tips[int(pair)] = np.array([float(fit.evaluate(c[a], tp)) for a in range(3)])
            tip_supports[int(pair)] = frame_plots.at_pressure(levels, nm["support"].sel(pair=pair).values, tp)
        elif np.isfinite(tp):  # grounded: rolled off at tp before its CoG left the triangle
            rolled[int(pair)] = tp
    title = (f"Fig. 7  Kinematic workspace, {nm.attrs['contact']} face {topo.face_label(face)}, "
             f"{levels[0]:g}-{levels[-1]:g} MPa")
    if rolled:
        title += ("; " + ", ".join(f"#{v}" for v in rolled)
                  + f" rolled off at {min(rolled.values()):g}"
                  + (f"-{max(rolled.values()):g}" if max(rolled.values()) > min(rolled.values()) else "")
                  + " MPa")
    return frame_plots.fig_workspace(lines, rest_support, out, tip_points=tips, tip_supports=tip_supports,
                               title=title, corner_labels=(topo.FACES[face - 1] + 1).tolist())


def render_dataset(path: str | os.PathLike, out: str | os.PathLike, face: int | None = None) -> str:
    """Render any dataset of the toolkit to a PNG: a sweep (its CoG cloud), a nominal file or
    the workspace (the workspace of its face, or of `face`), a locomotion run (its path from
    above), a `tensegrity simulate` output (the robot at the end). Returns what was drawn."""
    from .render import frame_plots, paper
    ds = datasets.read(path)
    if "level" in ds and "pair" in ds.attrs:  # a sweep
        face_ = int(ds.attrs["face"])
        sel = ds["level"].values >= 0
        levels = ds["levels"].values
        nom = np.array([ds["cog"].values[ds["level"].values == k].mean(0) for k in range(levels.size)])
        frame_plots.fig_cog_cloud(ds["cog"].values[sel], nom, levels,
                            frames.rest_frame(face_, datasets.strut_length(ds))[1], out,
                            pair=int(ds.attrs["pair"]), face_label=topo.face_label(face_),
                            sample_pressure=ds["pressure_cmd"].values[sel],
                            corner_labels=(topo.FACES[face_ - 1] + 1).tolist())
        return "sweep: CoG cloud and level means"
    if "margin" in ds and "face" in ds.dims:  # the workspace
        face_ = topo.face_number(face) if face is not None else 8
        sub = ds.sel(face=face_)
        title = f"Workspace of face {face_} {topo.face_label(face_)} (nominal CoG, mapped)"
        return _render_nominal(sub, face_, out, title)
    if "margin" in ds and "pair" in ds.dims:  # a nominal file
        face_ = int(ds.attrs["face"])
        return _render_nominal(ds, face_, out, f"Nominal CoG, face {topo.face_label(face_)}")
    if "face_sequence" in ds or "step" in ds.dims:  # a locomotion run
        _path_figure(ds, out, "top")  # in the locomotion figure stages below
        return "locomotion run: path from above"
    if "nodes" in ds and "time" in ds["nodes"].dims:  # tensegrity simulate
        paper.fig_robot(ds["nodes"].values[-1], out, title=f"{ds.attrs.get('title', 'robot')} (end)")
        return "simulation: the robot at the end"
    raise ValueError(f"{path}: not a dataset this toolkit knows how to render")


def _render_nominal(ds, face: int, out, title: str) -> str:
    """Fig. 7 drawn from the nominal CoGs of `ds` (a nominal file or one face of the workspace):
    each pair's levels it stood at, a red ring at the tipping pressure (the nominal CoG
    interpolated there) and the deformed support there, dashed."""
    from .render import frame_plots
    rest_cog, rest_support = frames.rest_frame(face, datasets.strut_length(ds))
    levels = ds["pressure"].values
    lines, tips, tip_supports = {}, {}, {}
    for p in ds["pair"].values:
        cog = ds["cog"].sel(pair=p).values
        ok = np.isfinite(cog).all(axis=-1)
        n = int(np.argmin(ok)) if not ok.all() else len(ok)  # levels before a roll
        if n == 0:
            continue
        lines[int(p)] = np.vstack([rest_cog[None], cog[:n]])
        tp = float(ds["tip_pressure"].sel(pair=p)) if "tip_pressure" in ds else float("nan")
        if np.isfinite(tp) and tp <= levels[n - 1] + 1e-9:
            tips[int(p)] = frame_plots.at_pressure(levels[:n], cog[:n], tp)
            tip_supports[int(p)] = frame_plots.at_pressure(levels[:n], ds["support"].sel(pair=p).values[:n], tp)
    frame_plots.fig_workspace(lines, rest_support, out, title=title, tip_points=tips,
                        tip_supports=tip_supports, corner_labels=(topo.FACES[face - 1] + 1).tolist())
    return "workspace: nominal CoG per pair"


# --------------------------------------------------------------- locomotion figures
# (appended by the render split: Figs. 8-10, run paths and the animation. These read the run
# datasets, results/locomotion/{run}.nc; render.locomotion and render.runs draw from arrays.)

def _path_figure(ds: xr.Dataset, out, view: str) -> dict:
    """The path of the run dataset `ds` over its terrain, from above ("top") or "3d"."""
    from .render import runs as run_figures
    terrain = run_formats.terrain_from_dataset(ds)
    t = ds["time"].values
    if terrain.kind == "plane":
        slope = float(np.degrees(np.arccos(min(1.0, abs(float(np.asarray(terrain.normal)[2]))))))
        ground = f"a {slope:.3g} deg slope" if slope > 0.05 else "flat ground"
    else:
        ground = {"heightfield": "uneven terrain (height field)",
                  "none": "no ground"}.get(terrain.kind, f"{terrain.kind} ground")
    title = (f"Rolling run '{ds.attrs.get('run', '')}' on {ground}: "
             f"{ds.attrs['outcome']}, {int(ds.attrs['rolls'])} rolls "
             f"({'from above' if view == 'top' else '3D'})")
    return run_figures.fig_path(ds["nodes"].values, terrain, out, title,
                                faces=ds["next_face"].values,
                                step_end=np.clip(np.searchsorted(t, ds["t_end"].values), 0, len(t) - 1),
                                goal=ds["goal"].values, view=view)


def locomotion_states(paper_path: str | os.PathLike, slope_path: str | os.PathLike, fig8: str | os.PathLike,
                      fig9: str | os.PathLike, fig10: str | os.PathLike) -> list[dict]:
    """Stage `locomotion_states`: Fig. 8 and 9 from the paper run (its first roll: #10 on
    (9,10,12)) and Fig. 10 from a slope run (the robot at rest on the slope before its first
    roll). Returns what each figure drew (render.locomotion)."""
    from .physics import contact as ct
    from .render import locomotion as state_figures
    ds = datasets.read(paper_path)
    terrain = run_formats.terrain_from_dataset(ds)
    face = int(ds["face"].values[0])
    pair = int(ds["step_pair"].values[0, 0])
    tip = float(ds["tip_pressure"].values[0])
    edge = [topo.edge_nodes(face, j) for j in range(3)].index(tuple(ds["edge"].values[0]))
    k, p = run_formats.run_sample(ds, terrain, 1, "stable")
    out = [state_figures.fig_state(
        p, terrain, face, fig8,
        f"Fig. 8  Stable: #{pair} at {ds['pressure'].values[k].max():.1f} MPa, the CoG "
        f"projection stays inside {topo.face_label(face)}",
        arrow=ct.edge_outward(p[topo.FACES[face - 1]])[edge])]
    try:
        k, p = run_formats.run_sample(ds, terrain, 1, "rolling")
        title9 = (f"Fig. 9  Rolling: #{pair} tipped the robot at {tip:.2f} MPa; the CoG "
                  f"projection has left {topo.face_label(face)}")
    except ValueError:  # e.g. grounded sweeps: the planned pressure did not tip the robot
        k = int(np.clip(np.searchsorted(ds["time"].values, ds["t_end"].values[0]), 0,
                        ds.sizes["time"] - 1))
        p = ds["nodes"].values[k]
        title9 = (f"Fig. 9  Not rolling: #{pair} at up to {float(ds['peak_pressure'].values[0]):.2f} MPa "
                  f"did not tip the robot off {topo.face_label(face)} (run '{ds.attrs.get('run', '')}': "
                  f"{ds.attrs.get('outcome', '')})")
    out.append(state_figures.fig_state(p, terrain, face, fig9, title9))
    sl = datasets.read(slope_path)
    k0 = int(np.searchsorted(sl["time"].values, sl["t_start"].values[0]))
    out.append(state_figures.fig_slope(
        sl["nodes"].values[k0], run_formats.terrain_from_dataset(sl), int(sl["face"].values[0]), fig10,
        f"Fig. 10  Slope: the CoG projects along gravity onto the contact plane "
        f"('{sl.attrs['run']}' run)"))
    return out


def locomotion_paths(run_path: str | os.PathLike, top: str | os.PathLike,
                     three_d: str | os.PathLike) -> list[dict]:
    """Stage `locomotion_path`: the path of one run from above (`top`) and in 3D (`three_d`).
    Returns what each figure drew (render.runs.fig_path)."""
    ds = datasets.read(run_path)
    return [_path_figure(ds, top, "top"), _path_figure(ds, three_d, "3d")]


def locomotion_animation(run_path: str | os.PathLike, gif: str | os.PathLike, fps: int = 10,
                         speed: float = 8.0) -> dict:
    """Stage `locomotion_animation`: a GIF of one run at `fps` frames per second, `speed`
    times faster than simulated time. Returns {"path", "frames", "fps"}."""
    from .render import runs as run_figures
    ds = datasets.read(run_path)
    return run_figures.animate(ds["nodes"].values, ds["time"].values, ds["pressure"].values,
                               run_formats.terrain_from_dataset(ds), gif, goal=ds["goal"].values,
                               label=f"run '{ds.attrs.get('run', '')}'", fps=fps, speed=speed)
