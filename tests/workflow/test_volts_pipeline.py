"""The workspace pipeline in volts, end to end (issue 31): Snakemake on tests/workflow/tiny_volts.yaml
(the prototype's twisted-string actuator) makes the sweeps, nominal CoGs, curves, the 20-face,
two-pair and gravity-aware workspaces, the slope limit, the validation, the locomotion runs, their
figures, the GIF and the page, with the unit V in every file and curve document, and its datasets
pass the same CF check as the pneumatic ones (tests/workflow/test_cf_compliance.py). A target the
pipeline does not run in volts (a design study) is refused before any job, naming actuator.kind.
About 4 min on 2 shared cores: the slow tier."""

import importlib.util
import json
import subprocess
from pathlib import Path

import numpy as np
import pytest
from workflow_copy import SNAKEMAKE, copy_workflow

pytestmark = [pytest.mark.slow, pytest.mark.workflow]

ROOT = Path(__file__).resolve().parents[2]
VOLTS = ROOT / "tests" / "workflow" / "tiny_volts.yaml"


@pytest.fixture(scope="module")
def volts_run(tmp_path_factory) -> Path:
    wd = copy_workflow(tmp_path_factory.mktemp("volts"))
    r = subprocess.run(SNAKEMAKE + ["--cores", "2", "--configfile", str(VOLTS)], cwd=wd, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr[-3000:]
    return wd


def test_every_file_is_in_volts(volts_run):
    import xarray as xr

    res = volts_run / "results"
    files = sorted(res.rglob("*.nc"))
    assert {p.relative_to(res).parts[0] for p in files} == {
        "locomotion",
        "sweeps",
        "nominal",
        "curves",
        "two_pair",
        "workspace.nc",
        "workspace_two_pair.nc",
        "workspace_gravity.nc",
        "slope_limit.nc",
        "validation",
    }
    validation = sorted(p.name for p in files if p.parts[-2] == "validation")
    assert validation == ["gravity.nc", "prototype.nc", "two_pair.nc", "validation.nc"]
    for path in files:
        with xr.open_dataset(path) as ds:
            if path.name != "prototype.nc":  # the prototype's file is in V whatever the pipeline's robot
                assert ds.attrs["actuator"] == "twisted_string", path
            units = {k: v.attrs.get("units") for k, v in ds.variables.items()}
            assert "MPa" not in units.values(), (path, units)
            for k in ("pressure", "pressure_cmd", "tip_pressure", "pressure_a", "breaks", "pmax", "multi_pressure"):
                if k in units:
                    assert units[k] == "V", (path, k)
    for name in ("curves.json", "two_pair.json"):
        doc = json.loads((res / "curves" / name).read_text())
        assert doc["units"]["pressure"] == "V" and doc["actuator"] == "twisted_string"
    figures = {p.name for p in (res / "figures").glob("*.png")}
    assert {"fig6_cog_cloud.png", "fig7_workspace_equilateral.png", "two_pair_isosceles.png"} <= figures
    assert {"workspace_gravity.png", "slope_limit.png"} <= figures
    summary = (res / "validation" / "summary.md").read_text()
    assert "MPa" not in summary and "statics (physics.statics)" in summary


def test_a_higher_voltage_twists_further(volts_run):
    """Physics of the nominal CoGs in volts: a motor at a higher voltage stalls against a larger
    string tension, so each pair that moves the CoG (#9, #10 on the equilateral face) moves it
    farther from the unactuated robot's at every higher level; the curves pass through the nominal
    CoGs they were fitted to within the error curves.json states for each (max_residual, m), read
    in volts; whether a motor twisted its strands past their lock is in the sweep and nominal files."""
    import xarray as xr

    from tensegrity.physics import frames

    def evaluate(curve, p):  # README's evaluator of curves.json
        b, c = curve["breaks"], curve["coefs"]
        i = 0
        while i < len(c) - 1 and p >= b[i + 1]:
            i += 1
        y = 0.0
        for a in c[i]:
            y = y * (p - b[i]) + a
        return y

    res = volts_run / "results"
    doc = json.loads((res / "curves" / "curves.json").read_text())["contacts"]["equilateral"]["pairs"]
    with xr.open_dataset(res / "nominal" / "equilateral.nc") as nm:
        rest = frames.rest_frame(int(nm.attrs["face"]), float(nm["strut_length"]))[0]
        for pair in (9, 10):
            d = np.linalg.norm(nm["cog"].sel(pair=pair).values - rest, axis=-1)
            assert np.all(np.diff(d) > 1e-3), (pair, d)  # at least a millimetre per level
        for pair in nm["pair"].values:
            for k, axis in enumerate("xyz"):
                curve = doc[str(int(pair))][axis]
                for v, cog in zip(nm["pressure"].values, nm["cog"].sel(pair=pair).values[:, k]):
                    assert abs(evaluate(curve, float(v)) - cog) <= curve["max_residual"] + 1e-12
        locked = nm["strands_locked"].transpose("pair", "pressure").values
        assert set(locked.ravel().tolist()) <= {0, 1}
        assert np.all(np.diff(locked, axis=1) >= 0)  # the twist only grows with the level
        locked10 = nm["strands_locked"].sel(pair=10).values
    with xr.open_dataset(res / "sweeps" / "equilateral" / "pair10.nc") as sw:
        assert np.array_equal(sw["strands_locked"].values, locked10)


def test_its_datasets_pass_the_cf_check(volts_run, tmp_path):
    spec = importlib.util.spec_from_file_location("cf", Path(__file__).with_name("test_cf_compliance.py"))
    cf = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(cf)
    unexpected = {}
    for path in sorted((volts_run / "results").rglob("*.nc")):
        rep = cf.cf_report(path, tmp_path)
        bad = [m for m in cf.findings(rep) if not any(k.search(m) for k in cf.KNOWN)]
        if bad:
            unexpected[str(path.relative_to(volts_run))] = bad
        if path.parent.name == "curves":
            assert rep["scored_points"] == rep["possible_points"], (path, cf.findings(rep))
    assert not unexpected, json.dumps(unexpected, indent=1)


def test_the_gravity_ramps_and_the_checks_in_volts(volts_run):
    """The tiny ramp (locomotion.ramp_rate 1 V/s to 11 V, faster than the motors twist: design.md
    §10) records a tipping voltage, where the robot tips, within the ramp; the slope limit's
    simulated stand limit is no steeper than the friction angle; the demonstration runs in volts
    are validation check 6's, and G.1 compares the controller's rolls in volts."""
    import xarray as xr

    res = volts_run / "results"
    with xr.open_dataset(res / "workspace_gravity.nc") as g:
        tips = g["tip_pressure"].values
        assert np.all(tips[np.isfinite(tips)] <= 11.0) and g["stood"].values.any()
    with xr.open_dataset(res / "slope_limit.nc") as s:
        assert np.nanmax(s["simulated"].sel(kind="stand").values) <= s.attrs["friction_angle_deg"]
        assert "multi_not_computed" in s.attrs and "cables_not_computed" in s.attrs
    with xr.open_dataset(res / "validation" / "validation.nc") as v:
        assert "run" in v.dims  # check 6 read the runs in volts
    with xr.open_dataset(res / "validation" / "gravity.nc") as gv:
        assert "not_evaluated_G1" not in gv.attrs


def test_a_target_not_built_in_volts_is_refused_before_any_job(tmp_path):
    wd = copy_workflow(tmp_path)
    r = subprocess.run(
        SNAKEMAKE + ["study", "--config", "study=stiffness_pretension", "--cores", "1", "--configfile", str(VOLTS)],
        cwd=wd,
        capture_output=True,
        text=True,
    )
    assert r.returncode != 0
    assert "config key actuator.kind: 'twisted_string'" in r.stdout + r.stderr
    assert "stage study_" in r.stdout + r.stderr  # the first study job planned
    assert not (wd / "results").exists()  # no job ran


def test_the_commands_read_the_unit_and_refuse_the_other_actuator(volts_run, monkeypatch, capsys):
    """`tensegrity table` and `query` read the unit of the files in volts; `plan` plans in volts
    with the volts configuration, and with the pneumatic default configuration refuses the file,
    naming it and actuator.kind, instead of reading volts as MPa."""
    from tensegrity import cli

    monkeypatch.chdir(volts_run)
    assert cli.main(["table", "--face", "8", "--out", "face8.csv"]) == 0
    assert (
        (volts_run / "face8.csv")
        .read_text()
        .startswith("pair,pressure_V,cog_x_m,cog_y_m,cog_z_m,margin_m,tip_pressure_V")
    )
    capsys.readouterr()
    assert cli.main(["query", "--face", "8", "--pair", "10", "--pressure", "6", "--json"]) == 0
    assert json.loads(capsys.readouterr().out.strip().splitlines()[-1])["pressure_v"] == 6.0
    assert cli.main(["plan", "--direction", "75", "--config", str(VOLTS)]) == 0
    out = capsys.readouterr().out
    assert " V" in out and "MPa" not in out, out
    assert cli.main(["plan", "--direction", "75"]) == cli.EXIT_INPUT
    err = capsys.readouterr().err
    assert "results/workspace.nc is of the twisted_string actuator" in err and "actuator.kind is 'pneumatic'" in err


def test_the_paper_run_rolls_in_volts(volts_run):
    """The locomotion stage in volts: the paper run's file records the motor voltages applied
    (`voltage_cmd`, V), its first roll is #10 from (9,10,12) onto (10,11,12) (the prototype's
    first roll, design.md §10), and Figs. 8-10, the slope run's paths, the GIF and the page are
    drawn."""
    import xarray as xr

    with xr.open_dataset(volts_run / "results" / "locomotion" / "paper.nc") as ds:
        assert ds.attrs["actuator"] == "twisted_string" and "pressure" not in ds
        assert ds["voltage_cmd"].attrs["units"] == "V" and ds["tip_pressure"].attrs["units"] == "V"
        assert ds["faces"].values[:2].tolist() == [8, 20] and ds["step_pair"].values[0, 0] == 10
    assert (volts_run / "results" / "figures" / "rolling_paper.gif").stat().st_size > 0
    figures = {p.name for p in (volts_run / "results" / "figures").glob("*.png")}
    assert {"fig8_stable.png", "fig9_rolling.png", "fig10_slope.png", "path_slope_down_top.png"} <= figures
    page = (volts_run / "results" / "figures" / "workspace_3d.html").read_text()
    assert "robot (0 V)" in page and "robot (0 MPa)" not in page  # the interactive page, in volts
