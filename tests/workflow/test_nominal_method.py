"""The pipeline under nominal.method statics (issue 34): the DAG schedules no sweep (`snakemake
-n`), and (slow) the tiny workflow runs to the end with the nominal files made by statics, which
`tensegrity stage nominal_statics` reproduces byte for byte."""

import re
import subprocess
import sys
from pathlib import Path

import pytest
import xarray as xr
import yaml

from tensegrity import cli

SNAKEMAKE = [sys.executable, "-m", "snakemake"]
TINY = Path(__file__).with_name("tiny.yaml")

STATICS = ["--config", "nominal={method: statics}"]


def _rules(out: str) -> set[str]:
    return set(re.findall(r"^(?:local)?rule (\w+):", out, re.M))


def test_a_dry_run_by_statics_schedules_the_nominal_stage_and_no_sweep(workflow_copy):
    r = subprocess.run(
        [*SNAKEMAKE, "-n", "--configfile", str(TINY), *STATICS], cwd=workflow_copy, capture_output=True, text=True
    )
    assert r.returncode == 0, r.stderr[-2000:]
    rules = _rules(r.stdout + r.stderr)
    assert {"nominal", "render", "page", "validate", "fit"} <= rules and "sweep" not in rules, rules


@pytest.mark.slow
def test_the_tiny_workflow_by_statics_runs_to_the_end(workflow_copy, tmp_path):
    r = subprocess.run(
        [*SNAKEMAKE, "--cores", "2", "--configfile", str(TINY), *STATICS],
        cwd=workflow_copy,
        capture_output=True,
        text=True,
    )
    assert r.returncode == 0, r.stderr[-3000:]
    res = workflow_copy / "results"
    assert not (res / "sweeps").exists()
    assert xr.open_dataset(res / "nominal" / "isosceles.nc").attrs["nominal_method"] == "statics"
    summary = (res / "validation" / "summary.md").read_text()
    assert summary.count("static equilibria (nominal.method statics)") == 2  # checks 5 and 7
    assert (res / "figures" / "fig6_cog_cloud.png").stat().st_size > 10_000
    # `tensegrity stage nominal_statics` writes the rule's files byte for byte
    cfg = yaml.safe_load(TINY.read_text())
    cfg["nominal"]["method"] = "statics"
    (tmp_path / "statics.yaml").write_text(yaml.safe_dump(cfg))
    outs = [tmp_path / f"{c}.nc" for c in ("equilateral", "isosceles")]
    args = ["contacts=equilateral", "contacts=isosceles", *(f"out_paths={p}" for p in outs)]
    assert cli.main(["stage", "nominal_statics", "--config", str(tmp_path / "statics.yaml"), *args]) == 0
    for p in outs:
        assert p.read_bytes() == (res / "nominal" / p.name).read_bytes()
