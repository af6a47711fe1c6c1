"""A project copy (README: `Snakefile`, `workflow/`, `config/` copied to keep runs apart) is one
configuration for Snakemake and for the `tensegrity` command run there (issue 35, item 3); a
configuration that would fail inside a job stops Snakemake before any job, deleting nothing; an
empty config file is refused by Snakemake and the command alike."""

import os
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from tensegrity.io import datasets

ROOT = Path(__file__).resolve().parents[2]
SNAKEMAKE = [sys.executable, "-m", "snakemake"]
TENSEGRITY = [sys.executable, "-m", "tensegrity.cli"]


def _run(argv, cwd):
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")]))}
    return subprocess.run(argv, cwd=cwd, capture_output=True, text=True, env=env, timeout=900)


def test_the_command_in_a_project_copy_reads_the_copys_configuration(workflow_copy):
    wd = workflow_copy
    cfg = wd / "config" / "config.yaml"
    cfg.write_text(cfg.read_text().replace("strut_length: 0.5 ", "strut_length: 0.6 "))
    r = _run([*TENSEGRITY, "config", "show"], wd)
    assert r.returncode == 0, r.stderr
    assert r.stdout.startswith(f"# {wd / 'config' / 'config.yaml'}; defaults filled in")
    assert yaml.safe_load(r.stdout)["params"]["strut_length"] == 0.6
    (wd / "my.yaml").write_text("params:\n  cable_stiffness: 2000.0\n")
    r = _run([*TENSEGRITY, "config", "show", "my.yaml"], wd)
    shown = yaml.safe_load(r.stdout)
    assert (shown["params"]["strut_length"], shown["params"]["cable_stiffness"]) == (0.6, 2000.0)
    argv = ["simulate", "--pair", "10", "--pressure", "2.0", "--duration", "0.05", "--out"]
    assert _run([*TENSEGRITY, *argv, "run.nc"], wd).returncode == 0
    assert datasets.provenance_config(wd / "run.nc")["params"]["strut_length"] == 0.6
    r = _run([*TENSEGRITY, *argv, "stiff.nc", "--config", "my.yaml"], wd)
    assert r.returncode == 0, r.stderr
    prm = datasets.provenance_config(wd / "stiff.nc")["params"]
    assert (prm["strut_length"], prm["cable_stiffness"]) == (0.6, 2000.0)  # the file over the copy's


def test_an_empty_config_file_is_refused_by_snakemake_and_the_command(workflow_copy):
    wd = workflow_copy
    (wd / "empty.yaml").write_text("")
    r = _run([*SNAKEMAKE, "-n", "--configfile", "empty.yaml"], wd)
    assert (
        r.returncode != 0 and "Config file must be given as JSON or YAML with keys at top level" in r.stdout + r.stderr
    )
    r = _run([*TENSEGRITY, "config", "check", "empty.yaml"], wd)
    assert r.returncode == 3 and "config file empty.yaml: the file is empty" in r.stderr
    (wd / "config" / "config.yaml").write_text("# nothing\n")
    r = _run([*SNAKEMAKE, "-n"], wd)
    assert r.returncode != 0 and "config file config/config.yaml: the file is empty" in r.stdout + r.stderr


BAD_SOBOL = """parameters:
  cable_stiffness: {low: 800.0, high: 1200.0, units: N/m}
design: {method: sobol, n: 10}
"""


@pytest.mark.parametrize(
    "override, needle",
    [
        ("locomotion={goal_distance: 0.1}", "config key locomotion.goal_distance: "),
        ("sweep={hold: 1.0e9}", "config key sweep.hold: "),
        ("study=bad_sobol", "bad_sobol.yaml: study key design.n: 10 is not a power of 2"),
    ],
)
def test_a_config_that_would_fail_inside_a_job_stops_before_any_job_and_deletes_nothing(
    workflow_copy, override, needle
):
    """The old outputs (here stand-ins) stay as they were: Snakemake deletes a job's outputs
    only when it starts the job."""
    wd = workflow_copy
    (wd / "config" / "studies" / "bad_sobol.yaml").write_text(BAD_SOBOL)
    old = [
        wd / "results" / "locomotion" / "flat.nc",
        wd / "results" / "sweeps" / "equilateral" / "pair10.nc",
        wd / "results" / "studies" / "bad_sobol" / "chunks" / "chunk0000.nc",
    ]
    for p in old:
        p.parent.mkdir(parents=True)
        p.write_bytes(b"an earlier run's output")
    r = _run([*SNAKEMAKE, "--cores", "1", "--config", override], wd)
    assert r.returncode != 0
    assert needle in r.stdout + r.stderr, r.stderr[-2000:]
    assert all(p.read_bytes() == b"an earlier run's output" for p in old)
    assert not (wd / "results" / "logs").exists()
