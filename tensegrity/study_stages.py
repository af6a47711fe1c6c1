"""The design-study stages (workflow/rules/study.smk, `tensegrity study`): one chunk of designs,
the merge of the chunks into designs.nc, and the analysis (indices, best designs, figures).

Files (docs/datasets.md, "Design studies"), under results/studies/<name>/: chunks/chunkNNNN.nc,
designs.nc, analysis.nc and figures/*.png. `cfg` holds the main configuration's sections the
numbers depend on (STAGE_CONFIG["study"]: params, sim, locomotion); each file's provenance holds
it and the study (attribute `study_config`, JSON).
"""
from __future__ import annotations

import os
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path

import numpy as np
import xarray as xr

from .io import datasets
from .io.config import params_from_config, to_json
from .studies import analysis as an
from .studies import evaluate as ev
from .studies import results as res
from .studies import spec

CHUNK_FILE = "chunks/chunk{chunk:04d}.nc"


def _paper(study: Mapping, ws: ev.StudyWorkspace, designs: Sequence) -> dict:
    """The paper's statements per design (validation check 1, `validation.paper.check_paper`,
    on each design's nominal CoG): tip pressures, edges, migration (D, C, P) and status (D, 5)."""
    from .validation.paper import check_paper
    w = study["workspace"]
    contacts = list(w["contacts"])
    D, C, P = ws.margin.shape[:3]
    out = {"tip_pressure": np.full((D, C, P), np.nan), "tip_edge": np.zeros((D, C, P, 2), np.int64),
           "migration": np.full((D, C, P), np.nan), "status": np.zeros((D, len(res.STATEMENTS)), np.int8)}
    for i, prm in enumerate(designs):
        nominals = {c: xr.Dataset({"cog": (("pair", "pressure", "axis"), ws.cog[i, j]),
                                   "support": (("pair", "pressure", "corner", "axis"), ws.support[i, j]),
                                   "margin": (("pair", "pressure"), ws.margin[i, j])},
                                  coords={"pair": ws.pairs, "pressure": ws.levels}, attrs={"face": int(ws.faces[j])})
                    for j, c in enumerate(contacts)}
        r = check_paper(nominals, float(prm.strut_length), w["reference_pressure"], w["tip_tolerance"])
        for j, c in enumerate(contacts):
            k = ("equilateral", "isosceles").index(c)
            out["tip_pressure"][i, j] = r.tip_pressure[k, ws.pairs - 1]
            out["tip_edge"][i, j] = r.tip_edge[k, ws.pairs - 1]
            out["migration"][i, j] = r.migration[k, ws.pairs - 1]
        out["status"][i] = [res.STATEMENT_CODE[r.status[s]] for s in res.STATEMENTS]
    return out


def _attrs(study: Mapping) -> dict:
    return {"study_config": to_json(study)}


def run_chunk(cfg: dict, study: Mapping, chunk: int, out_path: str | os.PathLike, limit: int = 0,
              progress: Callable[[float], None] | None = None) -> Path:
    """Compute chunk number `chunk` (0-based) of the study (its designs in one batch) and write
    it to `out_path`. `limit` > 0: the study's first `limit` designs only."""
    from .locomotion.control import RollSettings
    from .locomotion.demos import locomotion_params
    rows = spec.chunk_rows(study, chunk, limit)
    X = spec.design_matrix(study)[rows]
    base = params_from_config(cfg)
    designs = spec.design_params(base, study, X)
    ws = paper = rolls = None
    w = study["workspace"]
    if w["enabled"]:
        ws = ev.workspace(designs, w["contacts"], w["pairs"], w["levels"], w["hold"], w["discard"],
                          cfg["sim"]["dt"], w["sample_every"], progress)
        paper = _paper(study, ws, designs)
    if study["roll"]["enabled"]:
        roll_designs = spec.design_params(locomotion_params(cfg), study, X)
        rolls = ev.roll_sequence(roll_designs, RollSettings.from_config(cfg["locomotion"], cfg["sim"]["dt"]),
                                 study["roll"]["max_pressure"])
    ds = res.chunk_dataset(study, rows, X, ws, paper, rolls)
    ds.attrs.update(_attrs(study), chunk=int(chunk))
    return datasets.write(ds, out_path, {**cfg, "study": study["name"]},
                          f"Design study '{study['name']}': designs {rows[0]}..{rows[-1]}",
                          stage="study_chunk", allow_nan=[k for k in res.ALLOW_NAN if k in ds])


def merge_chunks(cfg: dict, study: Mapping, chunk_paths: Sequence[str | os.PathLike],
                 out_path: str | os.PathLike) -> Path:
    """Concatenate the chunk files along `design` into designs.nc."""
    ds = res.merge([datasets.read(p) for p in chunk_paths])
    ds.attrs.update(_attrs(study))
    ds.attrs.pop("chunk", None)
    return datasets.write(ds, out_path, {**cfg, "study": study["name"]},
                          f"Design study '{study['name']}': {ds.sizes['design']} designs",
                          stage="study_merge", allow_nan=[k for k in res.ALLOW_NAN if k in ds])


def analyse(cfg: dict, study: Mapping, designs_path: str | os.PathLike, out_path: str | os.PathLike,
            figure_dir: str | os.PathLike) -> list[Path]:
    """Sensitivity indices of the study's outputs, the best designs and the figures
    (figures/sensitivity.png, response.png, and robustness.png for a roll study)."""
    from .render import studies as fig
    src = datasets.read(designs_path)
    names = list(study["parameters"])
    X = np.stack([src[n].values for n in names], axis=1)
    complete = src.sizes["design"] == spec.n_designs(study)
    outputs = list(study["analysis"]["outputs"])  # each computed (spec.validate)
    coords = {"parameter": ("parameter", names, {"long_name": "varied parameter"}),
              "output": ("output", outputs, {"long_name": "per-design output analysed"})}
    v, indices, failed = {}, {}, []
    method = an.method_of(study)
    # a pair that never tips within the levels, a roll that never happens: at the highest pressure
    censor = {"workspace": float(study["workspace"]["levels"][-1]), "roll": float(study["roll"]["max_pressure"])}
    for o in outputs:
        y = (src["roll_tip_pressure"].values[:, int(o[-1]) - 1] if o.startswith("roll_tip")
             else src[o].values.astype(float))
        nan = {n: np.full(len(names), np.nan) for p in an.INDICES[method] for n in p if n}
        try:
            indices[o] = (an.sensitivity(study, X, y, censor["roll" if o.startswith("roll_") else "workspace"])
                          if complete else nan)
        except (np.linalg.LinAlgError, ValueError) as e:  # e.g. delta's density of a 0/1 output
            indices[o] = nan
            failed.append(f"{o}: {type(e).__name__}: {str(e).splitlines()[0]}")
            print(f"sensitivity of {o} not computed: {e}")
    for pair in an.INDICES[method]:
        for n in pair:
            if n:
                v[n] = datasets.var(("output", "parameter"), np.array([indices[o][n] for o in outputs]), "1",
                                    f"{method} sensitivity index {n} (SALib; NaN: the study was not run in full)")
    files = []
    figdir = Path(figure_dir)
    attrs = {**_attrs(study), "method": method, "censored_at_mpa": censor["workspace"],
             "roll_censored_at_mpa": censor["roll"], "indices_not_computed": "; ".join(failed) or "none"}
    if "objective" in src:
        best = an.best_designs(src["objective"].values, study["analysis"]["best"])
        coords["rank"] = ("rank", np.arange(1, best.size + 1), {"units": "1", "long_name": "rank for the objective (1: best)"})
        v["best_design"] = datasets.var(("rank",), src["design"].values[best], "1",
                                        "designs with the lowest tipping pressure of the best pair, all pairs standing at the reference pressure")
        v["best_objective"] = datasets.var(("rank",), src["objective"].values[best], "MPa", "objective of the best designs")
        shown = list(dict.fromkeys(study["analysis"]["response"] + names))  # the response parameters first
        p1, p2 = (shown + shown)[:2]
        files.append(fig.response_map(src[p1].values, src[p2].values, src["objective"].values,
                                      src["min_margin"].values, (p1, spec.UNITS[p1]), (p2, spec.UNITS[p2]),
                                      best, figdir / "response.png"))
    if "roll_success" in src:
        rate, low, high = an.success_rate(src["roll_success"].values)
        attrs.update(roll_success_rate=rate, roll_success_rate_ci95_low=low, roll_success_rate_ci95_high=high)
        shown = list(dict.fromkeys(study["analysis"]["response"] + names))
        files.append(fig.robustness(src["roll_success"].values, src["roll_tip_pressure"].values,
                                    np.stack([src[n].values for n in shown], axis=1),
                                    [(n, spec.UNITS[n]) for n in shown], (rate, low, high), figdir / "robustness.png"))
    index_names = [n for p in an.INDICES[method] for n in p if n]
    files.append(fig.sensitivity_bars(names, outputs, method, {n: v[n][1] for n in index_names},
                                      figdir / "sensitivity.png"))
    ds = xr.Dataset(v, coords=coords, attrs=attrs)
    files.insert(0, datasets.write(ds, out_path, {**cfg, "study": study["name"]},
                                   f"Design study '{study['name']}': sensitivity and best designs",
                                   stage="study_analyse", allow_nan=[n for n in v if n not in ("best_design",)]))
    return files


def run_study(cfg: dict, study: Mapping, out_dir: str | os.PathLike, limit: int = 0,
              bar: Callable[[float], None] | None = None) -> list[Path]:
    """The whole study outside Snakemake: every chunk not yet written, the merge, the analysis.
    bar(s) receives the simulated seconds as they pass."""
    out = Path(out_dir)
    paths = []
    for c in range(spec.n_chunks(study, limit)):
        p = out / CHUNK_FILE.format(chunk=c)
        if not p.is_file():  # a finished chunk is never recomputed
            run_chunk(cfg, study, c, p, limit, bar)
        paths.append(p)
    merge_chunks(cfg, study, paths, out / "designs.nc")
    return analyse(cfg, study, out / "designs.nc", out / "analysis.nc", out / "figures")


def cmd_study(cfg: dict, name: str, out_dir: str | os.PathLike | None = None, limit: int = 0) -> int:
    """`tensegrity study`: load and check the study (before any work), run it with a progress bar
    in designs on a terminal (tqdm; quiet otherwise), print where the files are. Returns 0."""
    import sys
    from tqdm import tqdm
    from .stages import stage_config
    study = spec.load(name, base=params_from_config(cfg), dt=cfg["sim"]["dt"])
    out = Path(out_dir or Path("results", "studies", study["name"]))
    n = spec.n_designs(study) if not limit else min(limit, spec.n_designs(study))
    w = study["workspace"]
    per_design_s = len(w["levels"]) * w["hold"]
    with tqdm(total=n, desc=f"study {study['name']}", unit="design", disable=None, file=sys.stderr,
              bar_format="{desc}: {percentage:3.0f}%|{bar}| {n:.1f}/{total} designs [{elapsed}<{remaining}]") as bar:
        done = sum(len(spec.chunk_rows(study, c, limit)) for c in range(spec.n_chunks(study, limit))
                   if (out / CHUNK_FILE.format(chunk=c)).is_file())
        bar.update(done)

        def progress(seconds: float) -> None:  # a level of one chunk: its designs' share
            bar.update(min(study["chunk_size"], n) * seconds / per_design_s)

        files = run_study(stage_config(cfg, "study"), study, out, limit, progress)
        bar.n = n
        bar.refresh()
    for f in files:
        print(f)
    return 0
