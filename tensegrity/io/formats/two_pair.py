"""The two-pair workspace files (issue 10; docs/datasets.md, "Two-pair workspace"): builders,
the reader the planner relies on, and the numpy-only evaluator of the fitted surfaces.

- results/two_pair/{contact}.nc: every combination on the canonical face (`contact_dataset`),
  read by `read_contacts` (datasets) and `read_two_pair_nominals` (the validation's typed values).
- results/workspace_two_pair.nc: all 20 faces (`workspace_dataset`), read by `read_two_pair`
  (the planner) and `read_two_pair_grid` (the validation).
- results/curves/two_pair.json: fitted surfaces (`surfaces_document`, `evaluate_surface`).

Grid dimensions: `level_a` (the first pair's level) and `level_b` (the second's), both indexing
the same levels, given in MPa by the data variables `pressure_a` and `pressure_b`. (A coordinate
in pressure units would be taken for an atmospheric vertical axis by the CF checker.)
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike

from ...physics import topology as topo
from ...workspace.nominal import TwoPairNominal
from .. import datasets
from . import actuation
from .common import coords, rest_vars

CONTACT_FILE = "{contact}.nc"
ALLOW_NAN = ["cog", "cog_std", "support", "margin", "tip_pressure", "tip_boundary"]
CONTACT_ALLOW_NAN = [*ALLOW_NAN, "averaging_error"]  # results/two_pair/{contact}.nc
_GRID = ("level_a", "level_b")


def _grid_vars(lead: tuple[str, ...], ws: Mapping[str, np.ndarray]) -> dict:
    var = datasets.var
    out = {
        "cog": var((*lead, *_GRID, "axis"), ws["cog"], "m", "nominal centre of gravity in the face's support frame"),
        "support": var(
            (*lead, *_GRID, "corner", "axis"),
            ws["support"],
            "m",
            "deformed support triangle in the face's support frame",
        ),
        "margin": var(
            (*lead, *_GRID),
            ws["margin"],
            "m",
            "signed distance of the CoG projection to the support triangle boundary (positive inside)",
        ),
        "tip_pressure": var(
            lead,
            ws["tip_pressure"],
            "MPa",
            "least equal pressure of both pairs at which the CoG projection leaves the triangle "
            "(NaN: never or not available)",
        ),
        "tip_edge": var(
            (*lead, "end"),
            ws["tip_edge"],
            "1",
            "nodes of the edge crossed at the first equal-pressure grid point outside (0: none)",
        ),
        "tip_boundary": var(
            (*lead, "level_a"),
            ws["tip_boundary"],
            "MPa",
            "least pressure of the second pair at which the CoG projection leaves the triangle, "
            "the first held at pressure_a (NaN: never)",
        ),
        "staircase_pairs": var(
            (*lead, "member"),
            ws["staircase"],
            "1",
            "pairs in the order of the grid axes of the staircase the numbers come from (0: none)",
        ),
    }
    return out


def _coords(levels: ArrayLike) -> dict:
    P = len(levels)
    c = coords()
    c["combo"] = ("combo", np.arange(1, 67), {"units": "1", "long_name": "combination number (row of combo_pairs)"})
    c["member"] = ("member", [1, 2], {"units": "1", "long_name": "member of the combination"})
    c["end"] = ("end", [1, 2], {"units": "1", "long_name": "edge end"})
    for g in _GRID:
        c[g] = (
            g,
            np.arange(1, P + 1),
            {
                "units": "1",
                "long_name": f"index of the pressure level of the {'first' if g == 'level_a' else 'second'} pair",
            },
        )
    return c


def _level_vars(levels: ArrayLike, combos: ArrayLike) -> dict:
    var = datasets.var
    return {
        "pressure_a": var(("level_a",), levels, "MPa", "muscle pressure of the first pair of the combination"),
        "pressure_b": var(("level_b",), levels, "MPa", "muscle pressure of the second pair of the combination"),
        "combo_pairs": var(
            ("combo", "member"), combos, "1", "actuator pair numbers of the combination (first < second)"
        ),
    }


def contact_dataset(
    levels: ArrayLike,
    combos: ArrayLike,
    ws: Mapping[str, np.ndarray],
    swept: ArrayLike,
    cog_std: np.ndarray,
    attrs: dict,
    strut_length: float,
) -> xr.Dataset:
    """results/two_pair/{contact}.nc: the 66 combinations on one canonical face. ws as
    `workspace.two_pair.map_workspace` gives for one face (cog (66, P, P, 3), ...); swept (66,)
    1 where the combination was simulated (else mapped by the face's stabiliser); cog_std
    (66, P, P, 3) m the oscillation spread of the swept ones (NaN for the mapped), and
    ws["averaging_error"] (66, P, P) m their estimated averaging error (`workspace.nominal.
    averaging_error`; all NaN if ws lacks it); the robot's strut length and rest state on the
    face (`formats.rest_vars`)."""
    var = datasets.var
    data = _grid_vars(("combo",), ws) | _level_vars(levels, combos)
    data["swept"] = var(
        ("combo",),
        np.asarray(swept, np.int8),
        "1",
        "1: simulated, 0: mapped from a simulated combination by the face's stabiliser",
    )
    data["cog_std"] = var(
        ("combo", *_GRID, "axis"),
        cog_std,
        "m",
        "standard deviation of the CoG over the grid point's hold (oscillation; NaN: mapped)",
    )
    err = ws.get("averaging_error", np.full(np.shape(cog_std)[:-1], np.nan))
    data["averaging_error"] = var(
        ("combo", *_GRID),
        err,
        "m",
        "estimated error of the nominal CoG from the oscillation left in the grid point's window: a quarter of "
        "the range of the mean CoG over all half-length sub-windows (NaN: mapped)",
    )
    data |= rest_vars(strut_length, int(attrs["face"]))
    return xr.Dataset(data, coords=_coords(levels), attrs=attrs)


def workspace_dataset(
    levels: ArrayLike, combos: ArrayLike, ws: Mapping[str, np.ndarray], attrs: dict, strut_length: float
) -> xr.Dataset:
    """results/workspace_two_pair.nc: `workspace.two_pair.map_workspace` on all 20 faces, with
    the robot's strut length and rest state on every face (`formats.rest_vars`)."""
    var = datasets.var
    data = _grid_vars(("face", "combo"), ws) | _level_vars(levels, combos)
    data["face_nodes"] = var(
        ("face", "corner"), topo.FACES + 1, "1", "node numbers of the face's corners (support-frame corner order)"
    )
    data["reference_corner"] = var(
        ("face",), topo.FACE_REFERENCE + 1, "1", "corner of the reference vertex (the support frame's +y)"
    )
    data |= rest_vars(strut_length, np.arange(1, topo.N_FACES + 1))
    c = _coords(levels) | {"face": ("face", np.arange(1, topo.N_FACES + 1), {"units": "1", "long_name": "face number"})}
    return xr.Dataset(data, coords=c, attrs=attrs)


def read_contacts(paths: Sequence[str | os.PathLike]) -> tuple[np.ndarray, dict[str, xr.Dataset]]:
    """The two-pair contact files (results/two_pair/{contact}.nc): their common levels (P,) MPa
    and the datasets by contact case; ValueError if none is given or their levels differ."""
    src = {str(ds.attrs["contact"]): ds for ds in (datasets.read(p) for p in paths)}
    levels = [ds["pressure_a"].values for ds in src.values()]
    if not levels or any(not np.array_equal(lv, levels[0]) for lv in levels):
        raise ValueError("the two-pair contact files were swept at different levels (or none is given)")
    return levels[0], src


def two_pair_nominal(ds: xr.Dataset) -> TwoPairNominal:
    """The `TwoPairNominal` of a two-pair contact dataset (results/two_pair/{contact}.nc)."""
    return TwoPairNominal(
        str(ds.attrs["contact"]),
        int(ds.attrs["face"]),
        np.asarray(ds["pressure_a"].values, float),
        ds["cog"].transpose("combo", *_GRID, "axis").values,
        ds["tip_pressure"].values,
        ds["averaging_error"].transpose("combo", *_GRID).values if "averaging_error" in ds else None,
    )


def read_two_pair_nominals(paths: Sequence[str | os.PathLike]) -> dict[str, TwoPairNominal]:
    """The two-pair contact files by contact case (`read_contacts`) as `TwoPairNominal`s."""
    return {c: two_pair_nominal(ds) for c, ds in read_contacts(paths)[1].items()}


def read_two_pair_grid(path: str | os.PathLike) -> tuple[np.ndarray, np.ndarray]:
    """results/workspace_two_pair.nc as the validation compares it, in the file's combination
    order (the rows of `workspace.two_pair.COMBOS`): cog (20, 66, P, P, 3) m in each face's
    support frame and staircase_pairs (20, 66, 2), the pairs in the order of the grid axes of
    the staircase the numbers come from (0: none)."""
    ds = datasets.read(path)
    return (
        ds["cog"].transpose("face", "combo", *_GRID, "axis").values,
        ds["staircase_pairs"].transpose("face", "combo", "member").values,
    )


def read_two_pair(path: str | os.PathLike) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """results/workspace_two_pair.nc as arrays: combos (C, 2) int, 1-based, rows sorted
    ascending; levels (P,) MPa; cog (20, C, P, P, 3) m and support (20, C, P, P, 3, 3) m in each
    face's support frame (docs/design.md §2): cog[f, c, i, j] is the nominal CoG on face f+1
    with pair combos[c, 0] at levels[i] and combos[c, 1] at levels[j]; NaN where not available.
    A file without these variables, or with levels not strictly increasing, raises ValueError
    naming it."""
    ds = datasets.read(path)
    try:
        combos = np.asarray(ds["combo_pairs"].transpose("combo", "member").values, int)
        levels = np.asarray(ds["pressure_a"].values, float)
        cog = ds["cog"].transpose("face", "combo", *_GRID, "axis").values
        support = ds["support"].transpose("face", "combo", *_GRID, "corner", "axis").values
    except (KeyError, ValueError) as e:
        raise ValueError(f"{os.fspath(path)!r} is not a two-pair workspace: {e}") from e
    if not np.array_equal(levels, ds["pressure_b"].values) or np.any(np.diff(levels) <= 0):
        raise ValueError(f"{os.fspath(path)!r}: levels must be the same for both pairs and strictly increasing")
    if combos.shape[1] != 2 or np.any(combos[:, 0] >= combos[:, 1]):
        raise ValueError(f"{os.fspath(path)!r}: combo_pairs must hold two increasing pair numbers per row")
    order = np.lexsort((combos[:, 1], combos[:, 0]))
    return combos[order], levels, cog[:, order], support[:, order]


# ------------------------------------------------------------ results/curves/two_pair.json


def surfaces_document(contacts: Mapping[str, tuple], config: dict | None = None, kind: str = "pneumatic") -> dict:
    """results/curves/two_pair.json: `contacts` maps a contact case to (face_nodes (3,), combos
    (n, 2), surfaces [n][3] of `workspace.surfaces.fit_surface` dicts, per axis x, y, z);
    `config`: the configuration the surfaces were made with (`io.provenance`); `kind`: the
    actuator (twisted_string: volts, `actuation.document`)."""
    doc = {
        "units": {"pressure": "MPa", "cog": "m"},
        "frame": "support frame of the contact face (docs/design.md section 2)",
        "evaluate": "pa: pressure (MPa) of the first pair of the combination (the smaller number), pb of "
        "the second; valid for pmin <= pa, pb <= pmax. kind polynomial: value = sum over k of coefs[k] * "
        "pa**powers[k][0] * pb**powers[k][1]. kind spline (piecewise polynomial, degree [ka, kb]): find i "
        "with breaks_a[i] <= pa < breaks_a[i+1] and j likewise in breaks_b (clamp to the end pieces); "
        "value = sum over k, l of coefs[i][j][k][l] * (pa - breaks_a[i])**(ka - k) * (pb - breaks_b[j])**(kb - l)",
        "max_residual": "per surface, the largest |value(pa, pb) - nominal CoG| over the swept grid points (m); "
        "a polynomial whose residual would exceed 0.1 mm is replaced by the spline interpolating the grid",
        "contacts": {},
    }
    actuation.document(doc, kind)
    if config is not None:
        doc["config"] = config
    for contact, (face_nodes, combos, surfaces) in contacts.items():
        doc["contacts"][contact] = {
            "face_nodes": [int(n) for n in face_nodes],
            "combos": {
                f"{a},{b}": dict(zip("xyz", surfaces[i])) for i, (a, b) in enumerate(np.asarray(combos).tolist())
            },
        }
    return doc


def evaluate_surface(surface: Mapping, pa: ArrayLike, pb: ArrayLike) -> np.ndarray:
    """A fitted surface of two_pair.json at pressures pa, pb (MPa, broadcast): numpy only
    (`workspace.surfaces.evaluate`; a surface without `kind` is a polynomial)."""
    from ...workspace.surfaces import evaluate

    return evaluate(surface, pa, pb)
