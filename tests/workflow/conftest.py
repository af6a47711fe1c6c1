"""Fixtures of the workflow tier: a scratch copy of the workflow and one run of it on the tiny
configuration, shared by the smoke test and the documentation examples."""

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
TINY = ROOT / "tests" / "workflow" / "tiny.yaml"
SNAKEMAKE = [sys.executable, "-m", "snakemake"]


def copy_workflow(tmp: Path) -> Path:
    """`Snakefile`, `workflow/` and `config/` copied into `tmp` (a run never touches the checkout)."""
    shutil.copy(ROOT / "Snakefile", tmp)
    shutil.copytree(ROOT / "workflow", tmp / "workflow")
    shutil.copytree(ROOT / "config", tmp / "config")
    return tmp


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
