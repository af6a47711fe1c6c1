"""netCDF I/O for every stage (docs/design.md §5): checked, CF-attributed, atomic, reproducible.

`write` refuses a dataset whose variables lack `units` or `long_name` or hold NaN/inf, stamps the
global attributes of the contract (`title`, `source`, `history`, `Conventions`, `config`) and
writes through a temporary file renamed into place, so an interrupted job never leaves a
complete-looking file (`tensegrity.atomic`: temporaries a killed writer left behind are removed
by the next write of the same file). Nothing time-dependent is written: the same dataset and configuration give
a byte-identical file, which is what lets re-runs be compared.

Every numeric array variable is stored with the HDF5 Fletcher-32 checksum filter, and every
variable and the file carry a `digest` attribute of their decoded content (`io.digests`): `read`
checks both, so a file whose data or metadata bytes were damaged fails to read (`read` raises
`CorruptDatasetError`, naming the file and the variable) instead of returning wrong numbers or
the fill value. Coordinate variables carry no `_FillValue` (CF 2.5.1).
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike

from .. import atomic
from ..version import __version__
from . import digests

__all__ = [
    "write",
    "read",
    "provenance_config",
    "robot_value",
    "strut_length",
    "strut_radius",
    "geometry_vars",
    "CONVENTIONS",
    "CorruptDatasetError",
    "read_attrs",
]

CONVENTIONS = "CF-1.10"
_STRING_KINDS = "USO"  # unicode, bytes, object (strings as read back by xarray)


class CorruptDatasetError(ValueError):
    """A netCDF file that cannot be read: corrupted (checksum or digest mismatch), truncated or not
    netCDF. The message names the file (and the variable, for a digest mismatch)."""


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
            raise ValueError(
                f"variable {name!r} holds {n} non-finite value(s) (NaN or inf); "
                f"pass allow_nan=[{name!r}] if they are meaningful"
            )


def write(
    ds: xr.Dataset,
    path: str | os.PathLike,
    cfg: dict,
    title: str,
    *,
    stage: str | None = None,
    allow_nan: Iterable[str] = (),
) -> Path:
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
    out.attrs = {
        **ds.attrs,
        "title": title,
        "source": f"tensegrity {__version__}",
        "history": f"{old}\n{line}" if old else line,
        "Conventions": CONVENTIONS,
        "config": to_json(cfg),
    }
    _stamp(out)
    with atomic.replacing(path) as tmp:
        out.to_netcdf(tmp, engine="netcdf4", format="NETCDF4", encoding=_encoding(out))
    return path


def _stamp(out: xr.Dataset) -> None:
    """Give every variable of `out` (a shallow copy: its attribute dicts are its own) and `out`
    itself the `digest` attribute of what a reader will decode (`io.digests`)."""
    found = {}
    for name, v in out.variables.items():
        v.attrs = {k: a for k, a in v.attrs.items() if k != digests.ATTR}
        v.attrs[digests.ATTR] = found[name] = digests.variable_digest(v)
    out.attrs.pop(digests.ATTR, None)
    out.attrs[digests.ATTR] = digests.dataset_digest(out.attrs, out.coords, found)


def _verified(ds: xr.Dataset, path: str | os.PathLike, *, values: bool = True) -> xr.Dataset:
    """`ds`, read from `path`, with its `digest` attributes checked and removed; raises
    `CorruptDatasetError` naming the file and what differs."""
    wrong = digests.mismatches(ds, values=values)
    if wrong:
        raise CorruptDatasetError(
            f"dataset {os.fspath(path)!r} is corrupted: {'; '.join(wrong)} (the values read are not "
            "those written - damaged bytes, e.g. in an HDF5 chunk index -; re-create it)"
        )
    for v in ds.variables.values():
        v.attrs.pop(digests.ATTR, None)
    ds.attrs.pop(digests.ATTR, None)
    return ds


def _encoding(ds: xr.Dataset) -> dict:
    """Per-variable netCDF encoding: Fletcher-32 checksums on every numeric array (chunked
    storage; scalars and variable-length strings cannot carry the filter), no `_FillValue` on
    coordinate variables (CF 2.5.1: they hold no missing values, `_check` ensures it)."""
    enc = {}
    for name, v in ds.variables.items():
        e: dict[str, Any] = {}
        if v.ndim and v.dtype.kind not in _STRING_KINDS:
            e.update(fletcher32=True, contiguous=False)
        if name in ds.dims and v.dims == (name,):
            e["_FillValue"] = None
        enc[name] = e
    return enc


def var(dims: Iterable[str], data: ArrayLike, units: str, long_name: str, **attrs: Any) -> tuple:
    """An xarray variable spec (dims, data, attrs) with the `units` and `long_name` every
    variable of this toolkit carries."""
    return (tuple(dims), np.asarray(data), {"units": units, "long_name": long_name, **attrs})


def read(path: str | os.PathLike) -> xr.Dataset:
    """The dataset at `path`, loaded into memory; the file is closed on return.

    Raises FileNotFoundError if there is no file, and `CorruptDatasetError` (a ValueError) naming
    the file if it cannot be read: a checksum mismatch (corrupted data), a truncated file, not
    netCDF, or values or attributes that differ from the `digest` the file records for them (the
    variable is named; a file without digests, written before them, is read unchecked). The
    `digest` attributes are removed from the result. `ds.encoding["source"]` of it is the path."""
    if not Path(path).is_file():
        raise FileNotFoundError(f"no dataset file {os.fspath(path)!r}")
    try:
        with xr.open_dataset(path, engine="netcdf4") as ds:
            out = ds.load()
    except (RuntimeError, OSError, ValueError, KeyError, IndexError) as e:
        raise CorruptDatasetError(
            f"cannot read dataset {os.fspath(path)!r}: {type(e).__name__}: {e} (the file is corrupted "
            "- an HDF5 checksum or structure error -, truncated or not netCDF; re-create it)"
        ) from e
    out.encoding["source"] = os.fspath(path)
    return _verified(out, path)


def read_attrs(path: str | os.PathLike) -> dict:
    """The global attributes of the file at `path`, without reading its data: checked against the
    file's digest (which covers them and every variable's name and recorded digest), else
    `CorruptDatasetError`; FileNotFoundError if there is no file."""
    if not Path(path).is_file():
        raise FileNotFoundError(f"no dataset file {os.fspath(path)!r}")
    try:
        with xr.open_dataset(path, engine="netcdf4") as ds:
            return dict(_verified(ds, path, values=False).attrs)
    except (RuntimeError, OSError, ValueError, KeyError, IndexError) as e:
        if isinstance(e, CorruptDatasetError):
            raise
        raise CorruptDatasetError(f"cannot read dataset {os.fspath(path)!r}: {type(e).__name__}: {e}") from e


def robot_value(ds: xr.Dataset | str | os.PathLike, name: str) -> float:
    """A robot parameter (`params` key `name`, SI) a dataset was made with: its scalar variable
    `name` (files written since the geometry is stored in them), else its provenance's
    `params.<name>` (files written before), else the configuration schema's default."""
    if isinstance(ds, xr.Dataset) and name in ds.variables and ds[name].ndim == 0:
        return float(ds[name].values)
    if not isinstance(ds, xr.Dataset):
        ds = read(ds)  # checked against its digests
        if name in ds.variables and ds[name].ndim == 0:
            return float(ds[name].values)
    from .config import defaults

    try:
        section = provenance_config(ds).get("params") or {}
    except ValueError:  # no `config` attribute
        section = {}
    return float(section.get(name, defaults()["params"][name]))


def strut_length(ds: xr.Dataset | str | os.PathLike) -> float:
    """Strut length S (m) a dataset was made with (`robot_value`)."""
    return robot_value(ds, "strut_length")


def strut_radius(ds: xr.Dataset | str | os.PathLike) -> float:
    """Strut radius r (m, the contact sphere's) a dataset was made with (`robot_value`)."""
    return robot_value(ds, "strut_radius")


def geometry_vars(strut_length: float, strut_radius: float | None = None) -> dict:
    """The robot's geometry as scalar variables of a file (read back by `robot_value`)."""
    out = {"strut_length": var((), float(strut_length), "m", "strut length S of the robot")}
    if strut_radius is not None:
        out["strut_radius"] = var((), float(strut_radius), "m", "strut radius r of the robot (contact sphere radius)")
    return out


def provenance_config(ds: xr.Dataset | str | os.PathLike) -> dict:
    """The resolved configuration a dataset (or the file at a path) was produced with."""
    where = "dataset" if isinstance(ds, xr.Dataset) else f"{ds}"
    if isinstance(ds, xr.Dataset):
        attrs = ds.attrs
    else:
        try:
            attrs = read_attrs(ds)  # the attributes only, not the data; CorruptDatasetError if damaged
        except OSError as e:  # no file: a ValueError too, as for any file that cannot be read
            raise ValueError(f"cannot read dataset '{ds}': {e}") from None
    if "config" not in attrs:
        raise ValueError(f"{where} has no 'config' attribute (not written by tensegrity.io.datasets)")
    try:
        return json.loads(attrs["config"])
    except json.JSONDecodeError as e:
        raise ValueError(f"{where}: its 'config' attribute is not valid JSON: {e}") from None


def _json_default(obj: Any) -> Any:
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"config value of type {type(obj).__name__} is not JSON serialisable")


def to_json(cfg: Mapping) -> str:
    """The configuration as JSON with sorted keys, for provenance attributes; deterministic.
    Raises ValueError on NaN or infinity (validate first)."""
    from .schema_checks import plain

    return json.dumps(plain(cfg), sort_keys=True, allow_nan=False, default=_json_default)
