"""The slope limit with optimised actions (issue 30, item 1): the gravity-aware ramp driven by
weight vectors is the pair ramp for unit vectors, and on a slope where no single pair rolls the
robot uphill, the action the statics optimise for the pose does."""

import numpy as np

from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.workspace import gravity as gv
from tensegrity.workspace import slope_limit as sl
from tensegrity.workspace.sensitivity import edge_action, grounded
from tensegrity.workspace.slopes import place, slope_field

SETUP = gv.GravitySetup(max_pressure=0.4, settle=0.1)
PARAMS = SETUP.rolling(Params())
FACE = topo.face_number((9, 10, 12))


def test_unit_weights_ramp_as_the_pair():
    terrain, centres = slope_field([10.0])
    state = place(PARAMS, FACE, terrain, centres[0], 0.0, 2)
    level, n_settle = SETUP.levels()
    a = gv.ramp(PARAMS, terrain, FACE, state, np.array([10, 12]), level, n_settle, SETUP)
    b = gv.ramp(PARAMS, terrain, FACE, state, np.eye(12)[[9, 11]], level, n_settle, SETUP)
    c = gv.ramp(PARAMS, terrain, FACE, state, topo.cable_levels(np.eye(12)[[9, 11]]), level, n_settle, SETUP)
    for name in a[0]:
        np.testing.assert_array_equal(a[0][name], b[0][name], err_msg=name)
        np.testing.assert_array_equal(a[0][name], c[0][name], err_msg=name)  # per cable (R, 24)
    np.testing.assert_array_equal(a[1], b[1])
    np.testing.assert_array_equal(a[1], c[1])


def test_optimised_action_rolls_uphill_where_no_single_pair_does():
    """12 deg, uphill along heading 0 of the equilateral face: the uphill edge is (9, 10) (its
    outward normal 30 deg off uphill). Ramped to 5 MPa one by one, no pair rolls the robot over
    it on 10 or 15 deg (results/workspace_gravity.nc: pair 9, the pair of that edge on flat
    ground, does not roll it at all); the action the statics optimise over it for the pose,
    pairs 7 and 9 together, does, at a lower pressure than pair 9 needs on flat ground."""
    setup = gv.GravitySetup()
    params = setup.rolling(Params())
    k = [topo.edge_nodes(FACE, i) for i in range(3)].index((9, 10))
    a = edge_action(grounded(params, FACE, sl.pose(params, FACE, 12.0, 0.0)), k, setup.max_pressure, 0.005)
    assert a is not None and set(np.flatnonzero(a.weights) + 1) == {7, 9}
    terrain, centres = slope_field([12.0])
    state = place(params, FACE, terrain, centres[0], 0.0, 2)
    level, n_settle = setup.levels()
    rec, gone = gv.ramp(params, terrain, FACE, state, np.vstack([np.eye(12)[8], a.weights]), level, n_settle, setup)
    alone, multi = (gv.tip(rec, b, FACE, n_settle, gone[b]) for b in range(2))
    assert alone[2] != (9, 10) and multi[2] == (9, 10), (alone, multi)
    assert multi[0] < 4.2  # MPa: pair 9 alone on flat ground (control.roll: 4.1-4.2)


def test_both_searches_never_below_the_least_total_alone():
    """The uphill limit from the equilateral face at heading 270 (its one uphill edge (10, 12)),
    2 bisection steps from 10 deg (about the single-pair limit) up to 35 deg (about the stand
    limit's high end): with edge_action's actions alone none rolls the robot (the statics find
    none over (10, 12) from 16 deg on); with the deepest-crossing action tried where it fails,
    the bracket is never lower (`slope_multi` docstring) and here higher, and the file says
    which search found the action."""
    from types import SimpleNamespace

    from tensegrity.workspace.sensitivity import ActuationSettings
    from tensegrity.workspace.slope_multi import SEARCHES, multi_limits

    setup = gv.GravitySetup()
    params = setup.rolling(Params())
    face = topo.face_number(topo.CONTACT_FACES["equilateral"])
    shape = (3, 1, 1)
    lim = sl.SlopeLimits(
        sl.KINDS,
        ("equilateral",),
        np.array([270.0]),
        *(np.full(shape, np.nan) for _ in range(2)),
        np.array([35.0, 10.0, 35.0]).reshape(shape),  # stand, uphill (single pair), downhill (none to do)
        np.zeros(shape, int),
        np.full(shape, np.nan),
        np.full(shape, "", dtype=object),
        np.array([35.5, 10.5, 35.5]).reshape(shape),
    )
    sweeps = {"equilateral": SimpleNamespace(face=face)}
    alone, both = (
        multi_limits(None, params, sweeps, lim, setup, ActuationSettings(), 2, s) for s in (SEARCHES[:1], SEARCHES)
    )
    assert both.simulated[1, 0, 0] >= alone.simulated[1, 0, 0], (both.simulated, alone.simulated)
    assert alone.simulated[1, 0, 0] == 10.0 and alone.search[1, 0, 0] == 0
    assert both.simulated[1, 0, 0] > 20.0 and both.search[1, 0, 0] == 2
    assert np.count_nonzero(both.weights[1, 0, 0]) > 2
