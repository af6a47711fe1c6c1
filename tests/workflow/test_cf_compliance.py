"""Every netCDF file the pipeline writes passes the IOOS compliance checker against CF-1.10.

The datasets of one run of the workflow on tests/workflow/tiny.yaml (sweeps, nominal, curves,
workspace, validation, locomotion runs) are checked with `compliance-checker` (test-only
dependency, environment.txt), the same as `cchecker.py --test=cf:1.10 FILE`.

Two of the checker's findings are name heuristics that conflict with the dataset contract
(docs/design.md §5), listed in KNOWN and reported in docs/datasets.md: a dimension called `time`
must be a CF calendar time (standard_name `time`, units "s since <epoch>", a calendar, every other
dimension to its left), and one called `pressure`, or any coordinate in pressure units, must be
atmospheric (standard_name `air_pressure`, a vertical axis, rightmost). The muscle pressure is a
relative pressure in MPa and the simulation time has no epoch. Everything else must be clean; the
curve files score 100 %; `test_every_dataset_scores_100_percent` turns into a failure (XPASS) the
day the contract changes so that the allowance can go.
"""

import json
import re
from pathlib import Path

import pytest

checker = pytest.importorskip(
    "compliance_checker.runner",
    reason="compliance-checker is not installed (a test-only dependency pinned in environment.txt)",
)

pytestmark = [pytest.mark.filterwarnings("ignore:The ioos_sos checker is deprecated:DeprecationWarning")]

ROOT = Path(__file__).resolve().parents[2]
TINY = ROOT / "tests" / "workflow" / "tiny.yaml"
DATASETS = [
    "results/workspace.nc",
    "results/validation/validation.nc",
    "results/curves/curves.json",
    "results/locomotion/paper.nc",
    "results/locomotion/slope_down.nc",
]

KNOWN = [
    re.compile(p)
    for p in (
        r"^Coordinate variable 'time' should have standard_name='time', found: 'None'$",
        r"^Coordinate variable 'pressure' should have standard_name='air_pressure', found: 'None'$",
        r"^\w+'s spatio-temporal dimensions are not in the recommended order T, Z, Y, X .*"
        r"\b(pressure|statics_pressure) \(Z\)",
    )
]


@pytest.fixture(scope="module")
def run(tiny) -> Path:
    """The workflow copy that ran on the tiny configuration (tests/workflow/conftest.py)."""
    return tiny


def cf_report(path: Path, tmp: Path) -> dict:
    """The checker's JSON report of `path` against CF-1.10."""
    out = tmp / (path.name + ".json")
    checker.CheckSuite.load_all_available_checkers()
    checker.ComplianceChecker.run_checker(
        str(path),
        checker_names=["cf:1.10"],
        verbose=0,
        criteria="normal",
        output_filename=str(out),
        output_format="json",
    )
    return json.loads(out.read_text())["cf:1.10"]


def findings(report: dict) -> list[str]:
    return [m for r in report["all_priorities"] for m in r["msgs"]]


def netcdf_files(run: Path) -> list[Path]:
    files = sorted((run / "results").rglob("*.nc"))
    kinds = {p.relative_to(run / "results").parts[0] for p in files}
    assert kinds >= {"sweeps", "nominal", "curves", "workspace.nc", "validation", "locomotion"}, kinds
    return files


@pytest.fixture(scope="module")
def reports(run, tmp_path_factory) -> dict:
    """{path: the checker's report} of every dataset of the tiny run (checked once, ~0.5 s each)."""
    tmp = tmp_path_factory.mktemp("cf")
    return {path: cf_report(path, tmp) for path in netcdf_files(run)}


def test_datasets_are_cf_compliant(run, reports):
    scores, unexpected = {}, {}
    for path, rep in reports.items():
        name = str(path.relative_to(run))
        scores[name] = f"{rep['scored_points']}/{rep['possible_points']}"
        bad = [m for m in findings(rep) if not any(k.search(m) for k in KNOWN)]
        if bad:
            unexpected[name] = bad
        if path.parent.name == "curves":  # no time or pressure dimension: nothing to allow
            assert rep["scored_points"] == rep["possible_points"], (name, findings(rep))
    assert not unexpected, json.dumps(unexpected, indent=1)
    print(json.dumps(scores, indent=1))


@pytest.mark.xfail(
    strict=True,
    reason="the contract's `time` and `pressure` dimensions meet the checker's "
    "name heuristics (standard_name time / air_pressure); see the module docstring",
)
def test_every_dataset_scores_100_percent(reports):
    for path, rep in reports.items():
        assert rep["scored_points"] == rep["possible_points"], (str(path), findings(rep))
