"""Digests of what a netCDF file's reader must find (docs/datasets.md, "Checksums").

`datasets.write` gives every variable (coordinates too) an attribute `digest`, the SHA-256 of its
decoded content in a canonical form, and the file a global `digest` over its global attributes,
its coordinate names and every variable's name and digest; `datasets.read` recomputes them from
what it decoded and refuses a file where one differs. HDF5's Fletcher-32 filter only covers the
chunks it reads: a damaged chunk index makes HDF5 read none and return the fill value, which only a
check of the decoded values catches.

Canonical form (version 1; the value is "sha256:" and 64 hex digits): the tag below, then the
dimension names, then the values, then the attributes sorted by name (the `digest` attribute
itself left out), each piece a length-prefixed record (8-byte little-endian length) of a class
and its bytes. Values: the shape, then the elements in C order, as little-endian int64 (bool,
int, uint), float64 with every NaN as the one canonical quiet NaN, complex128 likewise, or
length-prefixed UTF-8 (strings; bytes as they are). Attribute values are flattened (netCDF reads a
one-element attribute back as a scalar).
"""

from __future__ import annotations

import hashlib
from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np
import xarray as xr

__all__ = ["ATTR", "variable_digest", "dataset_digest", "mismatches"]

ATTR = "digest"
_TAG = b"tensegrity digest 1"
_PREFIX = "sha256:"


def _record(h: Any, kind: bytes, payload: bytes) -> None:
    for part in (kind, payload):
        h.update(len(part).to_bytes(8, "little"))
        h.update(part)


def _canonical(values: Any) -> tuple[bytes, bytes]:
    """(class, bytes) of an array's values, shape included."""
    a = np.asarray(values)
    shape = np.asarray(a.shape, dtype="<i8").tobytes()
    k = a.dtype.kind
    if k in "USO":
        strings = (x if isinstance(x, bytes) else str(x).encode("utf-8") for x in a.ravel(order="C"))
        return b"str", shape + b"".join(len(s).to_bytes(8, "little") + s for s in strings)
    if k in "biu":
        return b"int", shape + np.ascontiguousarray(a, dtype="<i8").tobytes()
    if k in "fc":
        b = np.ascontiguousarray(a, dtype="<c16" if k == "c" else "<f8")
        flat = b.view("<f8")
        if np.isnan(flat).any():
            flat = np.where(np.isnan(flat), np.float64(np.nan), flat).astype("<f8")
        return (b"complex" if k == "c" else b"float"), shape + flat.tobytes()
    if k in "Mm":
        return b"time", shape + np.ascontiguousarray(a.astype(f"{a.dtype.str[:2]}8[ns]").view("<i8")).tobytes()
    raise TypeError(f"no canonical form for values of dtype {a.dtype}")


def _attrs(h: Any, attrs: Mapping) -> None:
    for key in sorted(k for k in attrs if k != ATTR):
        _record(h, b"attr", str(key).encode("utf-8"))
        _record(h, *_canonical(np.ravel(attrs[key])))


def variable_digest(var: xr.Variable) -> str:
    """The digest of a variable: its dimension names, decoded values and attributes."""
    h = hashlib.sha256(_TAG)
    _record(h, b"dims", "\0".join(map(str, var.dims)).encode("utf-8"))
    _record(h, *_canonical(var.values))
    _attrs(h, var.attrs)
    return _PREFIX + h.hexdigest()


def dataset_digest(attrs: Mapping, coords: Iterable[str], digests: Mapping[str, str]) -> str:
    """The digest of a file: its global attributes, coordinate names and variables' digests."""
    h = hashlib.sha256(_TAG)
    _attrs(h, attrs)
    _record(h, b"coords", "\0".join(sorted(map(str, coords))).encode("utf-8"))
    for name in sorted(digests):
        _record(h, str(name).encode("utf-8"), str(digests[name]).encode("utf-8"))
    return _PREFIX + h.hexdigest()


def mismatches(ds: xr.Dataset, *, values: bool = True) -> list[str]:
    """What of `ds` (as decoded from a file) differs from the digests the file carries: a list of
    sentences, empty when all match or when the file carries none (written before digests).
    values=False checks the global digest against the variables' stored digests only (no data
    read: for readers of the attributes)."""
    carried = {n: v.attrs.get(ATTR) for n, v in ds.variables.items()}
    if ATTR not in ds.attrs and not any(carried.values()):
        return []
    out = [f"variable {n!r} carries no {ATTR!r} attribute" for n, d in carried.items() if not d]
    if values:
        for name, var in ds.variables.items():
            found = variable_digest(var)
            if carried[name] and found != carried[name]:
                out.append(f"variable {name!r} does not match its digest (found {found}, recorded {carried[name]})")
    whole = dataset_digest(ds.attrs, ds.coords, carried)
    if ds.attrs.get(ATTR) != whole:
        out.append(
            f"the global attributes or the list of variables do not match the file's digest "
            f"(found {whole}, recorded {ds.attrs.get(ATTR)})"
        )
    return out
