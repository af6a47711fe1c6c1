"""The gravity-aware ramp in volts (issue 31): the twisted-string robot driven by a voltage ramp is
the run of those voltages (the motors' angles carried from interval to interval), a higher voltage
leans it further toward the edge its pair tips it over, and on flat ground the heading does not
matter. The tipping voltage against the experiment's lowest rolling voltage: docs/design.md §10
(a ramp at 0.05 V/s tips #10 at 10.08 V, the experiment's bracket is 9.94-10.12 V)."""

import numpy as np
import pytest

from tensegrity.physics import dynamics as d
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.physics.terrain import Terrain
from tensegrity.physics.twisted import TwistedString, Voltages
from tensegrity.workspace import gravity as gv
from tensegrity.workspace.slopes import gravity_frame, place

EQUI = topo.face_number(topo.CONTACT_FACES["equilateral"])  # (9,10,12)
MOTORS = TwistedString()
SETUP = gv.GravitySetup(ramp_rate=4.0, max_pressure=12.0, settle=0.1, grid_step=0.4)


def test_a_voltage_ramp_is_the_run_of_its_voltages_and_leans_the_robot_toward_the_edge():
    """`ramp` simulates one interval at a time; one `simulate` of the same voltages, interval by
    interval in a single call, gives the same CoG at every interval's end (1e-12 m: the same run,
    to round-off), so the motors' state is carried, not restarted. #10 on (9,10,12) tips over
    10-12: the CoG projection's margin only falls while the voltage rises (after the strands
    take up their slack) and 4 s at 12 V lean it by more than 10 mm; it does not tip: the motors
    take longer (about 18 s at 11.1 V in the experiment)."""
    params = SETUP.rolling(Params())
    state = place(params, EQUI, Terrain.flat(), (0.0, 0.0), 0.0)
    level, n = SETUP.levels(hold=4.0)
    rec, gone = gv.ramp(params, Terrain.flat(), EQUI, state, np.array([10]), level, n, SETUP, motors=MOTORS)
    assert gone[0] == rec["pressure"].shape[1]  # not dropped: it did not tip
    volts = np.zeros((1, level.size, topo.N_PAIRS))
    volts[0, :, 9] = level
    every = round(SETUP.interval / SETUP.dt)
    sched = Voltages(np.full(level.size, SETUP.interval), volts)
    _, tr = d.simulate(params, state, sched, Terrain.flat(), SETUP.dt, every, motors=MOTORS)
    cog = gravity_frame(tr.nodes(params.strut_length)[0], EQUI)[0]
    np.testing.assert_allclose(rec["cog"][0, : level.size], cog, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(rec["pressure"][0, : level.size], level)
    margin = rec["margin"][0, n : level.size]
    assert margin[-1] < margin[0] - 0.01
    assert np.all(np.diff(margin[25::25]) < 0)  # every 0.5 s from 2 V on (it rocks by micrometres)


def test_on_flat_ground_the_heading_does_not_matter_in_volts():
    """Two headings on the slope-0 strip are one scene turned: the same margins along the voltage
    grid (2e-4 m, as with the muscles: the contacts' friction cones are polygons). The records
    of a robot that went through the whole ramp without a roll are on the grid (not NaN)."""
    sw = gv.run(Params(), EQUI, [10], [0.0], [0.0, 120.0], SETUP, flat_once=False, motors=MOTORS)
    assert sw.stood.all() and not sw.rolled.any()
    np.testing.assert_allclose(sw.pressure, 0.4 * np.arange(1, 31), rtol=0, atol=1e-12)
    assert np.isfinite(sw.margin).all()
    np.testing.assert_allclose(sw.margin[0, 0], sw.margin[0, 1], atol=2e-4)


def test_the_level_is_bounded_by_the_actuator_before_any_work():
    """12 V is a motor voltage, not a pressure: the pneumatic ramp refuses it, naming the key;
    the motors refuse 30 V."""
    params, state = Params(), place(Params(), EQUI, Terrain.flat(), (0.0, 0.0), 0.0)
    cases = ((gv.GravitySetup(max_pressure=12.0), None, "MPa"), (gv.GravitySetup(max_pressure=30.0), MOTORS, "V"))
    for setup, motors, unit in cases:
        level, n = setup.levels()
        with pytest.raises(ValueError, match=f"gravity.max_pressure: .* {unit} is outside"):
            gv.ramp(params, Terrain.flat(), EQUI, state, np.array([10]), level, n, setup, motors=motors)
