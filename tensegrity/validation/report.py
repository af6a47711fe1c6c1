"""Outputs of the validation stage: validation.nc, summary.md and summary.html (the table
in the HTML report). The checks themselves are in `validation`."""
from __future__ import annotations

import html
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
import xarray as xr

from ..io import datasets
from .checks import AXES, CONTACTS, FAIL, PASS, SKIP, Check, _levels, run_checks


def to_dataset(checks: Sequence[Check], levels, faces, statics_pressures) -> tuple[xr.Dataset, list[str]]:
    """All checks' numbers and verdicts as one dataset, and the names of the variables that may
    hold NaN. Verdicts are on the dimension `check`: status (string) and passed (1/0/-1)."""
    rows = [r for c in checks for r in c.verdicts]
    data, allow = {}, []
    for c in checks:
        data.update(c.data)
        allow += list(c.allow_nan)
    data["passed"] = datasets.var(("check",), np.array([1 if r.status == PASS else 0 if r.status == FAIL else -1
                                                for r in rows], np.int8), "1",
                          "1: passed, 0: failed, -1: not evaluated")
    for key in ("statement", "measured", "reference", "status"):
        data[key] = (("check",), np.array([getattr(r, key) for r in rows], dtype=str),
                     {"long_name": {"statement": "what is checked", "measured": "measured value, with units",
                                    "reference": "the paper's value or the goal",
                                    "status": f"{PASS}, {FAIL} or {SKIP}"}[key]})
    coords = {
        "check": ("check", np.array([r.id for r in rows], dtype=str), {"long_name": "check number"}),
        "contact": ("contact", np.array(CONTACTS), {"long_name": "contact case"}),
        "pair": ("pair", np.arange(1, 13), {"units": "1", "long_name": "actuator pair number"}),
        "pressure": ("pressure", np.asarray(levels, float), {"units": "MPa", "long_name": "muscle pressure"}),
        "statics_pressure": ("statics_pressure", np.asarray(statics_pressures, float),
                             {"units": "MPa", "long_name": "pressure of the statics check"}),
        "sample_face": ("sample_face", np.asarray(faces, np.int64),
                        {"units": "1", "long_name": "face number of the mapping check"}),
        "axis": ("axis", np.array(AXES), {"long_name": "support-frame axis"}),
        "end": ("end", np.array([1, 2]), {"units": "1", "long_name": "edge end"}),
    }
    if "orbit_pairs" in data:
        n_orb, size = data["orbit_pairs"][1].shape
        coords["orbit"] = ("orbit", np.arange(1, n_orb + 1), {"units": "1", "long_name": "3-fold orbit number"})
        coords["member"] = ("member", np.arange(1, size + 1), {"units": "1", "long_name": "orbit member"})
    used = {d for v in data.values() for d in v[0]}
    ds = xr.Dataset(data, coords={k: v for k, v in coords.items() if k in used})
    return ds, [a for a in allow if a in ds]


def summary_tables(checks: Sequence[Check]) -> list[tuple[str, list[str], list[list[str]]]]:
    rows = [[r.id, r.statement, r.measured, r.reference, r.status.upper()] for c in checks for r in c.verdicts]
    tables = [("Checks", ["#", "statement", "measured", "paper / goal", "verdict"], rows)]
    for c in checks:
        tables += list(c.tables)
    return tables


def _counts(checks: Sequence[Check]) -> str:
    rows = [r for c in checks for r in c.verdicts]
    n = {s: sum(r.status == s for r in rows) for s in (PASS, FAIL, SKIP)}
    return f"{n[PASS]} of {len(rows)} checks passed, {n[FAIL]} failed, {n[SKIP]} not evaluated."


def summary_markdown(checks: Sequence[Check], note: str = "") -> str:
    """The summary as Markdown: the verdict table and the per-pair tables."""
    esc = lambda s: str(s).replace("|", "\\|").replace("\n", " ")
    out = ["# Validation of the kinematic workspace", "", _counts(checks)]
    if note:
        out += ["", note]
    for title, header, rows in summary_tables(checks):
        out += ["", f"## {title}", "", "| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
        out += ["| " + " | ".join(esc(x) for x in row) + " |" for row in rows]
    return "\n".join(out) + "\n"


def summary_html(checks: Sequence[Check], note: str = "") -> str:
    """The summary as a self-contained HTML page (for the Snakemake report)."""
    colour = {PASS.upper(): "#1a7f37", FAIL.upper(): "#cf222e", SKIP.upper(): "#9a6700"}
    parts = ["<!doctype html><html><head><meta charset='utf-8'><title>Validation</title><style>",
             "body{font-family:sans-serif;font-size:14px;margin:1em}table{border-collapse:collapse;"
             "margin-bottom:1.5em}td,th{border:1px solid #ccc;padding:4px 8px;vertical-align:top;"
             "text-align:left}th{background:#f3f3f3}", "</style></head><body>",
             "<h1>Validation of the kinematic workspace</h1>", f"<p>{html.escape(_counts(checks))}</p>"]
    if note:
        parts.append(f"<p>{html.escape(note)}</p>")
    for title, header, rows in summary_tables(checks):
        parts.append(f"<h2>{html.escape(title)}</h2><table><tr>"
                     + "".join(f"<th>{html.escape(h)}</th>" for h in header) + "</tr>")
        for row in rows:
            cells = []
            for x in row:
                style = f" style='color:{colour[x]};font-weight:bold'" if x in colour else ""
                cells.append(f"<td{style}>{html.escape(str(x))}</td>")
            parts.append("<tr>" + "".join(cells) + "</tr>")
        parts.append("</table>")
    parts.append("</body></html>")
    return "\n".join(parts) + "\n"


def run_stage(cfg: Mapping, nominal_paths, workspace_path, nc_path, md_path, html_path=None) -> list[Path]:
    """The validate stage, files to files: read the pipeline's nominal CoG files and workspace,
    run every check, write validation.nc (every number, with units), the Markdown summary and,
    if `html_path` is given, the HTML summary for the report. Failed checks do not raise."""
    nominals = {}
    prov = {}
    for p in nominal_paths:
        ds = datasets.read(p)
        nominals[str(ds.attrs["contact"])] = ds
        prov.update(datasets.provenance_config(p))
    workspace = datasets.read(workspace_path) if workspace_path else None
    if workspace_path:
        prov.update(datasets.provenance_config(workspace_path))
    prov.update(cfg)
    checks = run_checks(cfg, nominals, workspace)
    v = cfg["validate"]
    ds, allow = to_dataset(checks, _levels(nominals), v["faces"], v["statics_pressures"])
    note = ("Every number, with units: validation.nc. Sweeps: "
            f"{', '.join(f'{float(p):g}' for p in cfg['sweep']['levels'])} MPa held {cfg['sweep']['hold']:g} s, "
            f"{cfg['sweep']['mode']} mode, dt {cfg['sim']['dt']:g} s, nominal = mean after the first "
            f"{cfg['nominal']['discard']:g} s of each level.")
    paths = [datasets.write(ds, nc_path, prov, "Validation of the workspace against the paper, statics, "
                            "symmetry, the grounded mode and a halved time step", stage="validate",
                            allow_nan=allow),
             datasets.write_text(md_path, summary_markdown(checks, note))]
    if html_path:
        paths.append(datasets.write_text(html_path, summary_html(checks, note)))
    return paths
