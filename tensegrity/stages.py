"""The workflow's stages as functions from files to files (design.md section 5).

Each reads its inputs, calls the pure modules (sweep, nominal, fit, mapping, render) and writes
its outputs with `datasets.write`. The Snakemake scripts and the command line call these.
`cfg` holds the configuration sections a stage depends on; it is stored, merged with the
inputs' own, as each output's provenance.
"""
from __future__ import annotations

import contextlib
import json
from pathlib import Path

import numpy as np
import xarray as xr

from .io import datasets
from .physics import frames, topology as topo
from .workspace import mapping
from .workspace import nominal as nom
from .io.config import params_from_config

AXES = ["x", "y", "z"]
CONTACTS = list(topo.CONTACT_FACES)


@contextlib.contextmanager
def logging_to(path, threads: int | None = None):
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


def _coords(pairs=None, levels=None):
    c = {"axis": ("axis", AXES, {"long_name": "support-frame axis"}),
         "corner": ("corner", [1, 2, 3], {"units": "1", "long_name": "support triangle corner"}),
         "node": ("node", np.arange(1, 13), {"units": "1", "long_name": "node number"})}
    if pairs is not None:
        c["pair"] = ("pair", np.asarray(pairs), {"units": "1", "long_name": "actuator pair number"})
    if levels is not None:
        c["pressure"] = ("pressure", np.asarray(levels, float), {"units": "MPa", "long_name": "muscle pressure"})
    return c


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


def run_sweep(cfg: dict, contact: str, out_dir) -> list[Path]:
    """Sweep every configured pair on the contact face; write `out_dir`/pairNN.nc."""
    from .workspace import sweep as sw  # the simulator (numba) only where it runs
    if contact not in topo.CONTACT_FACES:
        raise ValueError(f"unknown contact {contact!r}: use one of {CONTACTS}")
    s, sim = cfg["sweep"], cfg["sim"]
    res = sw.run(params_from_config(cfg), topo.CONTACT_FACES[contact], s["pairs"], s["levels"],
                 s["hold"], s["settle"], s["mode"], sim["dt"], sim["record_every"])
    stride = int(s["node_stride"])
    paths = []
    for b, pair in enumerate(res.pairs):
        ds = xr.Dataset(
            {"cog": datasets.var(("time", "axis"), res.cog[b], "m", "centre of gravity in the support frame"),
             "support": datasets.var(("time", "corner", "axis"), res.support[b], "m",
                             "deformed support triangle in the support frame"),
             "pressure_cmd": datasets.var(("time",), res.pressure_cmd[b], "MPa", f"pressure commanded to pair #{pair}"),
             "level": datasets.var(("time",), res.level, "1", "index of the pressure level held (-1: settling)"),
             "on_face": datasets.var(("time",), res.on_face[b].astype(np.int8), "1",
                             "1 while the contact face's three nodes touch the ground (always 1 in the free mode)"),
             "nodes": datasets.var(("time_nodes", "node", "axis"), res.nodes[b, ::stride], "m",
                           "node positions, world frame (every node_stride-th sample)")},
            coords={**_coords(), "time": ("time", res.t, {"units": "s", "long_name": "time"}),
                    "time_nodes": ("time_nodes", res.t[::stride], {"units": "s", "long_name": "time of node samples"}),
                    "levels": ("levels", res.levels, {"units": "MPa", "long_name": "pressure levels of the staircase"})},
            attrs={"contact": contact, "face": res.face, "face_nodes": topo.FACES[res.face - 1] + 1,
                   "pair": int(pair), "mode": s["mode"], "hold_s": float(s["hold"]), "settle_s": float(s["settle"])})
        ds["axis"].attrs["units"] = "1"
        paths.append(datasets.write(ds, Path(out_dir) / f"pair{pair:02d}.nc", cfg,
                                    f"Pressure sweep of pair #{pair} standing on {topo.face_label(res.face)}",
                                    stage="sweep"))
    return paths


def run_nominal(cfg: dict, sweep_paths, out_path) -> Path:
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
        if k < len(levels):
            rolled[i, k:] = 1
            cog[i, k:], std[i, k:], sup[i, k:], margin[i, k:] = np.nan, np.nan, np.nan, np.nan
            tip[i] = levels[k] if not tip[i] <= levels[k] else tip[i]
    ds = xr.Dataset(
        {"cog": datasets.var(("pair", "pressure", "axis"), cog, "m", "nominal centre of gravity in the support frame"),
         "cog_std": datasets.var(("pair", "pressure", "axis"), std, "m", "standard deviation of the CoG over the level (oscillation)"),
         "support": datasets.var(("pair", "pressure", "corner", "axis"), sup, "m", "mean deformed support triangle in the support frame"),
         "margin": datasets.var(("pair", "pressure"), margin, "m", "signed distance of the CoG projection to the support triangle boundary (positive inside)"),
         "tip_pressure": datasets.var(("pair",), tip, "MPa", "least pressure at which the CoG projection leaves the triangle (NaN: never)"),
         "rolled": datasets.var(("pair", "pressure"), rolled, "1", "1 from the level at which the grounded robot rolled off the face (always 0 in the free mode)")},
        coords=_coords(pairs, levels),
        attrs={k: first.attrs[k] for k in ("contact", "face", "face_nodes", "mode")} | {"discard_s": discard})
    ds["axis"].attrs["units"] = "1"
    return datasets.write(ds, out_path, _provenance(cfg, *sweep_paths),
                          f"Nominal CoG of the {first.attrs['contact']} contact case {topo.face_label(int(first.attrs['face']))}",
                          stage="nominal", allow_nan=["tip_pressure", "cog", "cog_std", "support", "margin"])


def run_fit(cfg: dict, nominal_path, out_path) -> Path:
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
    units = {"breaks": "MPa", "coefs": "m MPa-power", "degree": "1", "pmin": "MPa", "pmax": "MPa",
             "cv_rmse": "m", "kind": "", "model": ""}
    names = {"breaks": "piece boundaries of the piecewise polynomial (NaN padded)",
             "coefs": "coefficients in u = p - breaks[piece], highest power first (NaN padded)",
             "degree": "polynomial degree", "pmin": "lowest pressure of the valid range",
             "pmax": "highest pressure of the valid range", "cv_rmse": "cross-validated RMSE of the fit",
             "kind": "polynomial or spline", "model": "chosen model"}
    data = {}
    for k, a in arr.items():
        attrs = {"long_name": names[k]}
        if units[k]:
            attrs["units"] = units[k]
        data[k] = (fit.ARRAY_DIMS[k], a, attrs)
    ds = xr.Dataset(data, coords={"pair": src["pair"], "axis": src["axis"]},
                    attrs={k: src.attrs[k] for k in ("contact", "face", "face_nodes", "mode")})
    return datasets.write(ds, out_path, _provenance(cfg, nominal_path),
                          f"Fitted CoG curves of the {src.attrs['contact']} contact case",
                          stage="fit", allow_nan=["breaks", "coefs", "cv_rmse"])


def curves_json(curve_paths, out_path) -> Path:
    """All contact cases' curves as one JSON file (plain numbers, evaluable in any language)."""
    from .workspace import fit
    doc = {"units": {"pressure": "MPa", "cog": "m"},
           "evaluate": "find piece i with breaks[i] <= p < breaks[i+1] (clamp to the end pieces); "
                       "value = sum(coefs[i][k] * (p - breaks[i])**(deg - k))",
           "contacts": {}}
    for path in curve_paths:
        ds = datasets.read(path)
        curves = fit.arrays_to_curves({k: ds[k].values for k in fit.ARRAY_DIMS})
        doc["contacts"][ds.attrs["contact"]] = {
            "face_nodes": [int(n) for n in ds.attrs["face_nodes"]],
            "pairs": {str(int(p)): {ax: fit.to_dict(curves[i][j]) for j, ax in enumerate(AXES)}
                      for i, p in enumerate(ds["pair"].values)}}
    return datasets.write_text(out_path, json.dumps(doc, indent=1, sort_keys=True, allow_nan=False))


def run_map(cfg: dict, nominal_paths, out_path) -> Path:
    """Map the canonical nominal workspaces to all 20 faces."""
    src = {ds.attrs["contact"]: ds for ds in (datasets.read(p) for p in nominal_paths)}
    levels = next(iter(src.values()))["pressure"].values
    P = len(levels)
    cog = np.full((20, 12, P, 3), np.nan)
    sup = np.full((20, 12, P, 3, 3), np.nan)
    for face in range(1, 21):
        ds = src.get(str(topo.FACE_TYPES[face - 1]))
        if ds is None:
            continue
        if not np.array_equal(ds["pressure"].values, levels):
            raise ValueError("the contact cases were swept at different pressure levels")
        full_c, full_s = np.full((12, P, 3), np.nan), np.full((12, P, 3, 3), np.nan)
        idx = ds["pair"].values - 1
        full_c[idx], full_s[idx] = ds["cog"].values, ds["support"].values
        cog[face - 1], sup[face - 1] = mapping.map_face(face, full_c, full_s)
    margin = np.full((20, 12, P), np.nan)
    ok = np.isfinite(cog[..., 0])
    margin[ok] = frames.margin_2d(cog[ok][:, :2], sup[ok][:, :, :2])
    tip = np.array([[frames.first_crossing(levels, m)[0] if np.isfinite(m).all() else np.nan for m in mf] for mf in margin])
    ds = xr.Dataset(
        {"cog": datasets.var(("face", "pair", "pressure", "axis"), cog, "m", "nominal centre of gravity in the face's support frame"),
         "support": datasets.var(("face", "pair", "pressure", "corner", "axis"), sup, "m", "deformed support triangle in the face's support frame"),
         "margin": datasets.var(("face", "pair", "pressure"), margin, "m", "signed distance of the CoG projection to the support triangle boundary (positive inside)"),
         "tip_pressure": datasets.var(("face", "pair"), tip, "MPa", "least pressure at which the CoG projection leaves the triangle (NaN: never or not computed)"),
         "face_nodes": datasets.var(("face", "corner"), topo.FACES + 1, "1", "node numbers of the face's corners (support-frame corner order)"),
         "face_type": (("face",), topo.FACE_TYPES.astype(str), {"long_name": "equilateral (3 cables) or isosceles (2 cables and a gap)"}),
         "reference_corner": datasets.var(("face",), topo.FACE_REFERENCE + 1, "1", "corner of the reference vertex (the support frame's +y)")},
        coords={**_coords(np.arange(1, 13), levels),
                "face": ("face", np.arange(1, 21), {"units": "1", "long_name": "face number"})})
    ds["axis"].attrs["units"] = "1"
    return datasets.write(ds, out_path, _provenance(cfg, *nominal_paths),
                          "Kinematic workspace of all 20 contact faces, mapped by symmetry",
                          stage="map", allow_nan=["cog", "support", "margin", "tip_pressure"])


def render_robot(cfg: dict, fig1, fig4, fig5) -> None:
    """Figs. 1, 4 and 5: the robot, its actuator pairs, and the support frame of (9,10,12)."""
    from .physics import dynamics as d
    from .render import scene as render
    from .physics.terrain import Terrain
    params = params_from_config(cfg)
    nodes = topo.reference_nodes(params.strut_length)
    render.fig_robot(nodes, fig1)
    render.fig_robot(nodes, fig4, highlight_pairs=[4, 6, 7, 9, 10, 12])
    state = d.stand_on(params, topo.CONTACT_FACES["equilateral"], Terrain.flat())
    render.fig_support_frame(d.nodes(state.x, state.q, params.strut_length)[0],
                             topo.CONTACT_FACES["equilateral"], fig5)


def render_cloud(sweep_path, nominal_path, out, max_pressure: float = 2.4) -> None:
    """Fig. 6: the CoG point cloud and nominal CoGs of one pair, levels up to max_pressure."""
    from .render import scene as render
    sw_ds, nm = datasets.read(sweep_path), datasets.read(nominal_path)
    pair, face = int(sw_ds.attrs["pair"]), int(sw_ds.attrs["face"])
    levels = nm["pressure"].values
    keep = levels <= max_pressure + 1e-9
    sel = (sw_ds["level"].values >= 0) & (sw_ds["level"].values < keep.sum())
    nom = nm["cog"].sel(pair=pair).values[keep]
    render.fig_cog_cloud(sw_ds["cog"].values[sel], nom, levels[keep], frames.rest_frame(face, datasets.strut_length(nm))[1], out,
                         pair=pair, face_label=topo.face_label(face),
                         sample_pressure=sw_ds["pressure_cmd"].values[sel],
                         corner_labels=(topo.FACES[face - 1] + 1).tolist())


def render_workspace(curves_path, nominal_path, out, points: int = 60) -> None:
    """Fig. 7: every pair's fitted CoG curve from 0 MPa to the highest level, with the support
    triangle of the unactuated robot and where each curve leaves the deformed triangle."""
    from .workspace import fit
    from .render import scene as render
    cv, nm = datasets.read(curves_path), datasets.read(nominal_path)
    face = int(nm.attrs["face"])
    rest_cog, rest_tri = frames.rest_frame(face, datasets.strut_length(nm))
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
    render.fig_workspace(lines, rest_tri, out, tip_points=tips,
                         title=f"Fig. 7  Kinematic workspace, {nm.attrs['contact']} face "
                               f"{topo.face_label(face)}, {levels[0]:g}-{levels[-1]:g} MPa",
                         corner_labels=(topo.FACES[face - 1] + 1).tolist())


def render_dataset(path, out, face: int | None = None) -> str:
    """Render any dataset of the toolkit to a PNG: a sweep (its CoG cloud), a nominal file or
    the workspace (the workspace of its face, or of `face`), a locomotion run (its path from
    above), a `tensegrity simulate` output (the robot at the end). Returns what was drawn."""
    from .render import scene as render
    ds = datasets.read(path)
    if "level" in ds and "pair" in ds.attrs:  # a sweep
        face_ = int(ds.attrs["face"])
        sel = ds["level"].values >= 0
        levels = ds["levels"].values
        nom = np.array([ds["cog"].values[ds["level"].values == k].mean(0) for k in range(levels.size)])
        render.fig_cog_cloud(ds["cog"].values[sel], nom, levels, frames.rest_frame(face_, datasets.strut_length(ds))[1], out,
                             pair=int(ds.attrs["pair"]), face_label=topo.face_label(face_),
                             sample_pressure=ds["pressure_cmd"].values[sel],
                             corner_labels=(topo.FACES[face_ - 1] + 1).tolist())
        return "sweep: CoG cloud and level means"
    if "margin" in ds and "face" in ds.dims:  # the workspace
        face_ = topo.face_number(face) if face is not None else 8
        sub = ds.sel(face=face_)
        title = f"Workspace of face {face_} {topo.face_label(face_)} (nominal CoG, mapped)"
        return _render_nominal(render, sub, face_, out, title)
    if "margin" in ds and "pair" in ds.dims:  # a nominal file
        face_ = int(ds.attrs["face"])
        return _render_nominal(render, ds, face_, out, f"Nominal CoG, face {topo.face_label(face_)}")
    if "face_sequence" in ds or "step" in ds.dims:  # a locomotion run
        from .render import locomotion as render_locomotion
        render_locomotion.fig_path(ds, out, "top")
        return "locomotion run: path from above"
    if "nodes" in ds and "time" in ds["nodes"].dims:  # tensegrity simulate
        render.fig_robot(ds["nodes"].values[-1], out, title=f"{ds.attrs.get('title', 'robot')} (end)")
        return "simulation: the robot at the end"
    raise ValueError(f"{path}: not a dataset this toolkit knows how to render")


def _render_nominal(render, ds, face: int, out, title: str) -> str:
    rest_cog, rest_tri = frames.rest_frame(face, datasets.strut_length(ds))
    lines = {int(p): np.vstack([rest_cog[None], ds["cog"].sel(pair=p).values])
             for p in ds["pair"].values if np.isfinite(ds["cog"].sel(pair=p).values).all()}
    render.fig_workspace(lines, rest_tri, out, title=title, corner_labels=(topo.FACES[face - 1] + 1).tolist())
    return "workspace: nominal CoG per pair"
