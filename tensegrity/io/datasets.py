"""netCDF I/O for every stage (docs/design.md §5): checked, CF-attributed, atomic, reproducible.

`write` refuses a dataset whose variables lack `units` or `long_name` or hold NaN/inf, stamps the
global attributes of the contract (`title`, `source`, `history`, `Conventions`, `config`) and
writes through a temporary file renamed into place, so an interrupted job never leaves a
complete-looking file. Nothing time-dependent is written: the same dataset and configuration give
a byte-identical file, which is what lets re-runs be compared.
"""
from __future__ import annotations

import json
from importlib import metadata as _metadata
import os
import secrets
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike

from .config import to_json

try:
    __version__ = _metadata.version("tensegrity")
except _metadata.PackageNotFoundError:  # a source tree that was never installed
    __version__ = "0+unknown"

__all__ = ["write", "read", "provenance_config", "CONVENTIONS"]

CONVENTIONS = "CF-1.10"
_STRING_KINDS = "USO"  # unicode, bytes, object (strings as read back by xarray)


def _check(ds: xr.Dataset, allow_nan: Iterable[str]) -> None:
    """Raise ValueError naming the first variable without units/long_name or with NaN/inf."""
    allow = set(allow_nan)
    unknown = allow - set(ds.variables)
    if unknown:
        raise ValueError(f"allow_nan names no variable of the dataset: {', '.join(sorted(unknown))}")
    for name, var in ds.variables.items():
        if var.dtype.kind in _STRING_KINDS:
            continue
        for attr in ("units", "long_name"):
            if not str(var.attrs.get(attr, "")).strip():
                raise ValueError(f"variable {name!r} has no {attr!r} attribute")
        if var.dtype.kind in "fc" and name not in allow and not np.all(np.isfinite(var.values)):
            n = int(np.size(var.values) - np.count_nonzero(np.isfinite(var.values)))
            raise ValueError(f"variable {name!r} holds {n} non-finite value(s) (NaN or inf); "
                             f"pass allow_nan=[{name!r}] if they are meaningful")


def write(ds: xr.Dataset, path: str | os.PathLike, cfg: dict, title: str, *,
          stage: str | None = None, allow_nan: Iterable[str] = ()) -> Path:
    """Check `ds` and write it to `path` (netCDF4) atomically; returns the path.

    cfg: the resolved configuration, stored as the JSON attribute `config`.
    title: the `title` attribute, a sentence saying what the file holds.
    stage: the producing stage (e.g. "sweep"), recorded in `history`.
    allow_nan: float variables allowed to hold NaN/inf (e.g. where a quantity is undefined).
    Existing `history` of `ds` is kept, the new line appended; `ds` itself is not modified.
    If writing fails, the temporary file is removed and an existing `path` is left untouched.
    """
    _check(ds, allow_nan)
    path = Path(path)
    line = f"created by tensegrity {__version__}" + (f" {stage}" if stage else "")
    old = str(ds.attrs.get("history", "")).strip()
    out = ds.copy(deep=False)
    out.attrs = {**ds.attrs, "title": title, "source": f"tensegrity {__version__}",
                 "history": f"{old}\n{line}" if old else line, "Conventions": CONVENTIONS,
                 "config": to_json(cfg)}
    path.parent.mkdir(parents=True, exist_ok=True)
    # Same directory, so that os.replace is an atomic rename on one file system; a hidden name
    # that no Snakemake output pattern matches.
    tmp = path.with_name(f".{path.name}.{os.getpid()}.{secrets.token_hex(4)}.tmp")
    try:
        out.to_netcdf(tmp, engine="netcdf4", format="NETCDF4")
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return path


def var(dims: Iterable[str], data: ArrayLike, units: str, long_name: str, **attrs: Any) -> tuple:
    """An xarray variable spec (dims, data, attrs) with the `units` and `long_name` every
    variable of this toolkit carries."""
    return (tuple(dims), np.asarray(data), {"units": units, "long_name": long_name, **attrs})


def write_text(path: str | os.PathLike, text: str) -> Path:
    """Write a text file atomically (a temporary file renamed into place); returns the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.{secrets.token_hex(4)}.tmp")
    try:
        tmp.write_text(text)
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return path


def read(path: str | os.PathLike) -> xr.Dataset:
    """The dataset at `path`, loaded into memory; the file is closed on return."""
    with xr.open_dataset(path, engine="netcdf4") as ds:
        return ds.load()


def strut_length(ds: xr.Dataset | str | os.PathLike) -> float:
    """Strut length S (m) a dataset was made with: its provenance's `params.strut_length`, else
    the default of the configuration schema (a dataset written without a configuration)."""
    from .config import defaults
    try:
        section = provenance_config(ds).get("params") or {}
    except ValueError:  # no `config` attribute
        section = {}
    return float(section.get("strut_length", defaults()["params"]["strut_length"]))


def provenance_config(ds: xr.Dataset | str | os.PathLike) -> dict:
    """The resolved configuration a dataset (or the file at a path) was produced with."""
    if not isinstance(ds, xr.Dataset):
        with xr.open_dataset(ds, engine="netcdf4") as f:
            attrs = dict(f.attrs)
    else:
        attrs = ds.attrs
    if "config" not in attrs:
        raise ValueError("dataset has no 'config' attribute (not written by tensegrity.datasets)")
    return json.loads(attrs["config"])
