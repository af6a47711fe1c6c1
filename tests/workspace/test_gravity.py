"""The gravity-aware workspace and the slope limit as physics: the heading does not matter on
flat ground, the slope-0 strip is flat ground, a slope toward the edge a pair tips over lowers
its tipping pressure, and the unactuated robot's standing limit is the geometric one."""

import numpy as np
import pytest

from tensegrity.io import config
from tensegrity.io.formats import gravity as gf
from tensegrity.physics import dynamics as d
from tensegrity.physics import frames
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.physics.terrain import Terrain
from tensegrity.workspace import gravity as gv
from tensegrity.workspace import slope_limit as sl
from tensegrity.workspace.slopes import heading_of, place, slope_field

pytestmark = pytest.mark.unit
EQUI = topo.face_number(topo.CONTACT_FACES["equilateral"])  # (9,10,12)
P = Params()
G = gv.GravitySetup(strut_damping=0.0)  # the ramp of the undamped robot P


def ramp(**kw) -> gv.GravitySetup:
    return gv.GravitySetup(**{"strut_damping": 0.0, **kw})


@pytest.fixture(scope="module")
def flat():
    """#10 and #11 on (9,10,12) on flat ground, three headings, each simulated."""
    return gv.run(P, EQUI, [10, 11], [0.0], [0.0, 100.0, 230.0], ramp(max_pressure=4.4), flat_once=False)


def test_heading_turns_the_robot_as_asked():
    terrain, centres = slope_field([0.0, 12.0])
    for h in (0.0, 75.0, 250.0):
        s = place(P, EQUI, terrain, centres[1], h)
        got = float(heading_of(d.nodes(s.x, s.q, P.strut_length)[0], EQUI))
        assert (got - h + 180) % 360 - 180 == pytest.approx(0.0, abs=1e-6)


def test_on_flat_ground_the_heading_does_not_matter(flat):
    assert flat.stood.all()
    tip = flat.tip_pressure[0, :, 0]  # #10 tips, over 10-12
    assert np.isfinite(tip).all() and np.ptp(tip) < 0.01
    assert (flat.tip_edge[0, :, 0] == [10, 12]).all()
    assert not flat.rolled[0, :, 1].any()  # #11 barely moves the CoG on this face
    np.testing.assert_allclose(flat.margin[0, 0], flat.margin[0, 1], atol=2e-4)


def test_the_zero_slope_strip_is_flat_ground(flat):
    """The same ramp on the plane z = 0 (no height field) tips #10 at the same pressure, and
    earlier than the free workspace's 4.2 MPa (gravity sags the robot toward the edge)."""
    state = place(P, EQUI, Terrain.flat(), (0.0, 0.0), 0.0)
    level, n = gv.ramp_levels(1.0, 4.4, 0.5, 0.02)
    rec, gone = gv.ramp(P, Terrain.flat(), EQUI, state, np.array([10]), level, n, G)
    tip, _, edge = gv.tip(rec, 0, EQUI, n, gone[0])
    assert edge == (10, 12)
    assert tip == pytest.approx(flat.tip_pressure[0, 0, 0], abs=0.01)
    assert 3.6 < tip < 4.1


def test_tipping_pressure_falls_as_the_slope_runs_down_toward_the_edge():
    rest = frames.rest_frame(EQUI, P.strut_length)[1]
    out = sl.direction(rest, EQUI, (10, 12))
    uphill = np.degrees(np.arctan2(-out[1], -out[0])) % 360  # downhill points across 10-12
    sw = gv.run(P, EQUI, [10], [0.0, 4.0, 8.0, 12.0], [uphill], ramp(max_pressure=4.4))
    tip = sw.tip_pressure[:, 0, 0]
    assert np.all(np.diff(tip) < -0.2), tip
    assert (sw.tip_edge[:, 0, 0] == [10, 12]).all()


def _geometric_limit(face: int, heading: float) -> float:
    """Slope (deg) at which the rigid robot's CoG, projected along gravity onto the ground
    (the contact spheres' radius below the face plane), reaches the edge."""
    cog, tri = frames.rest_frame(face, P.strut_length)
    down = -np.array([np.cos(np.radians(heading)), np.sin(np.radians(heading))])
    lo, hi = 0.0, 60.0
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        proj = cog[:2] + (cog[2] + P.strut_radius) * np.tan(np.radians(mid)) * down
        lo, hi = (mid, hi) if frames.margin_2d(proj, tri[:, :2]) > 0 else (lo, mid)
    return lo


def test_the_standing_limit_tends_to_the_geometric_one_as_the_cables_stiffen():
    """Downhill toward the edge opposite the reference vertex (inradius 88.4 mm): the rigid limit
    is atan(0.0884 m / CoG height) = 21.3 deg. The default robot sags toward the edge and falls
    about 2 deg earlier; with 40 times stiffer cables (same rest length) it stands 0.75 deg below
    the rigid limit and not 0.25 deg above it."""
    h = 90.0
    a = _geometric_limit(EQUI, h)
    height = frames.rest_frame(EQUI, P.strut_length)[0][2] + P.strut_radius
    assert a == pytest.approx(np.degrees(np.arctan(0.0884 / height)), abs=0.05)
    stiff = P.replace(cable_stiffness=4e4, cable_pretension=800.0)
    assert sl.stands(stiff, [EQUI] * 2, [a - 0.75, a + 0.25], [h, h]).tolist() == [True, False]
    assert sl.stands(P, [EQUI] * 2, [a - 3.0, a - 1.5], [h, h]).tolist() == [True, False]


def test_the_dataset_round_trips_and_the_config_names_bad_keys(flat):
    ds = gf.gravity_dataset({"equilateral": flat}, G)
    back = gf.sweeps_from_dataset(ds)["equilateral"]
    np.testing.assert_array_equal(back.tip_pressure, flat.tip_pressure)
    np.testing.assert_array_equal(back.tip_edge, flat.tip_edge)
    assert all(ds[v].attrs["units"] and ds[v].attrs["long_name"] for v in ds.data_vars)
    assert ds.attrs["max_pressure_setting"] == G.max_pressure
    # the cross-key checks stop the configuration before any job; the settings check themselves
    for bad, key in (
        ({"grid_step": 0.25}, "gravity.grid_step"),
        ({"validate_slopes": [7]}, "gravity.validate_slopes"),
        ({"slopes": [15, 0], "validate_slopes": [0]}, "gravity.slopes"),
    ):
        with pytest.raises(config.ConfigError, match=key):
            config.validate({"gravity": bad})
    with pytest.raises(ValueError, match="gravity.grid_step"):
        gv.GravitySetup(grid_step=0.25)
    for bad in ({"slopes": [0, 80]}, {"headings": [360]}, {"max_pressure": 12}, {"colour": 1}):
        with pytest.raises(config.ConfigError, match="gravity"):
            config.validate({"gravity": bad})


def test_a_settling_shared_by_copies_gives_the_same_numbers():
    """`ramp(copies=)` settles the first of each run of equal robots and copies it: the same
    records, bit for bit, as settling every robot (two placements, three pairs each; one of
    them on a slope too steep to stand on, dropped during the settling)."""
    terrain, centres = slope_field([0.0, 40.0])
    state = d.State.concat([place(P, EQUI, terrain, centres[i], 30.0, 3) for i in range(2)])
    level, n = gv.ramp_levels(1.0, 1.0, 0.2, 0.02)
    pairs = np.tile([10, 11, 4], 2)
    one = gv.ramp(P, terrain, EQUI, state, pairs, level, n, G)
    shared = gv.ramp(P, terrain, EQUI, state, pairs, level, n, G, copies=3)
    assert (one[1] <= n).tolist() == [False] * 3 + [True] * 3
    np.testing.assert_array_equal(one[1], shared[1])
    for k in one[0]:
        np.testing.assert_array_equal(one[0][k], shared[0][k])
