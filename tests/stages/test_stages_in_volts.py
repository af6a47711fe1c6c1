"""The gravity-aware workspace, the slope limit and the validation in volts (issue 31): each stage
on a tiny input of the twisted-string actuator writes its file in V (the unit, the wording and the
attribute `actuator`), passes the CF check of the pneumatic files, and marks the checks it cannot
evaluate in volts as not evaluated, saying why. The whole pipeline in volts:
tests/workflow/test_volts_pipeline.py (slow tier)."""

import importlib.util
from pathlib import Path

import numpy as np
import pytest

from tensegrity.io import config, datasets
from tensegrity.stages import gravity as gravity_stage
from tensegrity.stages import nominal as nominal_stage
from tensegrity.stages import sweep as sweep_stage
from tensegrity.stages import two_pair as two_pair_stage
from tensegrity.stages import validate as validate_stage
from tensegrity.stages.config import stage_config
from tensegrity.validation.common import PASS, SKIP, STATICS_IN_VOLTS

ROOT = Path(__file__).resolve().parents[2]
CONTACTS = ("equilateral", "isosceles")


@pytest.fixture(scope="module")
def volts(tmp_path_factory):
    """#10 and #11 at 6 and 9 V held 0.3 s on both contact faces, the two-pair workspace of the
    two, the gravity-aware ramp of #10 to 2 V on flat ground and 10 deg, the slope limit (no
    bisection) and the validation stages, all with the twisted-string actuator."""
    tmp = tmp_path_factory.mktemp("volts")
    cfg = config.load(
        overrides={
            "actuator": {"kind": "twisted_string"},
            "sweep": {"pairs": [10, 11], "levels": [6.0, 9.0], "hold": 0.3},
            "nominal": {"discard": 0.1},
            "two_pair": {"pairs": [10, 11], "levels": [6.0, 9.0], "hold": 0.3, "discard": 0.1},
            "gravity": {
                "pairs": [10],
                "slopes": [0, 10],
                "headings": [0],
                "max_pressure": 2.0,
                "grid_step": 0.4,
                "settle": 0.1,
                "iterations": 0,
                "free_step": 5.0,
                "validate_slopes": [0],
            },
            "locomotion": {"ramp_rate": 2.0, "hold_time": 20.0},  # a roll in volts holds at least 11.1 s
        }
    )
    f = {"nominal": [], "two_pair": []}
    for contact in CONTACTS:
        sweeps = sweep_stage.sweep(stage_config(cfg, "sweep"), contact, tmp / "sweeps" / contact)
        f["nominal"].append(nominal_stage.nominal(stage_config(cfg, "nominal"), sweeps, tmp / f"nominal_{contact}.nc"))
        f["two_pair"].append(two_pair_stage.two_pair(stage_config(cfg, "two_pair"), contact, tmp / f"tp_{contact}.nc"))
    f["workspace"] = nominal_stage.workspace({}, f["nominal"], tmp / "workspace.nc")
    f["workspace_two_pair"] = two_pair_stage.two_pair_map({}, f["two_pair"], tmp / "workspace_two_pair.nc")
    f["gravity"] = gravity_stage.gravity(stage_config(cfg, "gravity"), tmp / "workspace_gravity.nc")
    f["slope_limit"] = gravity_stage.slope_limit(
        stage_config(cfg, "slope_limit"), f["gravity"], f["workspace"], tmp / "slope_limit.nc", tmp / "slope_limit.png"
    )
    gravity_stage.gravity_figure({}, f["gravity"], tmp / "workspace_gravity.png")
    out = tmp / "validation"
    validate_stage.validate(
        stage_config(cfg, "validate"), f["nominal"], f["workspace"], out / "validation.nc", out / "summary.md"
    )
    validate_stage.validate_two_pair(
        stage_config(cfg, "validate_two_pair"),
        f["two_pair"],
        f["workspace_two_pair"],
        f["workspace"],
        out / "two_pair.nc",
        out / "two_pair.md",
    )
    validate_stage.validate_gravity(
        stage_config(cfg, "validate_gravity"), f["gravity"], f["nominal"], out / "gravity.nc", out / "gravity.md"
    )
    return cfg, tmp, f


NEW = (
    "workspace_gravity.nc",
    "slope_limit.nc",
    "validation/validation.nc",
    "validation/two_pair.nc",
    "validation/gravity.nc",
)


def test_every_file_is_in_volts(volts):
    _, tmp, _ = volts
    for name in NEW:
        ds = datasets.read(tmp / name)
        assert ds.attrs["actuator"] == "twisted_string", name
        units = {k: v.attrs.get("units") for k, v in ds.variables.items()}
        assert "MPa" not in units.values(), (name, units)
        for k in ("pressure", "tip_pressure", "multi_pressure", "workspace_tip_pressure"):
            if k in units:
                assert units[k] == "V", (name, k)
        text = " ".join(str(v.attrs.get("long_name", "")) for v in ds.variables.values())
        text += " ".join(" ".join(map(str, v.values.ravel())) for v in ds.data_vars.values() if v.dtype.kind == "U")
        assert "MPa" not in text and "pressure" not in text.replace("pneumatic", ""), (name, text)
    for page in ("summary.md", "two_pair.md", "gravity.md"):
        assert "MPa" not in (tmp / "validation" / page).read_text(), page


def test_the_gravity_ramp_and_the_slope_limit_in_volts(volts):
    """The ramp to 2 V leans the robot little (the motors take seconds): it stands on both
    slopes and does not roll; the slope limit says V, and why it has no optimised actions and no
    per-cable ones."""
    _, tmp, f = volts
    g = datasets.read(f["gravity"])
    np.testing.assert_allclose(g["pressure"].values, [0.4, 0.8, 1.2, 1.6, 2.0])
    assert g["stood"].values.all() and not g["rolled"].values.any()
    assert np.isfinite(g["margin"].values).all()  # a ramp without a roll is on the grid
    s = datasets.read(f["slope_limit"])
    assert s.attrs["max_pressure_V"] == 2.0 and "max_pressure_MPa" not in s.attrs
    assert "knows no motor stall" in s.attrs["multi_not_computed"]
    assert np.isnan(s["simulated_multi"].values).all()
    assert "knows no motor stall" in s.attrs["cables_not_computed"]  # nor per-cable ones
    assert np.isnan(s["simulated_cables"].values).all() and not s["cables_weights"].values.any()
    assert (tmp / "slope_limit.png").stat().st_size and (tmp / "workspace_gravity.png").stat().st_size


def test_each_check_is_evaluated_in_volts_or_says_why_not(volts):
    _, tmp, _ = volts
    ds = datasets.read(tmp / "validation" / "validation.nc")
    st = dict(zip(ds["check"].values, ds["status"].values))
    why = dict(zip(ds["check"].values, ds["measured"].values))
    for c in ("1.1", "1.2", "1.3", "1.4", "1.5"):
        assert st[c] == SKIP and "pneumatic muscles (eq. 1)" in why[c] and "check 8" in why[c]
    assert st["2"] == SKIP and why["2"] == STATICS_IN_VOLTS
    assert st["3"] == st["5"] == PASS  # the mapping and dt/2, simulated with the motors
    assert st["4.1"] in (PASS, "fail") and st["7"] != SKIP
    assert st["6"] == SKIP  # no run files given
    verdicts = [str(v) for v in datasets.read(tmp / "validation" / "two_pair.nc")["verdict"].values]
    assert verdicts[0] == f"a: {SKIP}: {STATICS_IN_VOLTS}" and verdicts[1].startswith(f"b: {PASS}:")
    gv = datasets.read(tmp / "validation" / "gravity.nc")
    assert dict(zip(gv["check"].values, gv["status"].values))["G.1"] == SKIP  # 2 V tip nothing: no roll to compare
    # G.2: the motors lag the ramp, so its CoG is not the settled one (validation.gravity.MOTOR_LAG)
    assert dict(zip(gv["check"].values, gv["status"].values))["G.2"] == SKIP
    assert "no roll compared" in (tmp / "validation" / "gravity.md").read_text()


def test_a_slope_limit_of_volts_ramps_on_a_workspace_of_pressures_is_refused(volts, tmp_path):
    cfg, _, f = volts
    pneumatic = config.load(overrides={"gravity": {"iterations": 0}})
    with pytest.raises(ValueError, match="workspace_gravity.nc is of the twisted_string actuator.*actuator.kind"):
        gravity_stage.slope_limit(
            stage_config(pneumatic, "slope_limit"), f["gravity"], f["workspace"], tmp_path / "x.nc", tmp_path / "x.png"
        )


def test_the_new_files_pass_the_cf_check(volts, tmp_path):
    """The CF check of the pneumatic files (tests/workflow/test_cf_compliance.py, its allowances)."""
    pytest.importorskip("compliance_checker.runner")
    spec = importlib.util.spec_from_file_location("cf", ROOT / "tests" / "workflow" / "test_cf_compliance.py")
    cf = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(cf)
    _, tmp, _ = volts
    for name in NEW:
        bad = [m for m in cf.findings(cf.cf_report(tmp / name, tmp_path)) if not any(k.search(m) for k in cf.KNOWN)]
        assert not bad, (name, bad)


@pytest.mark.slow
def test_the_controllers_rolls_in_volts_tip_where_the_gravity_ramp_does(volts, tmp_path):
    """Check G.1 in volts: #10 on (9,10,12) and #11 on (10,11,12), flat ground, ramped at 0.2 V/s
    to 12 V, tip the robot in the gravity-aware workspace; the controller's grounded rolls in
    volts (`locomotion.control.roll` with the motors) cross the same edge within 0.2 V
    (gravity.tip_tolerance). Measured: 10.65 and 7.88 V, 0.00 V apart. About 14 s: the slow tier."""
    _, _, f = volts
    cfg = config.load(
        overrides={
            "actuator": {"kind": "twisted_string"},
            "gravity": {
                "pairs": [10, 11],
                "slopes": [0],
                "headings": [0],
                "max_pressure": 12.0,
                "grid_step": 0.5,
                "validate_slopes": [0],
                "tip_tolerance": 0.2,
            },
            "locomotion": {"ramp_rate": 0.2, "hold_time": 20.0, "settle_time": 15.0},
        }
    )
    g = gravity_stage.gravity(stage_config(cfg, "gravity"), tmp_path / "workspace_gravity.nc")
    validate_stage.validate_gravity(
        stage_config(cfg, "validate_gravity"), g, f["nominal"], tmp_path / "gravity.nc", tmp_path / "gravity.md"
    )
    ds = datasets.read(tmp_path / "gravity.nc")
    assert dict(zip(ds["check"].values, ds["status"].values))["G.1"] == PASS
    assert ds["pair"].values.tolist() == [10, 11] and np.all(ds["difference"].values <= 0.2)
    assert np.all((ds["workspace_tip_pressure"].values > 6.0) & (ds["workspace_tip_pressure"].values < 12.0))
    assert ds["workspace_tip_pressure"].attrs["units"] == "V"
