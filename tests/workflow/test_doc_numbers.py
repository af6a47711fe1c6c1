"""The numbers README.md, config/README.md and docs/ quote from the default run, checked against
that run (issue 35 item 4).

Each claim is a sentence of a document with its numbers left as fields; the test fills them in
from the run's files, at the precision the document uses, and asserts that the filled sentence
is in the document. A number that drifts (the code changed the run, or the text was edited)
fails here, naming the document and the sentence as it should read.

The default run costs about a minute of wall time on 2 cores, so this is the `slow` tier:
`pytest -m slow tests/workflow/test_doc_numbers.py` runs the default pipeline in a scratch copy;
with `TENSEGRITY_DEFAULT_RUN=DIR` it reads the finished default run in DIR instead (the directory
that holds `results/`; its files must have been made with the default configuration, which the
test checks). Benchmark figures are not run results: docs/benchmarks.md dates each of them with
the commit that recorded it (`test_benchmark_figures_are_dated`, in the default tier).
"""

import math
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from tensegrity.physics.topology import face_number
from tensegrity.workspace.two_pair import combos_of

ROOT = Path(__file__).resolve().parents[2]


def _r(x: float, nd: int) -> str:
    """`x` rounded to `nd` decimals as a document writes it (no trailing '.0' for nd = 0)."""
    return f"{x:.{nd}f}"


def _claims(results: Path) -> list[tuple[str, str]]:
    """(document, sentence) pairs filled in from the run."""
    v = xr.open_dataset(results / "validation" / "validation.nc")
    tp = xr.open_dataset(results / "validation" / "two_pair.nc")
    ws = xr.open_dataset(results / "workspace.nc")
    mm = 1e3
    eq, iso = {"contact": "equilateral"}, {"contact": "isosceles"}
    mig = mm * v["migration"].sel(**eq)
    tip10, tip11 = float(v["tip_pressure"].sel(**eq, pair=10)), float(v["tip_pressure"].sel(**iso, pair=11))
    passed = v["passed"].values
    shift = mm * np.hypot(v["grounded_shift"].sel(axis="x"), v["grounded_shift"].sel(axis="y"))
    g_roll = v["grounded_roll_pressure"]
    f_roll = v["free_roll_pressure"]
    face8 = face_number((9, 10, 12))
    cog = mm * ws["cog"].sel(face=face8, pair=10, pressure=2.4).values
    margin = mm * float(ws["margin"].sel(face=face8, pair=10, pressure=2.4))
    smallest = mm * float(ws["margin"].sel(face=face8, pressure=2.4).min())
    combos = [tuple(c) for c in combos_of(range(1, 13)).tolist()]
    tip_6_10 = float(tp["tip_pressure"].sel(**eq, combo=combos.index((6, 10)) + 1))
    c1 = re.search(
        r"\(#9\+#10, shift ([\d.]+) mm measured, ([\d.]+) mm predicted\)",
        (results / "validation" / "two_pair.md").read_text(),
    )
    cogs = ", ".join(_r(c, 1) for c in cog)
    pr = xr.open_dataset(results / "validation" / "prototype.nc")  # check 8 (issue 31)
    proto, proto_err = pr["lowest_voltage"].values, pr["lowest_voltage_error"].values
    claims = [
        ("README.md", f"With the default configuration {int((passed == 1).sum())} of {passed.size} checks pass."),
        ("README.md", f"move\nthe CoG most ({_r(float(mig.sel(pair=10)), 0)} mm at 2.4 MPa)"),
        ("README.md", f"#4, #6, #7 next ({_r(float(mig.sel(pair=4)), 0)} mm)"),
        ("README.md", f"over edge 10-12 at {_r(tip10, 2)} MPa (paper: 4.2)"),
        ("README.md", f"over 10-11 at {_r(tip11, 2)} MPa,\n{_r(tip11 / tip10, 2)} times #10's pressure"),
        ("README.md", f"equilibrium to {_r(mm * float(v['statics_difference'].max()), 3)} mm"),
        (
            "README.md",
            f"direct simulations to 1e{math.ceil(math.log10(mm * float(v['mapping_difference'].max())))} mm",
        ),
        ("README.md", f"dt/2 to {_r(mm * float(v['timestep_difference'].max()), 4)} mm"),
        ("README.md", f"by up to {_r(float(shift.max()), 1)} mm\n(goal 5 mm)"),
        (
            "README.md",
            f"rolls at\n{_r(float(g_roll.sel(**eq, pair=10)), 1)} MPa where the free workspace says "
            f"{_r(float(f_roll.sel(**eq, pair=10)), 1)} MPa (#11 on (10,11,12): "
            f"{_r(float(g_roll.sel(**iso, pair=11)), 1)} against {_r(float(f_roll.sel(**iso, pair=11)), 1)} MPa)",
        ),
        ("README.md", f"a CoG of\n({cogs}) mm."),
        ("README.md", f"# [ {_r(cog[0], 0)}.  {_r(cog[1], 1)} {_r(cog[2], 1)}]"),
        ("README.md", f"# #9, #10, #12: {_r(tip10, 2)} MPa"),
        ("README.md", f"# [{cogs}] mm"),
        ("README.md", f"# {_r(margin, 1)} mm, {_r(tip10, 2)} MPa"),
        ("README.md", f"{_r(float(c1[1]), 0)} mm for #9+#10 at 4.8 MPa where superposition predicts {c1[2]} mm"),
        ("README.md", f"(9,10,12) at {_r(tip_6_10, 2)} MPa, where the best single pair needs {_r(tip10, 2)} MPa"),
        ("config/README.md", f"the smallest margin, {_r(smallest, 1)} mm,"),
        (
            "README.md",
            f"the lowest rolling voltages are {proto[0]:.2f} V and {proto[1]:.2f} V "
            f"({float(proto_err.max()):.2f} V brackets)",
        ),
    ]
    return claims


def _words(text: str) -> str:
    """`text` with every run of white space (line breaks, indents) made one space."""
    return re.sub(r"\s+", " ", text)


@pytest.mark.slow
@pytest.mark.workflow
def test_numbers_quoted_from_the_default_run(default_run):
    wrong = [
        f"{doc}: expected the text {sentence!r}"
        for doc, sentence in _claims(default_run)
        if _words(sentence) not in _words((ROOT / doc).read_text())
    ]
    assert not wrong, "\n".join(wrong)


@pytest.mark.slow
@pytest.mark.workflow
def test_the_query_example_is_the_command_s_answer(default_run):
    """README's `tensegrity query` example prints what the command prints on the default run."""
    cmd = [sys.executable, "-m", "tensegrity.cli", "query", "--face", "8", "--pair", "10", "--pressure", "3.0"]
    out = subprocess.run(cmd, cwd=default_run.parent, capture_output=True, text=True, check=True).stdout.strip()
    assert f"# {out}" in (ROOT / "README.md").read_text().splitlines()


FIGURE = re.compile(r"\d+(\.\d+)?\s*(%|s\b|M\b|mm|deg|MPa|times|of \d+|/\d+|robot-steps|x\b)|\d+\.\d+")
MEASURED = ("benchmarks.md", "planner_evaluation.md")  # the documents of measured figures
DATED = re.compile(r"\bcommit [0-9a-f]{7,40}\b")


def _blocks(text: str) -> list[str]:
    """Paragraphs and tables of a Markdown text (headings and fenced code left out)."""
    text = re.sub(r"^```.*?^```", "", text, flags=re.S | re.M)
    out = []
    for chunk in re.split(r"\n\s*\n", text):
        lines = [line for line in chunk.splitlines() if not line.startswith("#")]
        tables = [line.startswith("|") for line in lines]
        for is_table in (False, True):  # a paragraph right before its table is a block of its own
            part = [line for line, t in zip(lines, tables) if t == is_table]
            if part:
                out.append("\n".join(part))
    return out


def test_benchmark_figures_are_dated():
    """Every paragraph or table of docs/benchmarks.md and docs/planner_evaluation.md with a figure names the commit that
    recorded it (in the text, or a "(commit X)" line after a table), and no document runs a bare
    `python` or `pip` (they fail outside an activated venv; `.venv/bin/python` does not)."""
    for name in MEASURED:
        blocks = _blocks((ROOT / "docs" / name).read_text())
        undated = [
            b[:80]
            for b, after in zip(blocks, blocks[1:] + [""])
            if FIGURE.search(b) and not DATED.search(b) and not (b.startswith("|") and DATED.match(after.strip("()")))
        ]
        assert not undated, f"docs/{name}: figures without the commit that recorded them: {undated}"
    for doc in ("README.md", "config/README.md", *(str(p.relative_to(ROOT)) for p in (ROOT / "docs").glob("*.md"))):
        bare = re.findall(r"(?:^|`|\$ )(python|pip) [\w./-]+", (ROOT / doc).read_text(), flags=re.M)
        assert not bare, f"{doc}: bare `{bare[0]}` commands (use .venv/bin/{bare[0]})"
