"""Check 6: the workflow's demonstration runs (results/locomotion/{run}.nc) arrived.

A run that does not arrive (outcome `stuck`, `no_contact`, `step_limit`, `off_terrain`,
`sim_error`) is a failed check, not a stopped workflow: the run's file is the evidence of what
went wrong (`io.formats.run.not_arrived` reads the outcomes of run files for the Snakefile's
`onsuccess` warning). Numbers and statuses only; `validation.summary` words them;
`io.formats.run.read_run_summaries` reads the files.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from .common import FAIL, PASS, SKIP, Result

ARRIVED = "arrived"


@dataclass(frozen=True)
class RunSummary:
    """What check 6 reads of a demonstration run (results/locomotion/{run}.nc, read by
    `io.formats.run.read_run_summaries`): its outcome ('arrived', 'stuck', ...) and message, the
    number of rolls, the goal (3,) m (NaN: a run over given edges, such as `paper`) and the
    final CoG (3,) m (NaN: no sample), world frame."""

    outcome: str
    message: str
    rolls: int
    goal: np.ndarray
    final_cog: np.ndarray

    @property
    def distance(self) -> float:
        """Horizontal distance (m) of the final CoG from the goal; NaN without a goal or a sample."""
        goal, cog = np.asarray(self.goal, float), np.asarray(self.final_cog, float)
        if not (np.isfinite(goal[:2]).all() and np.isfinite(cog[:2]).all()):
            return float("nan")
        return float(np.linalg.norm(cog[:2] - goal[:2]))


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


def check_runs(runs: Mapping[str, RunSummary]) -> RunsResult:
    """Every demonstration run (name -> its `RunSummary`, results/locomotion/{run}.nc) arrived:
    its outcome is 'arrived'. Not evaluated if there are no runs."""
    names = tuple(str(k) for k in runs)
    outcome = tuple(r.outcome for r in runs.values())
    message = tuple(r.message for r in runs.values())
    rolls = np.array([r.rolls for r in runs.values()], np.int64)
    distance = np.array([r.distance for r in runs.values()], float)
    st = SKIP if not names else PASS if all(o == ARRIVED for o in outcome) else FAIL
    return RunsResult(status={"6": st}, runs=names, outcome=outcome, message=message, rolls=rolls, distance=distance)


__all__ = ["ARRIVED", "RunSummary", "RunsResult", "check_runs"]
