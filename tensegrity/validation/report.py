"""The words of the workspace validation: the verdict table and the per-pair tables of every
check (`validation.summary`), laid out as summary.md and summary.html (`validation.pages`). The
checks (`validation.checks`) return numbers; `io.validation_formats` lays them out as
validation.nc; `stages.validate` reads and writes the files."""

from __future__ import annotations

from collections.abc import Sequence

from . import pages, summary
from .common import Result

TITLE = "Validation of the kinematic workspace and the demonstration runs"


def summary_tables(results: Sequence[Result]) -> list[summary.Table]:
    """The verdict table of every check, then the checks' extra tables: (title, header, rows)."""
    tables = [pages.verdict_table([r for res in results for r in summary.verdicts(res)], "paper / goal")]
    for res in results:
        tables += summary.tables(res)
    return tables


def counts(results: Sequence[Result]) -> str:
    """'n of m checks passed, ...' over every verdict of `results` (`pages.counts`)."""
    return pages.counts([s for r in results for s in r.status.values()])
