"""The checks' results in words: one `Verdict` row per verdict (what is claimed, what was measured
with units, the paper's value or the goal, the status) and the per-pair tables of summary.md.
Lengths are written in mm, pressures in MPa. `validation.report` lays them out as Markdown, HTML
and the text variables of validation.nc.

Here: which words each check's result gets. The words themselves are in `words_workspace`
(checks 1, 2, 3, 5) and `words_ground` (4, 6), made of the pieces of `words` (`Verdict`,
`Table`, `mm`, `label`, `edge_label`), which this module passes on."""

from __future__ import annotations

from .averaging import AveragingResult, averaging_verdicts
from .checks import MappingResult, StaticsResult, TimestepResult
from .common import CheckError, NotEvaluated, Result
from .grounded import GroundedResult
from .paper import PaperResult
from .prototype_check import PrototypeResult, prototype_table, prototype_verdicts
from .runs import RunsResult
from .words import Table, Verdict, edge_label, label, mm
from .words_ground import grounded_table, grounded_verdicts, runs_table, runs_verdicts
from .words_workspace import mapping_verdicts, paper_verdicts, statics_verdicts, timestep_verdicts

__all__ = ["verdicts", "tables", "Verdict", "Table", "mm", "label", "edge_label"]


def verdicts(result: Result) -> list[Verdict]:
    """The verdict rows of one check's result, in the order of its `status`."""
    if isinstance(result, CheckError):
        return [
            Verdict(
                result.number, f"{result.name} check", f"error: {result.error}", "runs", result.status[result.number]
            )
        ]
    if isinstance(result, NotEvaluated):
        return [Verdict(n, f"{result.name} check", result.reason, "-", s) for n, s in result.status.items()]
    for kind, words in (
        (PaperResult, paper_verdicts),
        (StaticsResult, statics_verdicts),
        (MappingResult, mapping_verdicts),
        (GroundedResult, grounded_verdicts),
        (TimestepResult, timestep_verdicts),
        (RunsResult, runs_verdicts),
        (AveragingResult, averaging_verdicts),
        (PrototypeResult, prototype_verdicts),
    ):
        if isinstance(result, kind):
            return words(result)
    raise TypeError(f"no wording for a {type(result).__name__}")


def tables(result: Result) -> list[Table]:
    """The extra tables (title, header, rows) of one check's result: check 4's per-pair table,
    check 6's per-run table, check 8's voltages."""
    if isinstance(result, GroundedResult):
        return [grounded_table(result)]
    if isinstance(result, RunsResult) and result.runs:
        return [runs_table(result)]
    if isinstance(result, PrototypeResult):
        return [prototype_table(result)]
    return []
