"""A measured trajectory read for calibration (docs/datasets.md, "Calibration"): a run file as
`tensegrity simulate --out` writes it (`nodes(time, node, axis)` m, world frame;
`pressure_cmd(time, pair)` MPa; `time` s; attribute `mode`), or a motion-capture CSV with the
header `time_s, n1_x, n1_y, n1_z, ..., n12_z, p1, ..., p12` (m, MPa; any column order, other
columns ignored; an empty cell or `nan` is a missing value). How gaps are handled:
`calibration.measurement`.
"""

from __future__ import annotations

import csv
import os
from pathlib import Path

import numpy as np

from ...calibration.measurement import Measurement
from ...physics import topology as topo
from .. import datasets

__all__ = ["read_measured", "CSV_COLUMNS", "write_measured_csv"]

NODE_COLUMNS = [f"n{i}_{a}" for i in range(1, topo.N_NODES + 1) for a in "xyz"]
PRESSURE_COLUMNS = [f"p{j}" for j in range(1, topo.N_PAIRS + 1)]
CSV_COLUMNS = ["time_s", *NODE_COLUMNS, *PRESSURE_COLUMNS]


def read_measured(path: str | os.PathLike) -> Measurement:
    """The measurement in the file `path` (.csv: motion capture; else a run file, netCDF).
    ValueError naming the file and what is missing or inconsistent; FileNotFoundError."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"no measured trajectory {os.fspath(path)!r}")
    if path.suffix.lower() == ".csv":
        return _read_csv(path)
    ds = datasets.read(path)
    for name, dims in (("nodes", ("time", "node", "axis")), ("pressure_cmd", ("time", "pair"))):
        if name not in ds:
            raise ValueError(f"{path}: no variable {name!r}; a run file (tensegrity simulate --out) holds {dims}")
        if ds[name].dims != dims:
            raise ValueError(f"{path}: variable {name!r} has dimensions {ds[name].dims}, expected {dims}")
    nodes = ds["nodes"].transpose("time", "node", "axis").sel(node=np.arange(1, 13), axis=["x", "y", "z"])
    return Measurement(
        ds["time"].values,
        nodes.values,
        ds["pressure_cmd"].sel(pair=np.arange(1, 13)).values,
        str(ds.attrs.get("mode", "")),
        str(path),
    )


def _number(text: str) -> float:
    return float("nan") if text.strip() == "" else float(text)


def _read_csv(path: Path) -> Measurement:
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        raise ValueError(f"{path}: empty file; expected the header {', '.join(CSV_COLUMNS[:3])}, ..., p12")
    header = [h.strip() for h in rows[0]]
    missing = [c for c in CSV_COLUMNS if c not in header]
    if missing:
        raise ValueError(f"{path}: no column {', '.join(missing[:6])}{' ...' if len(missing) > 6 else ''}")
    dup = sorted({h for h in header if header.count(h) > 1 and h in CSV_COLUMNS})
    if dup:
        raise ValueError(f"{path}: column {', '.join(dup)} appears twice")
    col = [header.index(c) for c in CSV_COLUMNS]
    data = np.empty((len(rows) - 1, len(CSV_COLUMNS)))
    for i, row in enumerate(rows[1:]):
        if len(row) != len(header):
            raise ValueError(f"{path}: line {i + 2} has {len(row)} fields, the header {len(header)}")
        try:
            data[i] = [_number(row[c]) for c in col]
        except ValueError:
            k = next(k for k, c in enumerate(col) if not _is_number(row[c]))
            raise ValueError(
                f"{path}: line {i + 2}, column {CSV_COLUMNS[k]}: {row[col[k]]!r} is not a number"
            ) from None
    n = 1 + len(NODE_COLUMNS)
    nodes = data[:, 1:n].reshape(-1, topo.N_NODES, 3)
    return Measurement(data[:, 0], nodes, data[:, n:], "", str(path))


def _is_number(text: str) -> bool:
    try:
        _number(text)
        return True
    except ValueError:
        return False


def write_measured_csv(m: Measurement, path: str | os.PathLike) -> Path:
    """Write m as a motion-capture CSV (`CSV_COLUMNS`; NaN as an empty cell) atomically."""
    from ... import atomic

    lines = [",".join(CSV_COLUMNS)]
    flat = np.concatenate([m.t[:, None], m.nodes.reshape(len(m.t), -1), m.pressure], axis=1)
    for row in flat:
        lines.append(",".join("" if np.isnan(v) else repr(float(v)) for v in row))
    return atomic.write_text(path, "\n".join(lines) + "\n")
