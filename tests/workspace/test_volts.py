"""The workspace pipeline in volts (issue 31): the twisted-string actuator's staircase, the unit in
the files (`io.formats.actuation`), and the stages and commands that refuse it by name. The whole
pipeline in volts runs in tests/workflow/test_volts_pipeline.py (slow tier)."""

import numpy as np
import pytest

from tensegrity.io import config
from tensegrity.io.formats import actuation
from tensegrity.physics import frames
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.physics.twisted import TwistedString
from tensegrity.stages.config import STAGES, VOLTS, actuator_error, stage_config
from tensegrity.workspace import sweep as sw

FACE = topo.CONTACT_FACES["equilateral"]


def test_a_voltage_staircase_pulls_the_cog_where_the_muscles_of_that_pair_do():
    """Both actuators shorten the same two cables of a pair, so in the free mode (no gravity) the
    CoG leaves the rest point in the same direction; the motors twist their strands further the
    longer a voltage is held, so the CoG's distance from rest only grows during a level. Tolerance:
    the two laws load the cables differently (a muscle's tension falls with its length, a twisted
    string's rises), so the paths agree in direction to a few degrees, not exactly (cos > 0.99)."""
    prm = Params()
    muscle = sw.run(prm, FACE, [10], sw.SweepSetup(levels=(0.6, 1.2), hold=0.2))
    motor = sw.run(prm, FACE, [10], sw.SweepSetup(levels=(9.0,), hold=2.5, record_every=100), TwistedString())
    assert np.all(motor.pressure_cmd[0] == 9.0)  # the levels are volts, as commanded
    rest = frames.rest_frame(FACE, prm.strut_length)[0]  # the unactuated robot's CoG
    a, b = (r.cog[0, -1, :2] - rest[:2] for r in (muscle, motor))
    assert np.linalg.norm(b) > 1e-3  # 9 V for 2.5 s moves the CoG by more than 1 mm
    assert a @ b / (np.linalg.norm(a) * np.linalg.norm(b)) > 0.99
    dist = np.linalg.norm(motor.cog[0, :, :2] - rest[:2], axis=-1)
    assert np.all(np.diff(dist[5:]) > -1e-7)  # after the first samples (the strands take up slack)


def test_a_staircase_run_level_by_level_is_the_same_run():
    """The sweep in volts runs one level at a time to read the motors' twist at the end of each
    (`sweep.run_levels`); each call continues from the last one's state (time, motor angles and
    speeds), so the trajectory is the one of a single call, to round-off (1e-12 m)."""
    from tensegrity.physics import dynamics as d
    from tensegrity.physics.terrain import Terrain
    from tensegrity.physics.twisted import Voltages

    prm, motors = Params().replace(gravity=0.0), TwistedString()
    state = d.stand_on(prm, FACE, Terrain.none(), batch=2)
    sched = Voltages.staircase([9, 10], [9.0, 12.0], 0.3)
    _, whole = d.simulate(prm, state, sched, Terrain.none(), 1e-4, 100, motors=motors)
    parts, locked = sw.run_levels(prm, state, sched, Terrain.none(), 1e-4, 100, motors)
    assert np.array_equal(parts.t, whole.t) and np.array_equal(parts.pressure, whole.pressure)
    assert np.abs(parts.x - whole.x).max() < 1e-12 and np.abs(parts.q - whole.q).max() < 1e-12
    assert locked.shape == (2, 2) and not locked.any()  # 0.6 s twists far less than the lock


def test_the_unit_is_in_the_file_and_a_pneumatic_file_is_left_as_it_was():
    import xarray as xr

    ds = xr.Dataset(
        {"tip_pressure": ("pair", [np.nan], {"units": "MPa", "long_name": "least pressure at which it tips"})},
        coords={"pressure": ("pressure", [1.0], {"units": "MPa", "long_name": "muscle pressure"})},
    )
    assert actuation.relabel(ds, "pneumatic") is ds and actuation.kind_of(ds) == "pneumatic"
    v = actuation.relabel(ds, "twisted_string")
    assert v.attrs["actuator"] == "twisted_string" and actuation.kind_of(v) == "twisted_string"
    assert [v[k].attrs["units"] for k in ("pressure", "tip_pressure")] == ["V", "V"]
    assert v["pressure"].attrs["long_name"] == "motor voltage"
    assert v["tip_pressure"].attrs["long_name"] == "least motor voltage at which it tips"
    assert ds["pressure"].attrs["units"] == "MPa" and "actuator" not in ds.attrs  # the input is unchanged
    assert actuation.words("held at pressure_a (MPa)", "twisted_string") == "held at pressure_a (V)"
    with pytest.raises(ValueError, match="mix actuators"):
        actuation.common_kind([ds, v])
    doc = actuation.document({"units": {"pressure": "MPa", "cog": "m"}, "evaluate": "p in MPa"}, "twisted_string")
    assert doc["units"]["pressure"] == "V" and doc["actuator"] == "twisted_string" and doc["evaluate"] == "p in V"
    with pytest.raises(ValueError, match="x.json is of the twisted_string actuator .*tensegrity query"):
        actuation.require_pneumatic(doc, "x.json", "tensegrity query")


def test_levels_are_read_in_the_actuators_unit_and_bounded_by_it():
    cfg = config.load(None, ["actuator.kind=twisted_string", "sweep.levels=[6.0, 11.1, 24.0]"])
    assert cfg["sweep"]["levels"] == [6.0, 11.1, 24.0]
    with pytest.raises(config.ConfigError, match=r"sweep.levels\[1\]: 25.0 is greater than the maximum of 24"):
        config.load(None, ["actuator.kind=twisted_string", "sweep.levels=[6.0, 25.0]"])
    with pytest.raises(config.ConfigError, match=r"two_pair.levels\[1\]: 11.0 is greater than the maximum of 10 MPa"):
        config.load(None, ["two_pair.levels=[6.0, 11.0]"])


def test_only_the_workspace_stages_run_in_volts_the_others_refuse_naming_the_key():
    pneumatic = config.load(None)
    volts = config.load(None, ["actuator.kind=twisted_string"])
    for stage in STAGES:
        assert actuator_error(pneumatic, stage) is None
        reads_strings = "actuator.twisted_string" in STAGES[stage].keys  # the prototype's experiment, calibrate
        # the pneumatic files' provenance as before
        assert ("actuator" in stage_config(pneumatic, stage)) == reads_strings, stage
        why = actuator_error(volts, stage)
        assert (why is None) == (stage in VOLTS), stage
        if why is None:
            assert stage_config(volts, stage)["actuator"] == volts["actuator"]
        else:
            assert why.startswith("config key actuator.kind: 'twisted_string'") and f"stage {stage}" in why


@pytest.mark.parametrize(
    "argv",
    [
        ["stage", "study_merge", "out_path=never.nc"],
        ["export", "mjcf", "--out", "never.xml"],
    ],
)
def test_commands_that_do_not_run_in_volts_refuse_before_any_work(argv, tmp_path, monkeypatch, capsys):
    from tensegrity.cli import main

    monkeypatch.chdir(tmp_path)
    assert main([*argv, "--set", "actuator.kind=twisted_string"]) == 3
    assert "config key actuator.kind: 'twisted_string'" in capsys.readouterr().err
    assert not list(tmp_path.iterdir())
