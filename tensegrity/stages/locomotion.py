"""Rules `locomotion_runs` and `locomotion_figures` (workflow/rules/locomotion.smk): the
demonstration runs planned from the workspace and rolled in the grounded simulation
(results/locomotion/{run}.nc), then Figs. 8-10, the runs' paths and an animation."""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import xarray as xr

from ..io import datasets, formats, settings
from ..io.formats import run as run_formats
from ..locomotion.demos import Scenarios
from ..locomotion.settings import RollSettings
from ..physics import topology as topo
from ..physics.terrain import Terrain
from . import provenance


def locomotion_runs(
    cfg: dict,
    names: Sequence[str],
    workspace_path: str | os.PathLike,
    out_paths: Sequence[str | os.PathLike],
    two_pair_path: str | os.PathLike | None = None,
) -> list[Path]:
    """Stage `locomotion_runs`: each demonstration run of `names` (locomotion.DEMOS), planned from
    the workspace file (results/workspace.nc) and, if given, the measured two-pair curves of
    results/workspace_two_pair.nc (without it two pairs are superposed), rolled in the grounded
    simulation, written to the matching `out_paths` (results/locomotion/{run}.nc). One job: the
    workspace is read once and the simulator started once."""
    from ..locomotion import demos, outcome, runs

    if len(names) != len(out_paths):
        raise ValueError(f"{len(names)} runs {list(names)} but {len(out_paths)} output paths")
    from .config import actuator_kind

    for path in (workspace_path, two_pair_path):  # levels in the configured actuator's unit
        if path is not None:
            formats.actuation.require_kind(datasets.read_attrs(path), os.fspath(path), actuator_kind(cfg))
    ws = formats.read_workspace(workspace_path, two_pair_path)
    scen = settings.build(Scenarios, cfg)
    setups = [demos.demo_setup(name, scen) for name in names]  # an unknown name: before any run
    params, s = settings.params(cfg), settings.build(RollSettings, cfg)
    prov = provenance(cfg, workspace_path)  # the same for every run
    out = []
    for name, setup, out_path in zip(names, setups, out_paths):
        if "edges" in setup:
            run = runs.roll_over(ws, setup["edges"], params, setup["terrain"], settings=s)
        else:
            run = runs.roll_to(ws, setup["goal"], params, setup["terrain"], settings=s)
        print(outcome.describe(run, name, s.unit), flush=True)
        out.append(
            datasets.write(
                run_formats.run_dataset(run, setup["terrain"], s.rolling(params), name, s.unit),
                out_path,
                prov,
                f"Rolling locomotion run '{name}': {run.outcome}",
                stage="locomotion",
                allow_nan=run_formats.RUN_ALLOW_NAN,
            )
        )
    return out


def _path_figure(ds, out: str | os.PathLike, view: str) -> dict:
    """The path of the run dataset `ds` over its terrain, from above ("top") or "3d"."""
    from ..render import runs as run_figures

    terrain = run_formats.terrain_from_dataset(ds)
    t = ds["time"].values
    title = (
        f"Rolling run '{ds.attrs.get('run', '')}' on {terrain.describe()}: "
        f"{ds.attrs['outcome']}, {int(ds.attrs['rolls'])} rolls "
        f"({'from above' if view == 'top' else '3D'})"
    )
    return run_figures.fig_path(
        ds["nodes"].values,
        terrain,
        out,
        title,
        faces=ds["next_face"].values,
        step_end=np.clip(np.searchsorted(t, ds["t_end"].values), 0, len(t) - 1),
        goal=ds["goal"].values,
        view=view,
    )


def _no_roll(ds: xr.Dataset, path: str | os.PathLike, figures: str) -> tuple[int, str]:
    """The face a run that recorded no step rests on (its start face) and why it made no roll
    (its outcome, then on a second line of a title its message, its start and end if long);
    ValueError naming the run file if it rests on no face (nothing to draw the figures on)."""
    faces = ds["faces"].values if "faces" in ds else np.zeros(0, np.int64)
    if not len(faces):
        raise ValueError(
            f"{figures} draw the robot on a face, but the run {os.fspath(path)!r} made no roll and rests "
            f"on no face (outcome {ds.attrs.get('outcome', '?')!r}: {ds.attrs.get('message', '')})"
        )
    msg = str(ds.attrs.get("message", ""))
    if len(msg) > 120:  # its start and its end (the counts of the verdicts), whole words
        msg = msg[:50].rsplit(" ", 1)[0] + " ... " + msg[-65:].split(" ", 1)[-1]
    return int(faces[0]), f"run '{ds.attrs.get('run', '')}' made no roll: {ds.attrs.get('outcome', '?')}\n({msg})"


def state_figures(
    cfg: dict,
    paper_path: str | os.PathLike,
    slope_path: str | os.PathLike,
    fig8: str | os.PathLike,
    fig9: str | os.PathLike,
    fig10: str | os.PathLike,
) -> list[dict]:
    """Stage `state_figures`: Fig. 8 and 9 from the paper run (its first roll: #10 on (9,10,12))
    and Fig. 10 from a slope run (the robot at rest on the slope before its first roll). A run
    that made no roll (e.g. stuck: no roll simulated ahead was acceptable) gives its robot at rest
    on its start face, its last sample, the titles saying it made no roll and why (a figure per
    output, as the workflow expects; ValueError naming the file if it rests on no face).
    Returns what each figure drew (render.locomotion)."""
    from ..render import locomotion as state_figures_

    ds = datasets.read(paper_path)
    terrain = run_formats.terrain_from_dataset(ds)
    if ds.sizes.get("step", 0) == 0:
        face, why = _no_roll(ds, paper_path, "Fig. 8 and 9")
        p = ds["nodes"].values[-1]
        out = [
            state_figures_.fig_state(
                p, terrain, face, fig, f"Fig. {n}  Not rolled: at rest on {topo.face_label(face)}, {why}"
            )
            for n, fig in ((8, fig8), (9, fig9))
        ]
    else:
        out = _paper_states(ds, terrain, fig8, fig9)
    sl = datasets.read(slope_path)
    if sl.sizes.get("step", 0) == 0:
        face, why = _no_roll(sl, slope_path, "Fig. 10")
        k0, title = -1, f"Fig. 10  Slope: the CoG projects along gravity onto the contact plane; {why}"
    else:
        face = int(sl["face"].values[0])
        k0 = int(np.searchsorted(sl["time"].values, sl["t_start"].values[0]))
        title = f"Fig. 10  Slope: the CoG projects along gravity onto the contact plane ('{sl.attrs['run']}' run)"
    out.append(
        state_figures_.fig_slope(sl["nodes"].values[k0], run_formats.terrain_from_dataset(sl), face, fig10, title)
    )
    return out


def _paper_states(ds: xr.Dataset, terrain: Terrain, fig8: str | os.PathLike, fig9: str | os.PathLike) -> list[dict]:
    """Fig. 8 and 9 from the first roll of the paper run `ds` (`state_figures`)."""
    from ..physics import contact as ct
    from ..render import locomotion as state_figures_

    face = int(ds["face"].values[0])
    pair = int(ds["step_pair"].values[0, 0])
    tip = float(ds["tip_pressure"].values[0])
    edge = [topo.edge_nodes(face, j) for j in range(3)].index(tuple(ds["edge"].values[0]))
    levels, unit = run_formats.commands(ds)
    k, p = run_formats.run_sample(ds, terrain, 1, "stable")
    out = [
        state_figures_.fig_state(
            p,
            terrain,
            face,
            fig8,
            f"Fig. 8  Stable: #{pair} at {levels[k].max():.1f} {unit}, the CoG "
            f"projection stays inside {topo.face_label(face)}",
            arrow=ct.edge_outward(p[topo.FACES[face - 1]])[edge],
        )
    ]
    try:
        k, p = run_formats.run_sample(ds, terrain, 1, "rolling")
        title9 = (
            f"Fig. 9  Rolling: #{pair} tipped the robot at {tip:.2f} {unit}; the CoG "
            f"projection has left {topo.face_label(face)}"
        )
    except ValueError:  # e.g. grounded sweeps: the planned pressure did not tip the robot
        k = int(np.clip(np.searchsorted(ds["time"].values, ds["t_end"].values[0]), 0, ds.sizes["time"] - 1))
        p = ds["nodes"].values[k]
        title9 = (
            f"Fig. 9  Not rolling: #{pair} at up to {float(ds['peak_pressure'].values[0]):.2f} {unit} "
            f"did not tip the robot off {topo.face_label(face)} (run '{ds.attrs.get('run', '')}': "
            f"{ds.attrs.get('outcome', '')})"
        )
    out.append(state_figures_.fig_state(p, terrain, face, fig9, title9))
    return out


def path_figures(
    cfg: dict, run_path: str | os.PathLike, top: str | os.PathLike, three_d: str | os.PathLike
) -> list[dict]:
    """Stage `path_figures`: the path of one run from above (`top`) and in 3D (`three_d`).
    Returns what each figure drew (render.runs.fig_path)."""
    ds = datasets.read(run_path)
    return [_path_figure(ds, top, "top"), _path_figure(ds, three_d, "3d")]


def animation(cfg: dict, run_path: str | os.PathLike, gif: str | os.PathLike) -> dict:
    """Stage `animation`: a GIF of one run at locomotion.animation_fps frames per second,
    locomotion.animation_speed times faster than simulated time. Returns {"path", "frames", "fps"}."""
    from ..render.animation import animate

    loc = cfg["locomotion"]
    ds = datasets.read(run_path)
    levels, unit = run_formats.commands(ds)
    return animate(
        ds["nodes"].values,
        ds["time"].values,
        levels,
        run_formats.terrain_from_dataset(ds),
        gif,
        goal=ds["goal"].values,
        label=f"run '{ds.attrs.get('run', '')}'",
        fps=int(loc["animation_fps"]),
        speed=float(loc["animation_speed"]),
        unit=unit,
    )
