"""The nominal stage by statics (nominal.method statics, issue 34): the static equilibria stand in
for the sweeps' averages, in files of the same contract, within 0.05 mm of the averages of the
default protocol (0.4 MPa steps, 1 s holds); checks 5 and 7, which would pass on them vacuously,
say why they are not evaluated; non-linear cables and the grounded mode are refused by key."""

import numpy as np
import pytest
import xarray as xr

from tensegrity.io import config
from tensegrity.io.formats import read_nominals
from tensegrity.stages import nominal, stage_config, sweep
from tensegrity.validation import averaging, checks
from tensegrity.validation.common import SKIP
from tensegrity.validation.words_workspace import timestep_verdicts
from tensegrity.workspace.sweep import SweepSetup

# the default protocol on two pairs of (10,11,12): its averaging error is under 0.05 mm
OVER = {
    "sweep": {"pairs": [10, 11], "levels": [0.4, 0.8, 1.2, 1.6], "hold": 1.0, "contacts": ["isosceles"]},
    "locomotion": {"runs": []},
}


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("nominal")
    cfg = config.validate(config.merge(config.defaults(), OVER))
    sweep.sweep(stage_config(cfg, "sweep"), "isosceles", tmp / "sweeps")
    avg, st = tmp / "averaging.nc", tmp / "statics.nc"
    nominal.nominal(stage_config(cfg, "nominal"), sorted((tmp / "sweeps").glob("*.nc")), avg)
    cfg_st = config.validate(config.merge(cfg, {"nominal": {"method": "statics"}}))
    nominal.nominal_statics(stage_config(cfg_st, "nominal_statics"), ["isosceles"], [st])
    return avg, st


def test_statics_nominal_is_the_averaged_one_within_0_05_mm_in_the_same_contract(files):
    avg, st = (xr.open_dataset(p) for p in files)
    assert {k: v.dims for k, v in avg.variables.items()} == {k: v.dims for k, v in st.variables.items()}
    assert (avg.attrs["nominal_method"], st.attrs["nominal_method"]) == ("averaging", "statics")
    assert '"method": "statics"' in st.attrs["config"] and '"method": "averaging"' in avg.attrs["config"]
    np.testing.assert_array_equal(avg["pressure"], st["pressure"])
    d = np.linalg.norm(avg["cog"] - st["cog"], axis=-1)
    assert 1e-6 < d.max() < 5e-5  # the averages still oscillate a little; never more than 0.05 mm
    assert np.abs(avg["support"] - st["support"]).max() < 5e-5
    assert float(st["averaging_error"].max()) == 0.0 and "statics" in st["averaging_error"].attrs["comment"]
    assert float(st["cog_std"].max()) == 0.0 and float(st["rolled"].max()) == 0


def test_checks_5_and_7_say_statics_made_the_files_instead_of_passing(files):
    noms = read_nominals(files[1:])
    assert noms["isosceles"].method == "statics"
    r7 = averaging.check_averaging(noms, 5e-5)
    assert r7.status["7"] == SKIP and "static equilibria" in averaging.averaging_verdicts(r7)[0].measured
    r5 = checks.check_timestep(None, noms, SweepSetup(), 0.2)  # no simulation: params unused
    assert r5.status["5"] == SKIP and "no time step" in timestep_verdicts(r5)[0].measured
    avg = read_nominals(files[:1])
    assert averaging.check_averaging(avg, 5e-5).status["7"] != SKIP  # the averaged file is checked


@pytest.mark.parametrize(
    "over, words",
    [
        ({"params": {"cable_exponent": 1.5}}, "statics needs linear cables"),
        ({"sweep": {"mode": "grounded"}}, "statics is the free mode's equilibrium"),
    ],
)
def test_statics_is_refused_where_it_does_not_hold_naming_the_key(over, words):
    cfg = config.merge({"nominal": {"method": "statics"}}, over)
    with pytest.raises(config.ConfigError, match=f"config key nominal.method: {words}"):
        config.validate(cfg)
    config.validate(config.merge(cfg, {"nominal": {"method": "averaging"}}))  # averaging takes it


def test_check_3_of_a_statics_workspace_compares_it_with_statics_and_can_fail(files, tmp_path):
    """Mapped to other faces, the equilibria are the independent statics solve seen from those
    faces (to round-off); a workspace 0.2 mm off on one face fails."""
    from dataclasses import replace

    from tensegrity.io.formats import workspace as wf
    from tensegrity.physics.params import Params
    from tensegrity.validation.statics_mapping import check_mapping_statics

    nominal.workspace({}, files[1:], tmp_path / "workspace.nc")
    ws = wf.read_workspace(tmp_path / "workspace.nc")
    r = check_mapping_statics(Params(), ws, [9, 18], ws.levels, 1e-4, min_per_kind=0)
    assert r.status["3"] == "pass" and r.reference == "statics" and np.nanmax(r.difference) < 1e-9
    assert np.isfinite(r.difference).sum() == 2 * 2 * 4  # 2 faces x pairs 10, 11 x 4 levels
    cog = ws.cog.copy()
    cog[17, :, :, 0] += 2e-4
    bad = check_mapping_statics(Params(), replace(ws, cog=cog), [9, 18], ws.levels, 1e-4, min_per_kind=0)
    assert bad.status["3"] == "fail" and np.nanmax(bad.difference[1]) > 1.9e-4
