"""Check 6: the workflow's demonstration runs (results/locomotion/{run}.nc) arrived.

A run that does not arrive (outcome `stuck`, `no_contact`, `step_limit`, `off_terrain`,
`sim_error`) is a failed check, not a stopped workflow: the run's file is the evidence of what
went wrong. `not_arrived` reads the outcomes of run files for the Snakefile's `onsuccess`
warning. Numbers and statuses only; `validation.summary` words them.
"""
from __future__ import annotations

import os
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .common import FAIL, PASS, SKIP, Result

if TYPE_CHECKING:
    import xarray as xr

ARRIVED = "arrived"


@dataclass(frozen=True)
class RunsResult(Result):
    """Numbers of check 6 on the R demonstration runs `runs` (names, in the order given):
    outcome and message (the run's `outcome` and `message` attributes), rolls (R,) and
    distance (R,) m, the horizontal distance of the final CoG from the goal (NaN for a run over
    given edges, such as `paper`); status of verdict 6 (not evaluated without runs)."""
    runs: tuple[str, ...]
    outcome: tuple[str, ...]
    message: tuple[str, ...]
    rolls: np.ndarray
    distance: np.ndarray

    @property
    def arrived(self) -> np.ndarray:
        """(R,) bool: the run arrived."""
        return np.array([o == ARRIVED for o in self.outcome], bool)


def _distance(ds: xr.Dataset) -> float:
    goal = np.asarray(ds["goal"].values, float) if "goal" in ds else np.full(3, np.nan)
    cog = np.asarray(ds["cog"].values, float) if "cog" in ds else np.empty((0, 3))
    if not np.isfinite(goal[:2]).all() or cog.shape[0] == 0:
        return float("nan")
    return float(np.linalg.norm(cog[-1, :2] - goal[:2]))


def check_runs(runs: Mapping[str, xr.Dataset]) -> RunsResult:
    """Every demonstration run (name -> its dataset, results/locomotion/{run}.nc) arrived:
    its `outcome` attribute is 'arrived'. Not evaluated if there are no runs."""
    names = tuple(str(k) for k in runs)
    outcome = tuple(str(ds.attrs.get("outcome", "unknown")) for ds in runs.values())
    message = tuple(str(ds.attrs.get("message", "")) for ds in runs.values())
    rolls = np.array([int(ds.attrs.get("rolls", 0)) for ds in runs.values()], np.int64)
    distance = np.array([_distance(ds) for ds in runs.values()], float)
    st = SKIP if not names else PASS if all(o == ARRIVED for o in outcome) else FAIL
    return RunsResult(status={"6": st}, runs=names, outcome=outcome, message=message, rolls=rolls,
                      distance=distance)


def run_name(path: str | os.PathLike) -> str:
    """The run a file results/locomotion/{run}.nc holds: its stem."""
    return Path(path).stem


def read_runs(paths: Iterable[str | os.PathLike]) -> dict[str, xr.Dataset]:
    """The run files, name -> dataset (read into memory, the files closed)."""
    from ..io import datasets
    out = {}
    for p in paths:
        ds = datasets.read(p)  # a corrupted or missing file is named in the error
        out[str(ds.attrs.get("run") or run_name(p))] = ds
    return out


def not_arrived(paths: Iterable[str | os.PathLike]) -> list[tuple[str, str, str]]:
    """(run, outcome, message) of every existing run file among `paths` whose run did not
    arrive; files that do not exist are left out (a workflow that did not make them). Reads
    the global attributes only, with netCDF4: the Snakefile's `onsuccess` imports no xarray."""
    import netCDF4
    out = []
    for p in paths:
        if not Path(p).is_file():
            continue
        with netCDF4.Dataset(p) as ds:
            attrs = {k: ds.getncattr(k) for k in ds.ncattrs()}
        outcome, message = str(attrs.get("outcome", "unknown")), str(attrs.get("message", ""))
        if outcome != ARRIVED:
            out.append((str(attrs.get("run") or run_name(p)), outcome, message))
    return out


def warning(paths: Iterable[str | os.PathLike]) -> str:
    """The end-of-workflow warning naming the runs among `paths` that did not arrive ('' if every
    existing run arrived)."""
    bad = not_arrived(paths)
    if not bad:
        return ""
    lines = [f"WARNING: {len(bad)} demonstration run(s) did not arrive (validation check 6 FAILS; "
             f"see results/validation/summary.md):"]
    lines += [f"  {name}: {outcome} ({message})" for name, outcome, message in bad]
    return "\n".join(lines)


__all__ = ["ARRIVED", "RunsResult", "check_runs", "read_runs", "not_arrived", "warning", "run_name"]
