"""One definition per rule (docs/design.md §2): the support frame of a face, the rest state, the
crossed edge, the first margin crossing, the on-face rule, the terrain spec, the hold of a ramp
and the whole-number check, each tested against geometry known in closed form, against the rule
it replaced or on a worked sequence."""

import numpy as np
import pytest

from tensegrity.physics import contact, frames, schedule, terrain
from tensegrity.physics import topology as topo
from tensegrity.physics.terrain import Terrain

EQUI = topo.face_number(topo.CONTACT_FACES["equilateral"])


@pytest.mark.parametrize("face", range(1, 21))
def test_face_frame_is_orthonormal_with_y_to_the_reference_corner_and_z_into_the_robot(face):
    p = topo.reference_nodes(0.5)
    origin, rot = frames.face_frame(p, face)
    np.testing.assert_allclose(rot @ rot.T, np.eye(3), atol=1e-12)
    support = p[topo.FACES[face - 1]]
    np.testing.assert_allclose(origin, support.mean(axis=0), atol=1e-15)
    ref = support[topo.FACE_REFERENCE[face - 1]] - origin
    assert np.dot(rot[1], ref) == pytest.approx(np.linalg.norm(ref))  # +y through the corner
    assert np.dot(rot[2], p.mean(axis=0) - origin) > 0  # +z into the robot


def test_face_frame_on_a_batch_equals_the_frame_of_each_robot():
    rng = np.random.default_rng(0)
    p = topo.reference_nodes(0.5) + 0.01 * rng.standard_normal((4, 5, 12, 3))
    origin, rot = frames.face_frame(p, EQUI)
    o1, r1 = frames.face_frame(p[2, 3], EQUI)
    np.testing.assert_allclose(origin[2, 3], o1, atol=1e-15)
    np.testing.assert_allclose(rot[2, 3], r1, atol=1e-15)


@pytest.mark.parametrize("strut_length", [0.3, 0.5, 0.8])
def test_rest_frame_scales_with_the_strut_length(strut_length):
    cog, support = frames.rest_frame(EQUI, strut_length)
    cog0, support0 = frames.rest_frame(EQUI, 0.5)
    np.testing.assert_allclose(cog, cog0 * strut_length / 0.5, atol=1e-15)
    np.testing.assert_allclose(support, support0 * strut_length / 0.5, atol=1e-15)
    # equilateral face of the regular icosahedron: circumradius = edge / sqrt(3), CoG on the axis
    edge = strut_length * np.sqrt(6) / 4
    np.testing.assert_allclose(np.linalg.norm(support[:, :2], axis=1), edge / np.sqrt(3), atol=1e-12)
    np.testing.assert_allclose(cog[:2], 0.0, atol=1e-15)
    cog[:] = 1.0  # a copy: the cached rest state is not touched
    assert frames.rest_frame(EQUI, strut_length)[0][0] != 1.0


def test_crossed_edge_names_the_violated_edge_and_none_inside():
    support = np.array([[0.0, 1.0], [-0.866, -0.5], [0.866, -0.5]])
    assert frames.crossed_edge(np.zeros(2), support) is None
    for k in range(3):  # just outside the middle of edge k
        mid = 0.5 * (support[k] + support[(k + 1) % 3])
        assert frames.crossed_edge(1.2 * mid, support) == k
    assert topo.edge_nodes(EQUI, 0) == tuple(sorted(int(n) + 1 for n in topo.FACES[EQUI - 1][:2]))


def test_first_crossing_interpolates_and_reports_the_first_sample_outside():
    assert frames.first_crossing([0.0, 1.0, 2.0, 3.0], [0.03, 0.02, 0.01, -0.01]) == (2.5, 3)
    p, k = frames.first_crossing([1.0, 2.0], [0.02, 0.01])
    assert np.isnan(p) and k == -1
    assert frames.first_crossing([0.4, 0.8], [-0.01, -0.02]) == (0.4, 0)  # outside from the start


def test_crossing_gives_the_pressure_the_sample_and_the_edge_by_its_nodes():
    support = np.array([[0.0, 1.0], [-0.866, -0.5], [0.866, -0.5]])
    mid = 0.5 * (support[1] + support[2])  # edge 1 joins corners 1 and 2
    path = np.array([0.0, 0.5, 1.2])[:, None] * mid  # CoG (3, 2) m walking out across edge 1
    margin, tri = frames.margin_2d(path, support), np.broadcast_to(support, (3, 3, 2))
    p, k, edge = frames.crossing([1.0, 2.0, 3.0], margin, path, tri, EQUI)
    assert (p, k) == frames.first_crossing([1.0, 2.0, 3.0], margin) and k == 2
    assert edge == topo.edge_nodes(EQUI, 1) and edge[0] < edge[1]
    assert frames.crossing([1.0, 2.0], margin[:2], path[:2], tri[:2], EQUI)[1:] == (-1, None)


def test_resting_face_is_the_one_on_face_rule():
    p = topo.reference_nodes(0.5)
    for face in (EQUI, 3, 17):
        origin, rot = frames.face_frame(p, face)
        world = (p - origin) @ rot.T  # the face's frame as the world: the face lies at z = 0
        gap = contact.clearance(world, Terrain.flat(), 0.0)
        assert contact.resting_face(gap, 1e-9) == face
        assert contact.face_from_gaps(gap, 1e-9) == face
        lifted = gap.copy()
        lifted[topo.FACES[face - 1][0]] += 0.02  # one corner off the ground: no face rests
        assert contact.resting_face(lifted, 0.01) == 0
        batch = np.stack([gap, lifted])
        np.testing.assert_array_equal(contact.resting_face(batch, np.array([0.01, 0.01])), [face, 0])


@pytest.mark.parametrize(
    "spec, kind",
    [
        ("flat", "plane"),
        ("none", "none"),
        ("slope:12", "plane"),
        ("slope:12:90", "plane"),
        ("random:3", "heightfield"),
        ("random:3:0.05", "heightfield"),
    ],
)
def test_terrain_spec(spec, kind):
    assert terrain.from_spec(spec).kind == kind


def test_terrain_spec_random_is_the_same_field_every_time():
    a, b = terrain.from_spec("random:3"), terrain.from_spec("random:3")
    np.testing.assert_array_equal(a.heights, b.heights)
    assert a.heights.shape[0] * a.spacing == pytest.approx(terrain.SPEC_FIELD_SIZE + a.spacing)
    assert terrain.from_spec("random:3:0.05").heights.std() > 1.5 * a.heights.std()


@pytest.mark.parametrize(
    "spec", ["hill", "slope", "slope:x", "random:1.5", "random:-1", "random:2:0", "flat:3", "slope:nan"]
)
def test_bad_terrain_spec_is_named(spec):
    with pytest.raises(ValueError, match="terrain"):
        terrain.from_spec(spec)


def _holds(lifted, rearm, budget=np.inf):
    """Whether each check of a ramp (interval 0.02 s, hold_time 0.06 s) holds, by
    `schedule.hold_step`, for the lifts `lifted` (n, ...) bool."""
    holding, held, armed, spent, out = False, 0.0, True, 0.0, []
    for up in lifted:
        holding, held, armed, spent = schedule.hold_step(holding, held, armed, up, 0.02, 0.06, rearm, spent, budget)
        out.append(holding)
    return np.array(out)


def test_hold_step_holds_hold_time_then_rearms_as_asked_within_its_budget():
    up = np.array([0, 1, 1, 1, 1, 1, 0, 1], bool)  # a node lifts, stays up, comes down, lifts
    held = [0, 1, 1, 1, 0]  # three intervals (0.06 s), then the ramp
    assert _holds(up, rearm=False).tolist() == held + [0, 0, 1]  # not again until it is down
    assert _holds(up, rearm=True).tolist() == held + [1, 1, 1]  # again at once
    assert _holds(up, rearm=True, budget=0.06).tolist() == held + [0, 0, 0]  # 0.06 s in all
    robots = np.stack([up, ~up, np.roll(up, 2)], axis=1)  # vectorised: each its own
    np.testing.assert_array_equal(
        _holds(robots, rearm=False), np.stack([_holds(r, rearm=False) for r in robots.T], axis=1)
    )


@pytest.mark.parametrize("rearm", [False, True])
@pytest.mark.parametrize("budget", [np.inf, 0.06])
def test_hold_step_for_one_robot_in_floats_gives_the_arrays_numbers(rearm, budget):
    """A roll's check passes Python bools and floats (`control.roll_controller`): the same
    holding, held, armed and spent, to the bit, as numpy's arrays of one, and floats back."""
    rng = np.random.default_rng(3)
    state = (False, 0.0, True, 0.0)
    arrays = tuple(np.asarray(v) for v in state)
    for up in rng.random(60) < 0.6:
        state = schedule.hold_step(*state[:3], bool(up), 0.02, 0.06, rearm, state[3], budget)
        arrays = schedule.hold_step(*arrays[:3], np.asarray(up), 0.02, 0.06, rearm, arrays[3], budget)
        assert [type(v) for v in state] == [bool, float, bool, float]
        assert state == tuple(a.item() for a in arrays)


def test_whole_steps_within_a_millionth_of_a_step():
    assert schedule.whole_steps(0.02, 1e-4) and schedule.whole_steps(1.0, 50 * 1e-4)
    assert not schedule.whole_steps(0.02, 3e-4) and not schedule.whole_steps(0.2, 0.3)
