"""Rules `study_chunk`, `study_merge` and `study_analyse` (workflow/rules/study.smk): one chunk
of designs, the merge of the chunks into designs.nc, and the analysis (indices, best designs,
figures); `run_study`, the whole study outside Snakemake (`tensegrity study`).

Files (docs/datasets.md, "Design studies"), under results/studies/<name>/: chunks/chunkNNNN.nc,
designs.nc, analysis.nc and figures/*.png. `cfg` holds the main configuration's keys the numbers
depend on (`config.STAGES["study_chunk"]`); each file's provenance holds them and the study
(attribute `study_config`, JSON).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path

import numpy as np

from ..io import datasets, settings
from ..io.datasets import to_json
from ..io.formats import study as sf
from ..locomotion.settings import RollSettings
from ..studies import analysis as an
from ..studies import evaluate as ev
from ..studies import spec
from ..workspace.sweep import SweepSetup
from . import provenance

CHUNK_FILE = "chunks/chunk{chunk:04d}.nc"


def _attrs(study: Mapping) -> dict:
    return {"study_config": to_json(study)}


def _prov(cfg: Mapping, study: Mapping, *inputs: str | os.PathLike) -> dict:
    return {**provenance(cfg, *inputs), "study": study["name"]}


def study_chunk(
    cfg: dict,
    study: Mapping,
    chunk: int,
    out_path: str | os.PathLike,
    limit: int = 0,
    progress: Callable[[float], None] | None = None,
) -> Path:
    """Stage `study_chunk`: compute chunk number `chunk` (0-based) of the study (its designs in
    one batch) and write it to `out_path`. `limit` > 0: the study's first `limit` designs only."""
    rows = spec.chunk_rows(study, chunk, limit)
    X = spec.design_matrix(study)[rows]
    base = settings.params(cfg)
    designs = spec.design_params(base, study, X)
    ws = paper = rolls = None
    w = study["workspace"]
    if w["enabled"] and w["method"] == "statics":
        ws, tips = ev.static_workspace(designs, w["contacts"], w["pairs"], w["levels"])
        paper = ev.paper_statements(designs, ws, w["contacts"], w["reference_pressure"], w["tip_tolerance"], tips)
        if progress:
            progress(len(w["levels"]) * float(w["hold"]))  # as the dynamic path reports its levels
    elif w["enabled"]:
        setup = SweepSetup(
            levels=tuple(w["levels"]),
            hold=float(w["hold"]),
            dt=float(cfg["sim"]["dt"]),
            record_every=int(w["sample_every"]),
        )
        ws = ev.workspace(designs, w["contacts"], w["pairs"], setup, float(w["discard"]), progress)
        paper = ev.paper_statements(designs, ws, w["contacts"], w["reference_pressure"], w["tip_tolerance"])
    if study["roll"]["enabled"]:
        s = settings.build(RollSettings, cfg)
        rolls = ev.roll_sequence(spec.design_params(s.rolling(base), study, X), s, study["roll"]["max_pressure"])
    ds = sf.chunk_dataset(study, rows, X, ws, paper, rolls)
    ds.attrs.update(_attrs(study), chunk=int(chunk))
    return datasets.write(
        ds,
        out_path,
        _prov(cfg, study),
        f"Design study '{study['name']}': designs {rows[0]}..{rows[-1]}",
        stage="study_chunk",
        allow_nan=[k for k in sf.ALLOW_NAN if k in ds],
    )


def study_merge(
    cfg: dict, study: Mapping, chunk_paths: Sequence[str | os.PathLike], out_path: str | os.PathLike
) -> Path:
    """Stage `study_merge`: the chunk files concatenated along `design` into designs.nc."""
    ds = sf.merge([datasets.read(p) for p in chunk_paths])
    ds.attrs.update(_attrs(study))
    ds.attrs.pop("chunk", None)
    return datasets.write(
        ds,
        out_path,
        _prov(cfg, study, *chunk_paths[:1]),
        f"Design study '{study['name']}': {ds.sizes['design']} designs",
        stage="study_merge",
        allow_nan=[k for k in sf.ALLOW_NAN if k in ds],
    )


def study_analyse(
    cfg: dict,
    study: Mapping,
    designs_path: str | os.PathLike,
    out_path: str | os.PathLike,
    figure_dir: str | os.PathLike,
) -> list[Path]:
    """Stage `study_analyse`: sensitivity indices of the study's outputs, the best designs and
    the figures (figures/sensitivity.png, response.png, and robustness.png for a roll study)."""
    from ..render import studies as fig

    src = datasets.read(designs_path)
    names = list(study["parameters"])
    X = np.stack([src[n].values for n in names], axis=1)
    complete = src.sizes["design"] == spec.n_designs(study)
    outputs = {
        o: (
            src["roll_tip_pressure"].values[:, int(o[-1]) - 1]
            if o.startswith("roll_tip")
            else src[o].values.astype(float)
        )
        for o in study["analysis"]["outputs"]
    }
    indices, failed = an.all_indices(study, X, outputs, complete)
    method, censor = an.method_of(study), an.censor_values(study)
    attrs = {
        **_attrs(study),
        "method": method,
        "censored_at_mpa": censor["workspace"],
        "roll_censored_at_mpa": censor["roll"],
        "indices_not_computed": "; ".join(failed) or "none",
    }
    figdir, files = Path(figure_dir), []
    shown = list(dict.fromkeys(study["analysis"]["response"] + names))  # the response parameters first
    best = None
    if "objective" in src:
        best = an.best_designs(src["objective"].values, study["analysis"]["best"])
        p1, p2 = (shown + shown)[:2]
        files.append(
            fig.response_map(
                src[p1].values,
                src[p2].values,
                src["objective"].values,
                src["min_margin"].values,
                (p1, spec.UNITS[p1]),
                (p2, spec.UNITS[p2]),
                best,
                figdir / "response.png",
            )
        )
    if "roll_success" in src:
        rate, low, high = an.success_rate(src["roll_success"].values)
        attrs.update(roll_success_rate=rate, roll_success_rate_ci95_low=low, roll_success_rate_ci95_high=high)
        files.append(
            fig.robustness(
                src["roll_success"].values,
                src["roll_tip_pressure"].values,
                np.stack([src[n].values for n in shown], axis=1),
                [(n, spec.UNITS[n]) for n in shown],
                (rate, low, high),
                figdir / "robustness.png",
            )
        )
    ds = sf.analysis_dataset(study, method, indices, best, src, attrs)
    index_names = [n for p in an.INDICES[method] for n in p if n]
    files.append(
        fig.sensitivity_bars(
            names, list(outputs), method, {n: ds[n].values for n in index_names}, figdir / "sensitivity.png"
        )
    )
    files.insert(
        0,
        datasets.write(
            ds,
            out_path,
            _prov(cfg, study, designs_path),
            f"Design study '{study['name']}': sensitivity and best designs",
            stage="study_analyse",
            allow_nan=[n for n in ds.data_vars if n != "best_design"],
        ),
    )
    return files


def run_study(
    cfg: dict,
    study: Mapping,
    out_dir: str | os.PathLike,
    limit: int = 0,
    progress: Callable[[float], None] | None = None,
) -> list[Path]:
    """The whole study outside Snakemake: every chunk not yet written, the merge, the analysis.
    progress(s) receives the simulated seconds as they pass. `cfg`: the keys of `study_chunk`."""
    out = Path(out_dir)
    paths = []
    for c in range(spec.n_chunks(study, limit)):
        p = out / CHUNK_FILE.format(chunk=c)
        if not p.is_file():  # a finished chunk is never recomputed
            study_chunk(cfg, study, c, p, limit, progress)
        paths.append(p)
    study_merge({}, study, paths, out / "designs.nc")
    return study_analyse({}, study, out / "designs.nc", out / "analysis.nc", out / "figures")
