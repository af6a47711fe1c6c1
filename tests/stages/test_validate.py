"""The validate stages (`stages.validate`): the workspace checks on the pipeline's files, read
through `io` (`io.formats.read_nominals`, `read_workspace`, `read_run_summaries`) and written
as validation.nc, summary.md and summary.html; the demonstration runs' files and the
end-of-workflow warning; the readers hand the checks the files' numbers."""

import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from tensegrity.io import config, datasets, settings
from tensegrity.io.formats import run as run_formats
from tensegrity.io.formats import two_pair as tpf
from tensegrity.io.formats import workspace as wf
from tensegrity.io.formats.nominal import read_nominal, read_nominals
from tensegrity.physics import topology as topo
from tensegrity.stages import nominal as nominal_stage
from tensegrity.stages import sweep as sweep_stage
from tensegrity.stages import validate as validate_stage
from tensegrity.stages.config import stage_config
from tensegrity.validation import checks, grounded, summary
from tensegrity.validation.common import FAIL, PASS, SKIP, CheckError, CheckSettings
from tensegrity.workspace import two_pair as tp
from tensegrity.workspace.sweep import SweepSetup

DISCARD = 0.2  # s, the pipeline's nominal average (config nominal.discard)
REPO = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def tiny_stage(tmp_path_factory):
    """The pipeline on #10 and #11 at two levels, then the validate stage on its outputs."""
    tmp = tmp_path_factory.mktemp("stage")
    cfg = config.load(
        overrides={
            "sweep": {"pairs": [10, 11], "levels": [2.0, 2.4], "hold": 0.5},
            "validate": {"statics_pressures": [2.4]},
        }
    )
    noms = []
    for contact in ("equilateral", "isosceles"):
        sweeps = sweep_stage.sweep(stage_config(cfg, "sweep"), contact, tmp / "sweeps" / contact)
        noms.append(nominal_stage.nominal(stage_config(cfg, "nominal"), sweeps, tmp / "nominal" / f"{contact}.nc"))
    ws = nominal_stage.workspace({}, noms, tmp / "workspace.nc")
    out = tmp / "validation"
    cfg = stage_config(cfg, "validate")
    paths = validate_stage.validate(cfg, noms, ws, out / "validation.nc", out / "summary.md", out / "summary.html")
    return cfg, noms, ws, out, paths


def test_stage_writes_every_number_with_units_and_a_table(tiny_stage):
    cfg, _, _, out, paths = tiny_stage
    assert [p.name for p in paths] == ["validation.nc", "summary.md", "summary.html"]
    ds = datasets.read(out / "validation.nc")
    for name, var in ds.variables.items():
        assert var.attrs.get("long_name"), name
        if var.dtype.kind in "fi":
            assert var.attrs.get("units"), name
    ids = list(ds["check"].values)
    assert ids == ["1.1", "1.2", "1.3", "1.4", "1.5", "2", "3", "4.1", "4.2", "5", "6", "7"]
    assert datasets.provenance_config(out / "validation.nc")["validate"] == cfg["validate"]
    st = dict(zip(ids, ds["status"].values))
    assert st["1.1"] == SKIP  # only two pairs swept: no ranking
    assert st["2"] == st["3"] == st["5"] == PASS
    assert st["6"] == SKIP and "run" not in ds.dims  # no run files given
    assert list(ds["passed"].values) == [{PASS: 1, FAIL: 0, SKIP: -1}[s] for s in ds["status"].values]
    md = (out / "summary.md").read_text()
    for i in ids:
        assert re.search(rf"^\| {re.escape(i)} \|", md, re.M), i
    assert "| # | statement | measured | paper / goal | verdict |" in md
    assert "<table>" in (out / "summary.html").read_text()
    assert not list(out.glob(".*tmp"))  # written atomically, nothing left behind


def test_a_check_that_raises_is_shown_as_failed(tiny_stage, monkeypatch):
    cfg, noms, ws, _, _ = tiny_stage

    def boom(*a, **k):
        raise RuntimeError("solver diverged")

    monkeypatch.setattr(checks, "check_statics", boom)
    monkeypatch.setattr(checks, "check_mapping", boom)
    monkeypatch.setattr(grounded, "check_grounded", boom)
    monkeypatch.setattr(checks, "check_timestep", boom)
    results = checks.run_checks(
        settings.params(cfg),
        settings.build(SweepSetup, cfg),
        DISCARD,
        read_nominals(noms),
        wf.read_workspace(ws),
        settings.build(CheckSettings, cfg),
    )
    assert isinstance(results[1], CheckError) and results[1].status == {"2": FAIL}
    rows = {r.id: r for res in results for r in summary.verdicts(res)}
    assert rows["2"].status == FAIL and rows["2"].measured == "error: RuntimeError: solver diverged"
    assert rows["1.2"].status in (PASS, FAIL)
    from tensegrity.io.formats.validation import workspace_validation_dataset

    ds, _ = workspace_validation_dataset(results, [2.0, 2.4], [1, 7, 9, 18], [2.4])
    assert list(ds["check"].values) == ["1.1", "1.2", "1.3", "1.4", "1.5", "2", "3", "4", "5", "6", "7"]
    assert "statics_difference" not in ds and "tip_pressure" in ds


def test_check_7_names_every_level_whose_averaging_error_is_above_the_tolerance(tiny_stage, tmp_path):
    """0.3 s windows after steps of 2.0 and 0.4 MPa: the files' own estimates decide check 7,
    which names each pair and level above validate.averaging_tolerance (issue 34)."""
    cfg, noms, ws, out, _ = tiny_stage
    files = read_nominals(noms)
    err = np.stack([files[c].averaging_error for c in topo.CONTACTS])  # (2, 12, 2) m
    ds = datasets.read(out / "validation.nc")
    np.testing.assert_array_equal(ds["averaging_error"].transpose("contact", "pair", "pressure").values, err)
    assert ds["averaging_error"].attrs["goal_m"] == cfg["validate"]["averaging_tolerance"]
    # a tolerance between the smallest and the largest estimate: the check fails naming exactly
    # the levels above it, largest first
    tol = float(np.sqrt(np.nanmin(err) * np.nanmax(err)))
    from tensegrity.validation import averaging

    res = averaging.check_averaging(files, tol)
    above = res.above()
    assert res.status == {"7": FAIL} and len(above) == int((np.nan_to_num(err) > tol).sum()) > 0
    text = summary.verdicts(res)[0].measured
    for contact, pair, level, e in above:
        assert f"#{pair} at {level:g} MPa on {topo.face_label(files[contact].face)}" in text
        assert e > tol
    assert averaging.check_averaging(files, 2 * np.nanmax(err)).status == {"7": PASS}
    old = {c: replace(n, averaging_error=None) for c, n in files.items()}  # files made before issue 34
    assert averaging.check_averaging(old, tol).status == {"7": SKIP}


def run_file(path, name, outcome, goal=(1.0, 0.0, np.nan), final=(0.9, 0.1, 0.2), rolls=3):
    """A file shaped like results/locomotion/{run}.nc (only what check 6 reads)."""
    ds = xr.Dataset(
        {"cog": (("time", "axis"), np.array([[0.0, 0.0, 0.2], final])), "goal": (("axis",), np.array(goal, float))},
        attrs={"run": name, "outcome": outcome, "message": f"{outcome} because", "rolls": rolls},
    )
    ds.to_netcdf(path)
    return path


def test_run_files_are_read_as_what_check_6_needs_and_warned_about(tmp_path):
    good = run_file(tmp_path / "flat.nc", "flat", "arrived")
    bad = run_file(tmp_path / "slope_up.nc", "slope_up", "no_contact", goal=(1.0, 0.0, 0.0), final=(-0.5, 0.0, 0.1))
    edges = run_file(tmp_path / "paper.nc", "paper", "arrived", goal=(np.nan,) * 3)
    runs = run_formats.read_run_summaries([edges, good, bad])
    assert list(runs) == ["paper", "flat", "slope_up"]
    assert [r.outcome for r in runs.values()] == ["arrived", "arrived", "no_contact"]
    assert runs["slope_up"].message == "no_contact because" and runs["slope_up"].rolls == 3
    np.testing.assert_array_equal(runs["flat"].final_cog, [0.9, 0.1, 0.2])
    assert np.isnan(runs["paper"].distance) and runs["flat"].distance == pytest.approx(0.1414, abs=1e-4)
    # the end-of-workflow warning names the runs that did not arrive, and only those
    text = validate_stage.runs_warning([edges, good, bad, tmp_path / "missing.nc"])
    assert "slope_up: no_contact (no_contact because)" in text and "flat" not in text
    assert validate_stage.runs_warning([edges, good]) == ""


def test_stage_fails_check_6_in_every_output(tiny_stage, tmp_path):
    cfg, noms, ws, _, _ = tiny_stage
    runs = [
        run_file(tmp_path / "paper.nc", "paper", "arrived", goal=(np.nan,) * 3),
        run_file(tmp_path / "slope_up.nc", "slope_up", "no_contact"),
    ]
    out = tmp_path / "validation"
    validate_stage.validate(
        cfg, noms, ws, out / "validation.nc", out / "summary.md", out / "summary.html", run_paths=runs
    )
    ds = datasets.read(out / "validation.nc")
    st = dict(zip(ds["check"].values, ds["status"].values))
    assert st["6"] == FAIL
    assert list(ds["run"].values) == ["paper", "slope_up"] and list(ds["run_arrived"].values) == [1, 0]
    assert list(ds["run_outcome"].values) == ["arrived", "no_contact"]
    assert ds["run_distance_to_goal"].attrs["units"] == "m" and ds["run_rolls"].attrs["long_name"]
    assert re.search(r"^\| 6 \| .* \| FAIL \|$", (out / "summary.md").read_text(), re.M)
    assert "slope_up no_contact" in (out / "summary.html").read_text()


def test_the_rule_puts_the_summary_in_the_report():
    smk = (REPO / "workflow" / "rules" / "validate.smk").read_text()
    assert re.search(r'report\(\s*"results/validation/summary\.html"', smk)
    assert "rules.validate.output" in (REPO / "Snakefile").read_text()
    assert re.search(r'runs=expand\(\s*"results/locomotion/\{run\}\.nc"', smk)  # check 6 reads the runs
    assert (REPO / "workflow" / "report" / "validation.rst").is_file()


def test_the_readers_hand_the_checks_the_files_numbers(tiny_stage):
    """results/nominal/{contact}.nc as a `Nominal`: the pairs swept (#10, #11) at their rows of
    all 12 pairs, NaN elsewhere; the face, mode and levels of the file. The tipping pressures
    of results/workspace.nc by face and pair."""
    _, noms, ws, _, _ = tiny_stage
    for path in noms:
        ds, n = datasets.read(path), read_nominal(path)
        assert n.contact == ds.attrs["contact"] and n.face == ds.attrs["face"] and n.mode == "free"
        np.testing.assert_array_equal(n.levels, [2.0, 2.4])
        np.testing.assert_array_equal(n.pairs, [10, 11])
        for name in ("cog", "support", "margin"):
            np.testing.assert_array_equal(getattr(n, name)[[9, 10]], ds[name].values)
            assert np.isnan(np.delete(getattr(n, name), [9, 10], axis=0)).all()
    assert list(read_nominals(noms[::-1])) == ["isosceles", "equilateral"]
    with pytest.raises(ValueError, match="is not a nominal CoG file"):
        read_nominal(ws)  # results/workspace.nc is not a nominal file
    tips = wf.tip_pressures(datasets.read(ws))
    np.testing.assert_array_equal(tips, datasets.read(ws)["tip_pressure"].values)
    assert tips.shape == (20, 12)


def test_the_two_pair_readers_hand_the_checks_the_files_numbers(tmp_path):
    """results/two_pair/{contact}.nc as a `TwoPairNominal`, results/workspace_two_pair.nc as the
    grid and staircases the direct check compares (synthetic numbers)."""
    rng, levels = np.random.default_rng(1), [1.0, 2.0]
    grid = lambda *lead: {
        "cog": rng.normal(size=(*lead, 66, 2, 2, 3)),
        "support": rng.normal(size=(*lead, 66, 2, 2, 3, 3)),
        "margin": rng.normal(size=(*lead, 66, 2, 2)),
        "tip_pressure": rng.uniform(1, 2, (*lead, 66)),
        "tip_edge": np.ones((*lead, 66, 2), int),
        "tip_boundary": np.full((*lead, 66, 2), np.nan),
        "staircase": np.tile(tp.COMBOS, (*lead, 1, 1)),
    }
    ws = grid() | {"averaging_error": rng.uniform(0, 1e-4, (66, 2, 2))}
    face = topo.face_number(topo.CONTACT_FACES["isosceles"])
    ds = tpf.contact_dataset(
        levels, tp.COMBOS, ws, np.ones(66), np.zeros((66, 2, 2, 3)), {"contact": "isosceles", "face": face}, 0.5
    )
    ds.to_netcdf(tmp_path / "isosceles.nc")
    n = tpf.read_two_pair_nominals([tmp_path / "isosceles.nc"])["isosceles"]
    assert n.contact == "isosceles" and n.face == face
    np.testing.assert_array_equal(n.levels, levels)
    np.testing.assert_array_equal(n.cog, ws["cog"])
    np.testing.assert_array_equal(n.tip_pressure, ws["tip_pressure"])
    np.testing.assert_array_equal(n.averaging_error, ws["averaging_error"])
    ws20 = grid(20)
    tpf.workspace_dataset(levels, tp.COMBOS, ws20, {}, 0.5).to_netcdf(tmp_path / "workspace_two_pair.nc")
    cog, staircase = tpf.read_two_pair_grid(tmp_path / "workspace_two_pair.nc")
    np.testing.assert_array_equal(cog, ws20["cog"])
    np.testing.assert_array_equal(staircase, ws20["staircase"])
