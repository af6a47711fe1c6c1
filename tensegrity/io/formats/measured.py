"""A measured trajectory read for calibration (docs/datasets.md, "Calibration"): a run file as
`tensegrity simulate --out` writes it (`nodes(time, node, axis)` m, world frame;
`pressure_cmd(time, pair)` MPa; `time` s; attribute `mode`), or a motion-capture CSV with the
header `time_s, n1_x, n1_y, n1_z, ..., n12_z, p1, ..., p12` (m, MPa; any column order, other
columns ignored; an empty cell or `nan` is a missing value). How gaps are handled:
`calibration.measurement`.

A run of the prototype's twisted strings is driven in volts: the run file holds
`voltage_cmd(time, pair)` V instead of `pressure_cmd`, the CSV the columns `v1, ..., v12` V
instead of `p1, ..., p12`. A file with both, or neither, is refused, naming the columns.
"""

from __future__ import annotations

import csv
import os
from pathlib import Path

import numpy as np

from ...calibration.measurement import Measurement
from ...physics import topology as topo
from .. import datasets

__all__ = ["read_measured", "CSV_COLUMNS", "VOLTAGE_CSV_COLUMNS", "write_measured_csv"]

NODE_COLUMNS = [f"n{i}_{a}" for i in range(1, topo.N_NODES + 1) for a in "xyz"]
PRESSURE_COLUMNS = [f"p{j}" for j in range(1, topo.N_PAIRS + 1)]
VOLTAGE_COLUMNS = [f"v{j}" for j in range(1, topo.N_PAIRS + 1)]
CSV_COLUMNS = ["time_s", *NODE_COLUMNS, *PRESSURE_COLUMNS]
VOLTAGE_CSV_COLUMNS = ["time_s", *NODE_COLUMNS, *VOLTAGE_COLUMNS]
# the command's variable in a run file and its columns in a CSV (Measurement.command)
_COMMAND = {"pressure": ("pressure_cmd", PRESSURE_COLUMNS), "voltage": ("voltage_cmd", VOLTAGE_COLUMNS)}


def _which(path: Path, present: dict[str, list[str]], neither: str) -> str:
    """The one command (pressure, voltage) whose names `present[command]` were found in `path`;
    ValueError naming them if both were, and saying `neither` if none was."""
    found = [k for k, names in present.items() if names]
    if len(found) == 1:
        return found[0]
    if not found:
        raise ValueError(f"{path}: {neither}; a run is driven by one of them")
    names = ", ".join(f"{', '.join(present[k][:3])}{' ...' if len(present[k]) > 3 else ''}" for k in found)
    raise ValueError(f"{path}: both pressures and voltages ({names}); a run is driven by one of them")


def read_measured(path: str | os.PathLike) -> Measurement:
    """The measurement in the file `path` (.csv: motion capture; else a run file, netCDF).
    ValueError naming the file and what is missing or inconsistent; FileNotFoundError."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"no measured trajectory {os.fspath(path)!r}")
    if path.suffix.lower() == ".csv":
        return _read_csv(path)
    ds = datasets.read(path)
    if "nodes" not in ds:
        raise ValueError(
            f"{path}: no variable 'nodes'; a run file (tensegrity simulate --out) holds (time, node, axis)"
        )
    present = {k: [v] if v in ds else [] for k, (v, _) in _COMMAND.items()}
    command = _which(path, present, "no variable 'pressure_cmd' (MPa) or 'voltage_cmd' (V) (time, pair)")
    cmd = _COMMAND[command][0]
    for name, dims in (("nodes", ("time", "node", "axis")), (cmd, ("time", "pair"))):
        if name not in ds:
            raise ValueError(f"{path}: no variable {name!r}; a run file (tensegrity simulate --out) holds {dims}")
        if ds[name].dims != dims:
            raise ValueError(f"{path}: variable {name!r} has dimensions {ds[name].dims}, expected {dims}")
    nodes = ds["nodes"].transpose("time", "node", "axis").sel(node=np.arange(1, 13), axis=["x", "y", "z"])
    return Measurement(
        ds["time"].values,
        nodes.values,
        ds[cmd].sel(pair=np.arange(1, 13)).values,
        str(ds.attrs.get("mode", "")),
        str(path),
        command,
    )


def _number(text: str) -> float:
    return float("nan") if text.strip() == "" else float(text)


def _read_csv(path: Path) -> Measurement:
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        raise ValueError(f"{path}: empty file; expected the header {', '.join(CSV_COLUMNS[:3])}, ..., p12")
    header = [h.strip() for h in rows[0]]
    present = {k: [c for c in names if c in header] for k, (_, names) in _COMMAND.items()}
    command = _which(path, present, "no column p1 .. p12 (MPa) or v1 .. v12 (V)")
    columns = ["time_s", *NODE_COLUMNS, *_COMMAND[command][1]]
    missing = [c for c in columns if c not in header]
    if missing:
        raise ValueError(f"{path}: no column {', '.join(missing[:6])}{' ...' if len(missing) > 6 else ''}")
    dup = sorted({h for h in header if header.count(h) > 1 and h in columns})
    if dup:
        raise ValueError(f"{path}: column {', '.join(dup)} appears twice")
    col = [header.index(c) for c in columns]
    data = np.empty((len(rows) - 1, len(columns)))
    for i, row in enumerate(rows[1:]):
        if len(row) != len(header):
            raise ValueError(f"{path}: line {i + 2} has {len(row)} fields, the header {len(header)}")
        try:
            data[i] = [_number(row[c]) for c in col]
        except ValueError:
            k = next(k for k, c in enumerate(col) if not _is_number(row[c]))
            raise ValueError(f"{path}: line {i + 2}, column {columns[k]}: {row[col[k]]!r} is not a number") from None
    n = 1 + len(NODE_COLUMNS)
    nodes = data[:, 1:n].reshape(-1, topo.N_NODES, 3)
    return Measurement(data[:, 0], nodes, data[:, n:], "", str(path), command)


def _is_number(text: str) -> bool:
    try:
        _number(text)
        return True
    except ValueError:
        return False


def write_measured_csv(m: Measurement, path: str | os.PathLike) -> Path:
    """Write m as a motion-capture CSV (`CSV_COLUMNS`, or `VOLTAGE_CSV_COLUMNS` for a run in
    volts; NaN as an empty cell) atomically."""
    from ... import atomic

    lines = [",".join(VOLTAGE_CSV_COLUMNS if m.command == "voltage" else CSV_COLUMNS)]
    flat = np.concatenate([m.t[:, None], m.nodes.reshape(len(m.t), -1), m.pressure], axis=1)
    for row in flat:
        lines.append(",".join("" if np.isnan(v) else repr(float(v)) for v in row))
    return atomic.write_text(path, "\n".join(lines) + "\n")
