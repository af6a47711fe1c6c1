"""A tiny design study (tests/studies/tiny_study.yaml: 8 designs in 2 chunks, a free-mode
workspace of 2 pairs x 4 levels x 2 contacts and the paper's roll sequence per design) run by
Snakemake with `--config study=tiny_study -- study`: its files, a finished chunk that is never
recomputed, the same bytes on a re-run, and a bad study stopped before any job runs."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from tensegrity.io import datasets, study_config
from tensegrity.studies import spec

ROOT = Path(__file__).resolve().parents[2]
TINY = ROOT / "tests" / "workflow" / "tiny.yaml"
STUDY = ROOT / "tests" / "studies" / "tiny_study.yaml"
OUT = Path("results/studies/tiny_study")


def _snakemake(wd: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "snakemake", "--cores", "2", "--configfile", str(TINY), *args],
        cwd=wd,
        capture_output=True,
        text=True,
        timeout=600,
    )


def test_the_study_writes_its_designs_analysis_and_figures(study_run):
    st = study_config.load(STUDY)
    ds = datasets.read(study_run / OUT / "designs.nc")
    assert ds.sizes["design"] == spec.n_designs(st) == 8
    X = spec.design_matrix(st)
    for j, name in enumerate(st["parameters"]):
        np.testing.assert_array_equal(ds[name].values, X[:, j])
        assert ds[name].attrs["units"] == st["parameters"][name]["units"]
    assert json.loads(ds.attrs["study_config"])["parameters"] == st["parameters"]
    assert len(list((study_run / OUT / "chunks").glob("chunk*.nc"))) == spec.n_chunks(st) == 2
    # every design stands on its faces at low pressure, and #11 tips the isosceles case
    assert (ds["margin"].sel(pressure=1.2) > 0).all()
    assert np.isfinite(ds["tip_pressure"].sel(contact="isosceles", pair=11)).all()
    assert ds["roll_success"].dims == ("design",) and set(np.unique(ds["roll_success"])) <= {0, 1}
    an = datasets.read(study_run / OUT / "analysis.nc")
    assert set(an["output"].values) == {"best_tip_pressure", "roll_success"}
    assert np.isfinite(an["S1"].sel(output="best_tip_pressure")).all()
    for name in ("sensitivity", "response", "robustness"):
        assert (study_run / OUT / "figures" / f"{name}.png").stat().st_size > 10_000


def test_a_finished_chunk_is_never_recomputed_and_a_rerun_gives_the_same_bytes(study_run):
    """A study interrupted after its first chunk (the second chunk and what follows missing)
    computes the second chunk only, and the same designs.nc, byte for byte."""
    out = study_run / OUT
    first = (out / "chunks" / "chunk0000.nc").stat().st_mtime_ns
    before = (out / "designs.nc").read_bytes()
    for f in ("chunks/chunk0001.nc", "designs.nc", "analysis.nc"):
        (out / f).unlink()
    r = _snakemake(study_run, "--config", "study=tiny_study", "--", "study")
    assert r.returncode == 0, (r.stdout + r.stderr)[-3000:]
    assert r.stderr.count("rule study_chunk:") == 1, r.stderr[-3000:]
    assert (out / "chunks" / "chunk0000.nc").stat().st_mtime_ns == first
    assert (out / "designs.nc").read_bytes() == before


def test_studies_are_not_part_of_the_default_target(study_run):
    r = _snakemake(study_run, "-n", "--config", "study=tiny_study")
    assert r.returncode == 0 and "study_chunk" not in r.stdout + r.stderr


def test_the_study_target_needs_a_study_name(study_run):
    r = _snakemake(study_run, "-n", "study")
    assert r.returncode != 0 and "config key study: name a study" in r.stdout + r.stderr


def test_a_bad_study_stops_before_any_job_naming_every_bad_key(tmp_path):
    import yaml
    from workflow_copy import copy_workflow

    wd = copy_workflow(tmp_path)
    st = yaml.safe_load(STUDY.read_text())
    st["parameters"]["cable_stiffness"].update(units="kN/m", low=2000.0)
    (wd / "config" / "studies" / "bad.yaml").write_text(yaml.safe_dump(st))
    r = _snakemake(wd, "--config", "study=bad", "--", "study")
    assert r.returncode != 0
    for key in ("study key parameters.cable_stiffness.units", "study key parameters.cable_stiffness.high"):
        assert key in r.stderr, r.stderr[-2000:]
    assert not (wd / "results").exists()


def test_the_command_line_refuses_a_bad_study_naming_the_key(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("parameters: {cable_stiffness: {low: 1, high: 2, units: kN}}\ndesign: {method: grid}\n")
    r = subprocess.run(
        [sys.executable, "-m", "tensegrity.cli", "study", str(bad), "--out", str(tmp_path / "out")],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert r.returncode != 0 and "study key parameters.cable_stiffness.units" in r.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.filterwarnings("ignore:The ioos_sos checker is deprecated:DeprecationWarning")
def test_the_study_datasets_are_cf_compliant(study_run, tmp_path):
    """The IOOS checker against CF-1.10, with the allowance of test_cf_compliance (pressure)."""
    pytest.importorskip("compliance_checker.runner")
    from test_cf_compliance import KNOWN, cf_report, findings

    for name in ("designs.nc", "analysis.nc"):
        bad = [m for m in findings(cf_report(study_run / OUT / name, tmp_path)) if not any(k.search(m) for k in KNOWN)]
        assert not bad, (name, bad)
