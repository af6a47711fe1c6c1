"""Bad input and blown-up runs stop loudly."""

from dataclasses import replace

import numpy as np
import pytest

from tensegrity.physics import dynamics as d
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.physics.schedule import Schedule
from tensegrity.physics.terrain import Terrain

EQUI = topo.face_number(topo.CONTACT_FACES["equilateral"])  # (9,10,12)


@pytest.mark.parametrize(
    "key,value",
    [
        ("strut_mass", 0.0),
        ("strut_length", -0.5),
        ("cable_stiffness", 0.0),
        ("cable_rest_length", -0.1),
        ("friction", float("nan")),
        ("cable_damping", -1.0),
    ],
)
def test_invalid_parameters_are_named(key, value):
    with pytest.raises(ValueError, match=key):
        Params(**{key: value})


def test_unknown_parameter_is_named():
    with pytest.raises(ValueError, match="stiffnes"):
        Params.from_dict({"stiffnes": 3.0})


@pytest.mark.parametrize("bad", [-0.1, float("nan"), 11.0])
def test_pressure_out_of_range(bad):
    with pytest.raises(ValueError, match="MPa"):
        Schedule.staircase([10], [0.4, bad], 1.0)


def test_unknown_pair_and_face():
    with pytest.raises(ValueError, match="unknown pair 13"):
        Schedule.staircase([13], [0.4], 1.0)
    with pytest.raises(ValueError, match="unknown face"):
        d.stand_on(Params(), (1, 2, 3))


def test_nan_state_is_refused_before_stepping():
    s = d.stand_on(Params(), EQUI, batch=2)
    x = s.x.copy()
    x[1, 2, 0] = np.nan
    with pytest.raises(ValueError, match="robot 1"):
        d.simulate(Params(), replace(s, x=x), Schedule.constant(np.zeros(12), 0.01))


def test_blow_up_names_robot_time_and_quantity():
    params = Params(gravity=0.0, cable_stiffness=np.array([1000.0, 1e8]))
    s = d.stand_on(params, EQUI, Terrain.none(), batch=2)
    pres = np.zeros((2, 12))
    pres[:, 9] = 2.0
    with pytest.raises(d.SimulationError, match=r"robot 1 of the batch: .* at t = [0-9.]+ s"):
        d.simulate(params, s, Schedule.constant(pres, 0.1), Terrain.none(), 1e-3)


def test_robot_off_the_terrain_is_an_error():
    terrain = Terrain.random(seed=1, size=1.0)
    with pytest.raises(ValueError, match="nothing under the robot"):
        d.stand_on(Params(), EQUI, terrain, position=(3.0, 0.0))
    s = d.stand_on(Params(), EQUI, terrain, position=(0.2, 0.0))
    s = replace(s, v=s.v + [5.0, 0, 0])  # thrown off the edge of a 1 m field
    with pytest.raises(d.SimulationError, match="no terrain under it"):
        d.simulate(Params(), s, Schedule.constant(np.zeros(12), 1.0), terrain)
