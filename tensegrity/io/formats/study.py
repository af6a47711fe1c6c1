"""The study datasets (docs/datasets.md, "Design studies"): a chunk of designs
(results/studies/<name>/chunks/chunkNNNN.nc), all designs (designs.nc, the chunks concatenated
along `design`) and the analysis (analysis.nc). Built from arrays; written by `io.datasets.write`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import xarray as xr

from ...studies.evaluate import STATEMENTS, RollOutcome, StudyWorkspace, design_outputs
from ...studies.spec import UNITS
from .. import datasets
from .common import coords

ALLOW_NAN = ["tip_pressure", "best_tip_pressure", "objective", "roll_tip_pressure"]
var = datasets.var


def design_coords(study: Mapping, rows: np.ndarray, X: np.ndarray) -> dict:
    """The `design` coordinate (0-based row of the design matrix) and one coordinate on it per
    varied parameter, in its units."""
    c = {
        "design": (
            "design",
            np.asarray(rows, np.int64),
            {"units": "1", "long_name": "design number (row of the design matrix)"},
        )
    }
    for j, name in enumerate(study["parameters"]):
        c[name] = (
            "design",
            np.asarray(X[:, j], float),
            {"units": UNITS[name], "long_name": f"varied parameter {name}"},
        )
    return c


def chunk_dataset(
    study: Mapping,
    rows: np.ndarray,
    X: np.ndarray,
    ws: StudyWorkspace | None,
    paper: Mapping | None,
    rolls: Sequence[RollOutcome] | None,
) -> xr.Dataset:
    """Dataset of the designs `rows` (n,) with parameter values X (n, k): their workspace `ws`
    (D = n), the paper's statements `paper` (tip_pressure, tip_edge, migration (n, C, P);
    status (n, 5) codes of STATEMENT_CODE) and their roll sequences."""
    c = design_coords(study, rows, X)
    v = {}
    if ws is not None:
        ref = study["workspace"]["reference_pressure"]
        contacts = study["workspace"]["contacts"]
        c.update({k: v for k, v in coords(ws.pairs, ws.levels).items() if k not in ("corner", "node")})
        c["contact"] = ("contact", list(contacts), {"long_name": "contact case"})
        c["end"] = ("end", [1, 2], {"units": "1", "long_name": "end of an edge"})
        c["statement"] = ("statement", list(STATEMENTS), {"long_name": "statement of the paper (validation check 1)"})
        out = design_outputs(ws, paper["tip_pressure"], ref)
        mref, min_margin, best = out["reference_margin"], out["min_margin"], out["best_tip_pressure"]
        v.update(
            cog=var(
                ("design", "contact", "pair", "pressure", "axis"),
                ws.cog,
                "m",
                "nominal centre of gravity in the support frame",
            ),
            margin=var(
                ("design", "contact", "pair", "pressure"),
                ws.margin,
                "m",
                "signed distance of the CoG projection to the support triangle boundary (positive inside)",
            ),
            tip_pressure=var(
                ("design", "contact", "pair"),
                paper["tip_pressure"],
                "MPa",
                "least pressure at which the CoG projection leaves the triangle (NaN: never)",
            ),
            tip_edge=var(
                ("design", "contact", "pair", "end"),
                paper["tip_edge"],
                "1",
                "nodes of the edge crossed at the first level outside (0: never)",
            ),
            migration=var(
                ("design", "contact", "pair"),
                paper["migration"],
                "m",
                "in-plane CoG migration from the unactuated CoG at the reference pressure",
            ),
            reference_margin=var(("design", "contact", "pair"), mref, "m", "margin at the reference pressure"),
            min_margin=var(
                ("design",), min_margin, "m", "smallest margin of any pair and contact at the reference pressure"
            ),
            best_tip_pressure=var(
                ("design",), best, "MPa", "lowest tipping pressure of any pair and contact (NaN: none tips)"
            ),
            objective=var(
                ("design",),
                out["objective"],
                "MPa",
                "lowest tipping pressure of the best pair, where every pair stands at the reference pressure "
                "(NaN: not standing)",
            ),
            paper_statement=var(
                ("design", "statement"),
                np.asarray(paper["status"], np.int8),
                "1",
                "whether the paper's statement holds",
                flag_values=np.array([-1, 0, 1], np.int8),
                flag_meanings="not_evaluated fails holds",
            ),
        )
    if rolls is not None:
        _check_rolls(rolls, rows)
        c["roll"] = ("roll", [1, 2], {"units": "1", "long_name": "roll of the paper's sequence (#10, then #11)"})
        v.update(
            roll_success=var(
                ("design",),
                np.array([r.success for r in rolls], np.int8),
                "1",
                "1 if both rolls landed on the paper's faces (10,11,12) then (6,10,11)",
            ),
            roll_tip_pressure=var(
                ("design", "roll"),
                np.array([r.tip_pressure for r in rolls]),
                "MPa",
                "pressure held when a support node lifted, grounded roll (NaN: no roll)",
            ),
            roll_face=var(
                ("design", "roll"),
                np.array([r.face for r in rolls], np.int64),
                "1",
                "face (1..20) the robot rests on after the roll (0: none or not tried)",
            ),
        )
    return xr.Dataset(v, coords=c, attrs={"study": study["name"], "design_method": study["design"]["method"]})


def _check_rolls(rolls: Sequence[RollOutcome], rows: np.ndarray) -> None:
    """A roll that landed has a tipping pressure, one that did not has none: a record that says
    otherwise is refused naming its design (it was written once, issue 35)."""
    for row, r in zip(np.asarray(rows).ravel(), rolls):
        landed = r.face > 0
        if r.success and not np.all(np.isfinite(r.tip_pressure)):
            raise ValueError(f"design {int(row)}: both rolls succeeded but a tipping pressure is NaN {r.tip_pressure}")
        if np.any(np.isfinite(r.tip_pressure) & ~landed):
            raise ValueError(f"design {int(row)}: a tipping pressure {r.tip_pressure} for a roll that landed nowhere")


def merge(chunks: Sequence[xr.Dataset]) -> xr.Dataset:
    """The chunks concatenated along `design`, in design order."""
    out = xr.concat(
        sorted(chunks, key=lambda ds: int(ds["design"][0])),
        dim="design",
        data_vars="minimal",
        coords="minimal",
        compat="override",
        join="override",
        combine_attrs="override",
    )
    for k in ("config", "history", "title", "source", "Conventions"):
        out.attrs.pop(k, None)
    return out


def analysis_dataset(
    study: Mapping,
    method: str,
    indices: Mapping[str, Mapping[str, np.ndarray]],
    best: np.ndarray | None,
    designs: xr.Dataset,
    attrs: dict,
) -> xr.Dataset:
    """analysis.nc: the sensitivity indices (output, parameter) of `method` (SALib) of each
    analysed output, and, if `best` (indices of the designs, best first), the best designs for
    the objective of `designs` (designs.nc); `attrs` as given."""
    names, outputs = list(study["parameters"]), list(indices)
    coords = {
        "parameter": ("parameter", names, {"long_name": "varied parameter"}),
        "output": ("output", outputs, {"long_name": "per-design output analysed"}),
    }
    v = {}
    for n in next(iter(indices.values())) if indices else ():
        v[n] = var(
            ("output", "parameter"),
            np.array([indices[o][n] for o in outputs]),
            "1",
            f"{method} sensitivity index {n} (SALib; NaN: the study was not run in full)",
        )
    if best is not None:
        coords["rank"] = (
            "rank",
            np.arange(1, best.size + 1),
            {"units": "1", "long_name": "rank for the objective (1: best)"},
        )
        v["best_design"] = var(
            ("rank",),
            designs["design"].values[best],
            "1",
            "designs with the lowest tipping pressure of the best pair, all pairs standing at the reference pressure",
        )
        v["best_objective"] = var(("rank",), designs["objective"].values[best], "MPa", "objective of the best designs")
    return xr.Dataset(v, coords=coords, attrs=attrs)
