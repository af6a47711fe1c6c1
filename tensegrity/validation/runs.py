"""Check 6: the workflow's demonstration runs (results/locomotion/{run}.nc) arrived.

A run that does not arrive (outcome `stuck`, `no_contact`, `step_limit`, `off_terrain`,
`sim_error`) is a failed check, not a stopped workflow: the run's file is the evidence of what
went wrong (`io.run_formats.not_arrived` reads the outcomes of run files for the Snakefile's
`onsuccess`warning. Numbers and statuses only; `validation.summary` words them; `io.run_formats.read_runs`
reads the files.
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
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


__all__ = ["ARRIVED", "RunsResult", "check_runs"]
