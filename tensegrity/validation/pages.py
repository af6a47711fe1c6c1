"""Verdict tables laid out as Markdown and as a self-contained HTML page: the summary.md and
summary.html of every validation stage (workspace, two-pair workspace, gravity-aware workspace)."""

from __future__ import annotations

import html
from collections.abc import Sequence

from .common import FAIL, INFO, PASS, SKIP
from .words import Table, Verdict

_COLOUR = {PASS.upper(): "#1a7f37", FAIL.upper(): "#cf222e", SKIP.upper(): "#9a6700"}
_STYLE = (
    "body{font-family:sans-serif;font-size:14px;margin:1em}table{border-collapse:collapse;"
    "margin-bottom:1.5em}td,th{border:1px solid #ccc;padding:4px 8px;vertical-align:top;"
    "text-align:left}th{background:#f3f3f3}"
)


def verdict_table(rows: Sequence[Verdict], reference: str = "goal / reference") -> Table:
    """The verdict rows as the table 'Checks' (title, header, rows)."""
    return (
        "Checks",
        ["#", "statement", "measured", reference, "verdict"],
        [[r.id, r.statement, r.measured, r.reference, r.status.upper()] for r in rows],
    )


def counts(statuses: Sequence[str]) -> str:
    """'n of m checks passed, k failed, j not evaluated.' over `statuses` (rows marked INFO are
    numbers, not checks, and are not counted)."""
    st = [s for s in statuses if s != INFO]
    n = {s: st.count(s) for s in (PASS, FAIL, SKIP)}
    text = f"{n[PASS]} of {len(st)} checks passed, {n[FAIL]} failed, {n[SKIP]} not evaluated."
    return text + (f" Rows marked '{INFO}' are numbers, not checks." if INFO in statuses else "")


def markdown(title: str, lead: Sequence[str], tables: Sequence[Table]) -> str:
    """`title`, the paragraphs `lead` and the tables as Markdown."""
    esc = lambda s: str(s).replace("|", "\\|").replace("\n", " ")
    out = [f"# {title}"]
    for par in lead:
        if par:
            out += ["", par]
    for name, header, rows in tables:
        out += ["", f"## {name}", "", "| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
        out += ["| " + " | ".join(esc(x) for x in row) + " |" for row in rows]
    return "\n".join(out) + "\n"


def html_page(title: str, lead: Sequence[str], tables: Sequence[Table]) -> str:
    """The same as a self-contained HTML page (for the Snakemake report); verdicts coloured."""
    parts = [
        f"<!doctype html><html><head><meta charset='utf-8'><title>{html.escape(title)}</title>"
        f"<style>{_STYLE}</style></head><body>",
        f"<h1>{html.escape(title)}</h1>",
    ]
    parts += [f"<p>{html.escape(par)}</p>" for par in lead if par]
    for name, header, rows in tables:
        parts.append(
            f"<h2>{html.escape(name)}</h2><table><tr>" + "".join(f"<th>{html.escape(h)}</th>" for h in header) + "</tr>"
        )
        for row in rows:
            cells = [
                f"<td style='color:{_COLOUR[x]};font-weight:bold'>{html.escape(x)}</td>"
                if x in _COLOUR
                else f"<td>{html.escape(str(x))}</td>"
                for x in row
            ]
            parts.append("<tr>" + "".join(cells) + "</tr>")
        parts.append("</table>")
    return "\n".join(parts + ["</body></html>"]) + "\n"
