"""Fixtures of the workflow tier: a scratch copy of the workflow and one run of it on the tiny
configuration, shared by the smoke test and the documentation examples."""

import os
import shutil
import subprocess
from pathlib import Path

import pytest
from workflow_copy import ROOT, SNAKEMAKE, TINY, copy_workflow


@pytest.fixture(scope="session")
def tiny(tmp_path_factory) -> Path:
    """A scratch copy in which the whole workflow ran on tests/workflow/tiny.yaml."""
    wd = copy_workflow(tmp_path_factory.mktemp("wf"))
    r = subprocess.run(SNAKEMAKE + ["--cores", "2", "--configfile", str(TINY)], cwd=wd, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr[-3000:]
    return wd


@pytest.fixture
def workflow_copy(tmp_path) -> Path:
    """A fresh scratch copy of the workflow (nothing run yet)."""
    return copy_workflow(tmp_path)


@pytest.fixture(scope="session")
def default_run(tmp_path_factory) -> Path:
    """`results/` of a complete run with the default configuration: made in a scratch copy (about
    a minute on 2 cores), or, with TENSEGRITY_DEFAULT_RUN=DIR, the finished run in DIR/results
    (checked to be one: its workspace's robot is the default robot)."""
    from tensegrity.io.config import load
    from tensegrity.io.datasets import provenance_config

    given = os.environ.get("TENSEGRITY_DEFAULT_RUN")
    if given:
        results = Path(given) / "results"
    else:
        wd = copy_workflow(tmp_path_factory.mktemp("default"))
        r = subprocess.run(SNAKEMAKE + ["--cores", "2"], cwd=wd, capture_output=True, text=True)
        assert r.returncode == 0, r.stderr[-3000:]
        results = wd / "results"
    default = load(ROOT / "config" / "config.yaml")["params"]
    assert provenance_config(results / "workspace.nc")["params"] == default, f"{results} is not a default run"
    return results


@pytest.fixture(scope="session")
def study_run(tmp_path_factory) -> Path:
    """A scratch copy of the workflow in which the tiny design study (tests/studies/tiny_study.yaml:
    8 designs in 2 chunks) ran locally, with tests/workflow/tiny.yaml (test_study_workflow.py; the
    SLURM test compares its own run with this one)."""
    wd = copy_workflow(tmp_path_factory.mktemp("study"))
    shutil.copy(ROOT / "tests" / "studies" / "tiny_study.yaml", wd / "config" / "studies" / "tiny_study.yaml")
    r = subprocess.run(
        SNAKEMAKE + ["--cores", "2", "--configfile", str(TINY), "--config", "study=tiny_study", "--", "study"],
        cwd=wd,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert r.returncode == 0, (r.stdout + r.stderr)[-3000:]
    return wd
