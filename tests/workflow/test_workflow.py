"""Smoke test: the whole workflow on tests/workflow/tiny.yaml in a scratch copy, and a bad config that
stops before any job runs and writes nothing."""

import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from tensegrity.io import datasets

ROOT = Path(__file__).resolve().parents[2]
SNAKEMAKE = [sys.executable, "-m", "snakemake"]


def test_tiny_workflow_makes_every_output(tiny):
    res = tiny / "results"
    for contact in ("equilateral", "isosceles"):
        assert sorted(p.name for p in (res / "sweeps" / contact).glob("*.nc")) == [
            f"pair{p:02d}.nc" for p in (4, 9, 10, 11, 12)
        ]
    ws = datasets.read(res / "workspace.nc")
    assert ws["cog"].dims == ("face", "pair", "pressure", "axis")
    assert np.isfinite(ws["cog"].sel(pair=10, face=8)).all()
    for name in (
        "fig1_robot",
        "fig4_pairs",
        "fig5_support_frame",
        "fig6_cog_cloud",
        "fig7_workspace_equilateral",
        "fig7_workspace_isosceles",
        "fig12_prototype",
    ):
        assert (res / "figures" / f"{name}.png").stat().st_size > 20_000
    assert (res / "curves" / "curves.json").stat().st_size > 1000
    assert (res / "figures" / "workspace_3d.html").stat().st_size > 3_000_000  # the page, plotly.js inside
    assert (res / "validation" / "summary.md").exists()
    val = datasets.read(res / "validation" / "validation.nc")  # check 6 read the runs
    assert list(val["run"].values) == ["paper", "slope_down"]
    st = dict(zip(val["check"].values, val["status"].values))
    assert st["6"] == ("pass" if val["run_arrived"].values.all() else "fail")
    assert [st[k] for k in ("8.1", "8.2", "8.3", "8.4")] == ["pass"] * 4  # the prototype's experiment
    cfg = datasets.provenance_config(res / "nominal" / "equilateral.nc")
    assert cfg["sweep"]["levels"] == [1.2, 2.4, 3.6, 4.8] and cfg["nominal"]["discard"] == 0.1


def test_rerun_gives_identical_numbers(tiny, workflow_copy):
    wd = workflow_copy
    r = subprocess.run(
        SNAKEMAKE + ["results/workspace.nc", "--cores", "2", "--configfile", str(ROOT / "tests/workflow/tiny.yaml")],
        cwd=wd,
        capture_output=True,
        text=True,
    )
    assert r.returncode == 0, r.stderr[-3000:]
    a, b = datasets.read(tiny / "results/workspace.nc"), datasets.read(wd / "results/workspace.nc")
    assert a.equals(b)


@pytest.mark.parametrize(
    "override,key",
    [
        ("sweep={pairs: [13]}", "sweep.pairs[0]"),
        ("sweep={levels: [0.4, .nan]}", "sweep.levels[1]"),
        ("bogus=1", "bogus"),
    ],
)
def test_bad_config_stops_before_any_job(workflow_copy, override, key):
    """(Snakemake takes about 10 s to exit on any error in a Snakefile; tests/test_config.py
    covers the other bad values without it.)"""
    wd = workflow_copy
    r = subprocess.run(SNAKEMAKE + ["--cores", "1", "--config", override], cwd=wd, capture_output=True, text=True)
    assert r.returncode != 0
    assert f"config key {key}" in r.stdout + r.stderr
    assert not (wd / "results").exists()


def test_a_run_that_does_not_arrive_warns_and_fails_check_6(tiny, tmp_path):
    """The workflow still exits 0 (the run's files show what happened) but names the run at the
    end, and validation check 6 fails. In a copy of the tiny results: only the runs, their
    figures and the validation re-run (about 20 s)."""
    wd = tmp_path / "wf"
    shutil.copytree(tiny, wd, symlinks=True)
    r = subprocess.run(
        SNAKEMAKE
        + [
            "--cores",
            "2",
            "--configfile",
            str(ROOT / "tests/workflow/tiny.yaml"),
            "--config",
            "locomotion={max_rolls: 1, animation_run: null}",
        ],
        cwd=wd,
        capture_output=True,
        text=True,
    )
    assert r.returncode == 0, r.stderr[-3000:]
    assert "WARNING: 2 demonstration run(s) did not arrive" in r.stderr
    assert "  paper: step_limit (step limit of 1 rolls reached)" in r.stderr
    val = datasets.read(wd / "results" / "validation" / "validation.nc")
    assert dict(zip(val["check"].values, val["status"].values))["6"] == "fail"
    assert list(val["run_outcome"].values) == ["step_limit", "step_limit"]
    assert "| 6 |" in (wd / "results" / "validation" / "summary.md").read_text()


@pytest.mark.parametrize("where", ["--configfile", "config/config.yaml"])
def test_duplicate_key_in_a_config_file_stops_before_any_job(workflow_copy, where):
    """Snakemake's YAML reader keeps the last of two keys; the Snakefile re-reads the files."""
    wd = workflow_copy
    if where == "--configfile":
        (wd / "mine.yaml").write_text("sweep:\n  hold: 0.3\n  hold: 0.5\n")
        args, message = ["--configfile", "mine.yaml"], "mine.yaml line 3: duplicate key 'hold'"
    else:
        cfg = wd / "config" / "config.yaml"
        line = len(cfg.read_text().splitlines()) + 1
        cfg.write_text(cfg.read_text() + "sim:\n  record_every: 5\n")
        args, message = [], f"config/config.yaml line {line}: duplicate key 'sim'"
    r = subprocess.run(SNAKEMAKE + ["--cores", "1", *args], cwd=wd, capture_output=True, text=True)
    assert r.returncode != 0 and message in r.stdout + r.stderr, r.stderr[-2000:]
    assert not (wd / "results").exists()


def test_report_holds_every_figure_and_the_validation_table(tiny):
    r = subprocess.run(
        SNAKEMAKE + ["--report", "report.html", "--configfile", str(ROOT / "tests/workflow/tiny.yaml")],
        cwd=tiny,
        capture_output=True,
        text=True,
    )
    assert r.returncode == 0, r.stderr[-3000:]
    html = (tiny / "report.html").read_text()
    for name in (
        "fig1_robot.png",
        "fig4_pairs.png",
        "fig5_support_frame.png",
        "fig6_cog_cloud.png",
        "fig7_workspace_equilateral.png",
        "fig7_workspace_isosceles.png",
        "fig12_prototype.png",
        "summary.html",
        "workspace_3d.html",  # the interactive page
    ):
        assert name in html
