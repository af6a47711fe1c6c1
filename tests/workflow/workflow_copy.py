"""What the workflow tests share outside fixtures: the checkout, the tiny configuration, the
Snakemake command and a scratch copy of the workflow (a module of its own: `from conftest import`
names whichever conftest.py was imported first)."""

import shutil
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
TINY = ROOT / "tests" / "workflow" / "tiny.yaml"
SNAKEMAKE = [sys.executable, "-m", "snakemake"]


def copy_workflow(tmp: Path) -> Path:
    """`Snakefile`, `workflow/` and `config/` copied into `tmp` (a run never touches the checkout)."""
    shutil.copy(ROOT / "Snakefile", tmp)
    shutil.copytree(ROOT / "workflow", tmp / "workflow")
    shutil.copytree(ROOT / "config", tmp / "config")
    return tmp
