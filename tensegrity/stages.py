"""The workflow's stages as functions from files to files (docs/design.md §5).

Each reads its inputs, calls the pure modules (sweep, nominal, fit, mapping, render) and writes
its outputs with `datasets.write`. The Snakemake scripts and the command line call these; the
figure stages live in `figure_stages` and are re-exported here.
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

from .io import datasets, formats
from .physics import frames, topology as topo
from .workspace import mapping
from .workspace import nominal as nom
from .io.config import params_from_config
from .sections import STAGE_CONFIG, stage_config  # noqa: F401  (re-exported: the rules' cfg)
from .figure_stages import (  # noqa: F401  (the figure rules call them as stages.*)
    locomotion_animation, locomotion_paths, locomotion_states, render_cloud, render_dataset,
    render_robot, render_workspace)

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


@contextlib.contextmanager
def job(path: str | os.PathLike, threads: int | None = None) -> Iterator[None]:
    """The body of a workflow script: `logging_to` the log file `path` with `threads` compute
    threads; on success the process then ends at once, without the interpreter's teardown
    (freeing numba's compiled code and the renderer took 0.3-0.45 s of CPU in every job, a
    tenth of the pipeline's). Every output is written and closed by then; the streams are
    flushed first. A failure raises as usual (traceback in the log, exit status 1)."""
    import logging
    import sys
    with logging_to(path, threads):
        yield
    logging.shutdown()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(0)


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
    from .workspace import fit
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


# ----- locomotion stages
# (appended by the locomotion split; everything above belongs to the stages module's owner)

def locomotion_run(cfg: dict, name: str, workspace_path: str | Path, out_path: str | Path,
                   two_pair_path: str | Path | None = None) -> Path:
    """Stage `locomotion_run`: the demonstration run `name` (one of locomotion.DEMOS), planned
    from the workspace file (results/workspace.nc) and, if given, the measured two-pair
    curves of results/workspace_two_pair.nc (`Workspace.with_two_pair`; without it two pairs
    are superposed), and rolled in the grounded simulation.
    Writes the run dataset (results/locomotion/{run}.nc, `io.run_formats.run_dataset`) to
    `out_path` and returns its path; prints the steps and the outcome. `cfg`: the sections of
    STAGE_CONFIG["locomotion_run"], merged over the workspace file's provenance."""
    return locomotion_runs(cfg, [name], workspace_path, [out_path], two_pair_path)[0]


def locomotion_runs(cfg: dict, names: Sequence[str], workspace_path: str | Path,
                    out_paths: Sequence[str | Path], two_pair_path: str | Path | None = None) -> list[Path]:
    """`locomotion_run` of each of `names` in turn, to the matching `out_paths`, the workspace
    read once (the workflow's rule `locomotion_runs`: one job, which starts the simulator once)."""
    from .io import formats, run_formats
    from .locomotion import demos, outcome, runs
    from .locomotion.control import RollSettings
    if len(names) != len(out_paths):
        raise ValueError(f"{len(names)} runs {list(names)} but {len(out_paths)} output paths")
    src = datasets.read(workspace_path)  # read once: the workspace and its provenance
    ws = formats.workspace_from_dataset(src)
    if two_pair_path is not None:
        from .io.two_pair_formats import read_two_pair
        ws = ws.with_two_pair(*read_two_pair(two_pair_path))
    setups = [demos.demo_setup(cfg, name) for name in names]  # an unknown name: before any run
    params = demos.locomotion_params(cfg)
    s = RollSettings.from_config(cfg["locomotion"], cfg["sim"]["dt"])
    provenance = {**datasets.provenance_config(src), **cfg}  # the same for every run
    out = []
    for name, setup, out_path in zip(names, setups, out_paths):
        if "edges" in setup:
            run = runs.roll_over(ws, setup["edges"], params, setup["terrain"], settings=s)
        else:
            run = runs.roll_to(ws, setup["goal"], params, setup["terrain"], settings=s)
        print(outcome.describe(run, name), flush=True)
        out.append(datasets.write(run_formats.run_dataset(run, setup["terrain"], name), out_path,
                                  provenance, f"Rolling locomotion run '{name}': {run.outcome}",
                                  stage="locomotion", allow_nan=run_formats.RUN_ALLOW_NAN))
    return out


