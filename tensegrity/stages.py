"""The workflow's stages as functions from files to files (design.md section 5).

Each reads its inputs, calls the pure modules (sweep, nominal, fit, mapping, render) and writes
its outputs with `datasets.write`. The Snakemake scripts and the command line call these.
`cfg` holds the configuration sections a stage depends on; it is stored, merged with the
inputs' own, as each output's provenance.
"""
from __future__ import annotations

import contextlib
import json
import os
from collections.abc import Iterable, Iterator, Sequence
from pathlib import Path

import numpy as np
import xarray as xr

from .io import datasets, formats
from .physics import frames, topology as topo
from .workspace import mapping
from .workspace import nominal as nom
from .io.config import params_from_config

CONTACTS = list(topo.CONTACT_FACES)


@contextlib.contextmanager
def logging_to(path: str | os.PathLike, threads: int | None = None) -> Iterator[None]:
    """Send stdout and stderr (and a traceback on failure) to the log file `path`; use
    `threads` compute threads."""
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    if threads:
        import numba
        numba.set_num_threads(max(1, min(int(threads), numba.config.NUMBA_NUM_THREADS)))
    with open(path, "w") as log, contextlib.redirect_stdout(log), contextlib.redirect_stderr(log):
        try:
            yield
        except BaseException:
            import traceback
            traceback.print_exc(file=log)
            raise


# The configuration sections each stage depends on: the Snakemake rules pass exactly these as
# `params: cfg=...` (so that editing another section re-runs nothing) and `tensegrity stage`
# stores the same, so a file's provenance does not depend on how it was made.
STAGE_CONFIG: dict[str, tuple[str, ...]] = {
    "sweep": ("params", "sim", "sweep"),
    "nominal": ("nominal",),
    "fit": ("fit",),
    "map": (),
    "render_robot": ("params",),
    "validate": ("params", "sim", "sweep", "nominal", "validate"),
    "locomotion_run": ("params", "sim", "locomotion"),
}


def stage_config(cfg: dict, stage: str) -> dict:
    """The sections of the resolved configuration `cfg` that `stage` depends on (STAGE_CONFIG);
    a locomotion run leaves out the list of runs and the animation settings."""
    if stage not in STAGE_CONFIG:
        raise ValueError(f"unknown stage {stage!r}: use one of {sorted(STAGE_CONFIG)}")
    out = {k: cfg[k] for k in STAGE_CONFIG[stage]}
    if stage == "locomotion_run":
        out["locomotion"] = {k: v for k, v in out["locomotion"].items()
                             if k != "runs" and not k.startswith("animation_")}
    return out


def _provenance(cfg: dict, *inputs) -> dict:
    """cfg merged over the provenance of the input files (inputs win nothing: cfg is newer)."""
    out = {}
    for path in inputs:
        out.update(datasets.provenance_config(path))
    out.update(cfg)
    return out


def run_sweep(cfg: dict, contact: str, out_dir: str | os.PathLike) -> list[Path]:
    """Sweep every configured pair on the contact face; write `out_dir`/pairNN.nc."""
    from .workspace import sweep as sw  # the simulator (numba) only where it runs
    if contact not in topo.CONTACT_FACES:
        raise ValueError(f"unknown contact {contact!r}: use one of {CONTACTS}")
    s, sim = cfg["sweep"], cfg["sim"]
    res = sw.run(params_from_config(cfg), topo.CONTACT_FACES[contact], s["pairs"], s["levels"],
                 s["hold"], s["settle"], s["mode"], sim["dt"], sim["record_every"])
    paths = []
    for b, pair in enumerate(res.pairs):
        ds = formats.sweep_dataset(res, b, contact, s)
        paths.append(datasets.write(ds, Path(out_dir) / formats.SWEEP_FILE.format(pair=int(pair)), cfg,
                                    f"Pressure sweep of pair #{pair} standing on {topo.face_label(res.face)}",
                                    stage="sweep"))
    return paths


def run_nominal(cfg: dict, sweep_paths: Sequence[str | os.PathLike], out_path: str | os.PathLike) -> Path:
    """Average every sweep file's levels into the nominal CoG dataset of one contact case."""
    sweeps = [datasets.read(p) for p in sweep_paths]
    sweeps.sort(key=lambda ds: ds.attrs["pair"])
    first = sweeps[0]
    levels = first["levels"].values
    hold, discard = first.attrs["hold_s"], float(cfg["nominal"]["discard"])
    res = [nom.nominal(ds["time"].values, ds["level"].values, ds["cog"].values,
                       ds["support"].values, len(levels), hold, discard) for ds in sweeps]
    cog, std, sup, margin = (np.stack([r[k] for r in res]) for k in range(4))
    pairs = [int(ds.attrs["pair"]) for ds in sweeps]
    tip = np.array([frames.first_crossing(levels, m)[0] for m in margin])
    # grounded mode: from the level the robot rolled off its face on, the numbers are not of
    # this face any more; they become NaN and the roll counts as the tip
    rolled = np.zeros(margin.shape, np.int8)
    for i, ds in enumerate(sweeps):
        k = nom.first_roll(ds["level"].values, ds["on_face"].values, len(levels))
        rolled[i, k:] = 1
        tip[i] = nom.mask_after_roll(levels, k, tip[i], cog[i], std[i], sup[i], margin[i])
    ds = formats.nominal_dataset(pairs, levels, cog, std, sup, margin, tip, rolled,
                                 {k: first.attrs[k] for k in ("contact", "face", "face_nodes", "mode")}
                                 | {"discard_s": discard})
    return datasets.write(ds, out_path, _provenance(cfg, *sweep_paths),
                          f"Nominal CoG of the {first.attrs['contact']} contact case {topo.face_label(int(first.attrs['face']))}",
                          stage="nominal", allow_nan=formats.NOMINAL_ALLOW_NAN)


def run_fit(cfg: dict, nominal_path: str | os.PathLike, out_path: str | os.PathLike) -> Path:
    """Fit a curve per pair and axis to the nominal CoG; write the plain-number curves."""
    from .workspace import fit  # scikit-learn is slow to import: only this stage needs it
    src = datasets.read(nominal_path)
    f = cfg["fit"]
    p, cog = src["pressure"].values, src["cog"].values
    ok = np.isfinite(cog).all(axis=-1)  # levels before a grounded robot rolled off its face
    for i, pair in enumerate(src["pair"].values):
        if ok[i].sum() < 2:
            raise ValueError(f"pair #{pair} on {topo.face_label(int(src.attrs['face']))} stood at fewer than 2 "
                             f"levels (it rolled off at {float(src['tip_pressure'][i]):g} MPa): nothing to fit; "
                             "sweep lower pressures or use the free mode")
    curves = [[fit.fit_curve(p[ok[i]], cog[i, ok[i], a], max_degree=f["max_degree"],
                             spline_knots=tuple(f["spline_knots"]), folds=f["folds"])
               for a in range(3)] for i in range(cog.shape[0])]
    arr = fit.curves_to_arrays(curves)
    ds = formats.curves_dataset(arr, src["pair"], src["axis"],
                                {k: src.attrs[k] for k in ("contact", "face", "face_nodes", "mode")})
    return datasets.write(ds, out_path, _provenance(cfg, nominal_path),
                          f"Fitted CoG curves of the {src.attrs['contact']} contact case",
                          stage="fit", allow_nan=formats.CURVES_ALLOW_NAN)


def curves_json(curve_paths: Iterable[str | os.PathLike], out_path: str | os.PathLike) -> Path:
    """All contact cases' curves as one JSON file (plain numbers, evaluable in any language)."""
    from .workspace import fit
    contacts = {}
    for path in curve_paths:
        ds = datasets.read(path)
        contacts[ds.attrs["contact"]] = (ds.attrs["face_nodes"], ds["pair"].values,
                                         fit.arrays_to_curves({k: ds[k].values for k in fit.ARRAY_DIMS}))
    doc = formats.curves_document(contacts)
    return datasets.write_text(out_path, json.dumps(doc, indent=1, sort_keys=True, allow_nan=False))


def run_map(cfg: dict, nominal_paths: Sequence[str | os.PathLike], out_path: str | os.PathLike) -> Path:
    """Map the canonical nominal workspaces to all 20 faces."""
    src = {ds.attrs["contact"]: ds for ds in (datasets.read(p) for p in nominal_paths)}
    levels = mapping.same_levels([ds["pressure"].values for ds in src.values()])
    ws = mapping.map_workspace(levels, {c: (ds["pair"].values, ds["cog"].values, ds["support"].values)
                                        for c, ds in src.items()})
    ds = formats.workspace_dataset(levels, ws)
    return datasets.write(ds, out_path, _provenance(cfg, *nominal_paths),
                          "Kinematic workspace of all 20 contact faces, mapped by symmetry",
                          stage="map", allow_nan=formats.WORKSPACE_ALLOW_NAN)


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
    (MPa). Returns what the figure drew (render.paper.fig_cog_cloud)."""
    from .render import paper
    sw_ds, nm = datasets.read(sweep_path), datasets.read(nominal_path)
    pair, face = int(sw_ds.attrs["pair"]), int(sw_ds.attrs["face"])
    levels = nm["pressure"].values
    keep = levels <= max_pressure + 1e-9
    sel = (sw_ds["level"].values >= 0) & (sw_ds["level"].values < keep.sum())
    nom = nm["cog"].sel(pair=pair).values[keep]
    return paper.fig_cog_cloud(sw_ds["cog"].values[sel], nom, levels[keep],
                               frames.rest_frame(face, datasets.strut_length(nm))[1], out,
                               pair=pair, face_label=topo.face_label(face),
                               sample_pressure=sw_ds["pressure_cmd"].values[sel],
                               corner_labels=(topo.FACES[face - 1] + 1).tolist())


def render_workspace(curves_path: str | os.PathLike, nominal_path: str | os.PathLike, out: str | os.PathLike,
                     points: int = 60) -> dict:
    """Fig. 7: every pair's fitted CoG curve from 0 MPa to the highest level, with the support
    triangle of the unactuated robot and where each curve leaves the deformed triangle.
    Returns what the figure drew (render.paper.fig_workspace)."""
    from .workspace import fit
    from .render import paper
    cv, nm = datasets.read(curves_path), datasets.read(nominal_path)
    face = int(nm.attrs["face"])
    rest_cog, rest_support = frames.rest_frame(face, datasets.strut_length(nm))
    curves = fit.arrays_to_curves({k: cv[k].values for k in fit.ARRAY_DIMS})
    lines, tips = {}, {}
    for i, pair in enumerate(cv["pair"].values):
        c = curves[i]
        p = np.linspace(c[0].pmin, c[0].pmax, points)
        xyz = np.stack([fit.evaluate(c[a], p) for a in range(3)], axis=-1)
        lines[int(pair)] = np.vstack([rest_cog[None], xyz])
        tp = float(nm["tip_pressure"].sel(pair=pair))
        tips[int(pair)] = (np.array([float(fit.evaluate(c[a], tp)) for a in range(3)])
                           if np.isfinite(tp) else None)
    levels = nm["pressure"].values
    return paper.fig_workspace(lines, rest_support, out, tip_points=tips,
                               title=f"Fig. 7  Kinematic workspace, {nm.attrs['contact']} face "
                                     f"{topo.face_label(face)}, {levels[0]:g}-{levels[-1]:g} MPa",
                               corner_labels=(topo.FACES[face - 1] + 1).tolist())


def render_dataset(path: str | os.PathLike, out: str | os.PathLike, face: int | None = None) -> str:
    """Render any dataset of the toolkit to a PNG: a sweep (its CoG cloud), a nominal file or
    the workspace (the workspace of its face, or of `face`), a locomotion run (its path from
    above), a `tensegrity simulate` output (the robot at the end). Returns what was drawn."""
    from .render import paper
    ds = datasets.read(path)
    if "level" in ds and "pair" in ds.attrs:  # a sweep
        face_ = int(ds.attrs["face"])
        sel = ds["level"].values >= 0
        levels = ds["levels"].values
        nom = np.array([ds["cog"].values[ds["level"].values == k].mean(0) for k in range(levels.size)])
        paper.fig_cog_cloud(ds["cog"].values[sel], nom, levels,
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
    """Fig. 7 drawn from the nominal CoGs of `ds` (a nominal file or one face of the workspace)."""
    from .render import paper
    rest_cog, rest_support = frames.rest_frame(face, datasets.strut_length(ds))
    lines = {int(p): np.vstack([rest_cog[None], ds["cog"].sel(pair=p).values])
             for p in ds["pair"].values if np.isfinite(ds["cog"].sel(pair=p).values).all()}
    paper.fig_workspace(lines, rest_support, out, title=title,
                        corner_labels=(topo.FACES[face - 1] + 1).tolist())
    return "workspace: nominal CoG per pair"


# ----- locomotion stages
# (appended by the locomotion split; everything above belongs to the stages module's owner)

def locomotion_run(cfg: dict, name: str, workspace_path: str | Path, out_path: str | Path) -> Path:
    """Stage `locomotion_run`: the demonstration run `name` (one of locomotion.DEMOS), planned
    from the workspace file (results/workspace.nc) and rolled in the grounded simulation.
    Writes the run dataset (results/locomotion/{run}.nc, `io.formats.run_dataset`) to
    `out_path` and returns its path; prints the steps and the outcome. `cfg`: the sections of
    STAGE_CONFIG["locomotion_run"], merged over the workspace file's provenance."""
    from .io import formats
    from .locomotion import demos, runs
    from .locomotion.control import RollSettings
    src = datasets.read(workspace_path)  # read once: the workspace and its provenance
    ws = formats.workspace_from_dataset(src)
    setup = demos.demo_setup(cfg, name)
    params = demos.locomotion_params(cfg)
    s = RollSettings.from_config(cfg["locomotion"], cfg["sim"]["dt"])
    if "edges" in setup:
        run = runs.roll_over(ws, setup["edges"], params, setup["terrain"], settings=s)
    else:
        run = runs.roll_to(ws, setup["goal"], params, setup["terrain"], settings=s)
    print(runs.describe(run, name))
    return datasets.write(formats.run_dataset(run, setup["terrain"], name), out_path,
                          {**datasets.provenance_config(src), **cfg},
                          f"Rolling locomotion run '{name}': {run.outcome}",
                          stage="locomotion", allow_nan=formats.RUN_ALLOW_NAN)


# ----- locomotion figure stages
# (appended by the render split: Figs. 8-10, run paths and the animation. These read the run
# datasets, results/locomotion/{run}.nc; render.locomotion and render.runs draw from arrays.)

def _path_figure(ds: xr.Dataset, out, view: str) -> dict:
    """The path of the run dataset `ds` over its terrain, from above ("top") or "3d"."""
    from .render import runs as run_figures
    terrain = formats.terrain_from_dataset(ds)
    t = ds["time"].values
    title = (f"Rolling run '{ds.attrs.get('run', '')}' on {terrain.kind} ground: "
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
    terrain = formats.terrain_from_dataset(ds)
    face = int(ds["face"].values[0])
    pair = int(ds["step_pair"].values[0, 0])
    tip = float(ds["tip_pressure"].values[0])
    edge = [topo.edge_nodes(face, j) for j in range(3)].index(tuple(ds["edge"].values[0]))
    k, p = formats.run_sample(ds, terrain, 1, "stable")
    out = [state_figures.fig_state(
        p, terrain, face, fig8,
        f"Fig. 8  Stable: #{pair} at {ds['pressure'].values[k].max():.1f} MPa, the CoG "
        f"projection stays inside {topo.face_label(face)}",
        arrow=ct.edge_outward(p[topo.FACES[face - 1]])[edge])]
    k, p = formats.run_sample(ds, terrain, 1, "rolling")
    out.append(state_figures.fig_state(
        p, terrain, face, fig9,
        f"Fig. 9  Rolling: #{pair} tipped the robot at {tip:.2f} MPa; the CoG "
        f"projection has left {topo.face_label(face)}"))
    sl = datasets.read(slope_path)
    k0 = int(np.searchsorted(sl["time"].values, sl["t_start"].values[0]))
    out.append(state_figures.fig_slope(
        sl["nodes"].values[k0], formats.terrain_from_dataset(sl), int(sl["face"].values[0]), fig10,
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
                               formats.terrain_from_dataset(ds), gif, goal=ds["goal"].values,
                               label=f"run '{ds.attrs.get('run', '')}'", fps=fps, speed=speed)
