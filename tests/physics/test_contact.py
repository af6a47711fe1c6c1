"""tensegrity.physics.contact: contact face, CoG projection along gravity, rolling edge.

Checked against geometry that is known in closed form: the symmetric robot's support margins
(the in-radius of the equilateral face, S sqrt(6)/4 / (2 sqrt 3) = 88.4 mm for S = 0.5 m), the
downhill shift h tan(angle) of the CoG projection on a slope, and the tipping angle atan(d/h)
of a rigid robot pivoting about an edge.
"""

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from tensegrity.physics import contact as ct
from tensegrity.physics import dynamics as d
from tensegrity.physics import frames
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.physics.terrain import Terrain

EQUI = topo.face_number(topo.CONTACT_FACES["equilateral"])  # (9,10,12)
ISO = topo.face_number(topo.CONTACT_FACES["isosceles"])  # (10,11,12)

R = 0.01  # strut radius, m
IN_RADIUS = 0.5 * math.sqrt(6) / 4 / (2 * math.sqrt(3))  # equilateral face, S = 0.5 m


def standing(face, terrain=None, yaw=0.0):
    s = d.stand_on(Params(), face, terrain or Terrain.flat(), yaw_deg=yaw)
    return d.nodes(s.x, s.q, 0.5)[0]


@pytest.mark.parametrize("face", range(1, 21))
def test_every_face_is_detected_and_stands(face):
    c = ct.analyse(standing(face), Terrain.flat(), R)
    assert c.face == face
    assert c.stands and c.edge is None and c.next_face is None
    assert np.allclose(c.clearance[topo.FACES[face - 1]], 0.0, atol=1e-9)
    # on flat ground the projection is straight below the CoG, in the support plane
    assert np.allclose(c.projection[:2], c.cog[:2], atol=1e-12)
    assert c.projection[2] == pytest.approx(R, abs=1e-12)
    assert c.normal == pytest.approx([0, 0, 1], abs=1e-12)


def test_equilateral_margin_is_the_in_radius():
    c = ct.analyse(standing(EQUI), Terrain.flat(), R)
    assert c.margin == pytest.approx(IN_RADIUS, abs=1e-12)
    assert c.projection_2d == pytest.approx([0, 0], abs=1e-12)


@pytest.mark.parametrize("angle", [5.0, 10.0, 20.0])
def test_projection_along_gravity_on_a_slope_shifts_downhill_by_h_tan(angle):
    """Paper Fig. 10: on a slope the CoG projects along gravity, not along the face normal; the
    two differ by h tan(angle) downhill, h the CoG's height above the support plane."""
    terrain = Terrain.slope(angle)
    p = standing(EQUI, terrain)
    c = ct.analyse(p, terrain, R)
    assert c.face == EQUI
    h = float(np.dot(c.cog - p[topo.FACES[EQUI - 1]].mean(0), c.normal))
    along_normal = c.cog - h * c.normal
    shift = c.projection - along_normal
    assert np.linalg.norm(shift) == pytest.approx(h * math.tan(math.radians(angle)), rel=1e-9)
    assert shift[0] < 0  # the plane rises toward +x: downhill is -x
    assert abs(np.dot(shift, c.normal)) < 1e-12  # stays in the plane


def test_incline_of_a_plane_and_of_rough_ground():
    """Terrain.incline: a plane's tilt wherever it is asked (any azimuth), the tilt of one
    height-field triangle for points inside it, NaN for points on triangles that differ (the
    brake's gate, locomotion.brake.Brake.active)."""
    x, y = np.array([0.0, 0.3, -0.2]), np.array([0.0, 0.1, 0.25])
    for angle, azimuth in ((0.0, 0.0), (15.0, 0.0), (20.0, 130.0)):
        assert Terrain.slope(angle, azimuth).incline(x, y) == pytest.approx(angle, abs=1e-9)
    rough = Terrain.random(seed=1, size=2.0, amplitude=0.05)
    assert np.isnan(rough.incline(x, y))
    i, j, h = 3, 4, rough.spacing  # three points inside the lower triangle of cell (i, j)
    u = rough.origin[0] + h * (i + np.array([0.1, 0.5, 0.1]))
    v = rough.origin[1] + h * (j + np.array([0.1, 0.1, 0.5]))
    z = rough.heights
    n = np.cross([h, 0.0, z[i + 1, j] - z[i, j]], [0.0, h, z[i, j + 1] - z[i, j]])
    assert rough.incline(u, v) == pytest.approx(math.degrees(math.acos(n[2] / np.linalg.norm(n))), abs=1e-6)


def test_steep_slope_does_not_stand_and_names_the_downhill_edge():
    terrain = Terrain.slope(30.0)
    p = standing(EQUI, terrain, yaw=105.0)  # edge 10-12 faces downhill (-x)
    c = ct.analyse(p, terrain, R)
    assert not c.stands and c.margin < 0
    assert c.edge == (10, 12) and c.next_face == ISO


def tipped(face, edge, angle_deg):
    """The rigid symmetric robot on `face`, rotated by angle_deg about `edge` (lifting the rest)."""
    p = standing(face)
    a, b = p[edge[0] - 1], p[edge[1] - 1]
    axis = (b - a) / np.linalg.norm(b - a)
    k = [topo.edge_nodes(face, j) for j in range(3)].index(edge)
    out = ct.edge_outward(p[topo.FACES[face - 1]])[k]
    if np.dot(np.cross(axis, p.mean(0) - a), out) < 0:
        axis = -axis  # rotate so that the CoG moves out over the edge
    return a + Rotation.from_rotvec(math.radians(angle_deg) * axis).apply(p - a)


@pytest.mark.parametrize("face,edge", [(EQUI, (10, 12)), (ISO, (10, 11)), (ISO, (11, 12))])
def test_rolling_edge_and_past_edge_cross_zero_at_the_tipping_angle(face, edge):
    p0 = standing(face)
    rest = ct.judge(p0, face)
    c0 = p0.mean(0)
    h = c0[2] - R
    dist = -ct.past_edge(p0, face, edge, 0.5)
    k = [topo.edge_nodes(face, j) for j in range(3)].index(edge)
    assert dist == pytest.approx(frames.edge_distances(rest.projection_2d, rest.support)[k], abs=1e-12)
    crit = math.degrees(math.atan2(dist, h))
    before, after = tipped(face, edge, crit - 1.0), tipped(face, edge, crit + 1.0)
    assert ct.past_edge(before, face, edge, 0.5) < 0 < ct.past_edge(after, face, edge, 0.5)
    assert ct.judge(before, face).stands
    out = ct.judge(after, face)
    assert not out.stands and out.edge == edge
    assert out.next_face == topo.neighbour(face, edge)


def test_neighbours_give_the_papers_sequence_and_pair_up():
    assert topo.neighbour((9, 10, 12), (10, 12)) == ISO
    assert topo.neighbour((10, 11, 12), (10, 11)) == topo.face_number((6, 10, 11))
    for f in range(1, 21):
        for k in range(3):
            e = topo.edge_nodes(f, k)
            n = topo.neighbour(f, e)
            assert n != f and topo.neighbour(n, e) == f and topo.common_edge(f, n) == e
    # a gap edge joins two isosceles faces, a cable an equilateral and an isosceles one
    assert topo.FACE_TYPES[topo.neighbour(ISO, (11, 12)) - 1] == "isosceles"
    with pytest.raises(ValueError, match="not an edge"):
        topo.neighbour(EQUI, (1, 2))


def test_edge_outward_normals():
    tri = standing(EQUI)[topo.FACES[EQUI - 1]]
    out = ct.edge_outward(tri)
    c = tri.mean(0)
    for k in range(3):
        mid = 0.5 * (tri[k] + tri[(k + 1) % 3])
        assert np.linalg.norm(out[k]) == pytest.approx(1.0)
        assert abs(np.dot(out[k], tri[(k + 1) % 3] - tri[k])) < 1e-12
        assert np.dot(out[k], mid - c) > 0
        assert abs(out[k][2]) < 1e-12  # the face lies flat


def test_no_face_in_the_air_or_when_tipping():
    p = standing(EQUI)
    with pytest.raises(ct.ContactError, match="0 node"):
        ct.contact_face(p + [0, 0, 0.05], Terrain.flat(), R)
    with pytest.raises(ct.ContactError, match="2 node"):
        ct.contact_face(tipped(EQUI, (10, 12), 10.0), Terrain.flat(), R)


def test_three_touching_nodes_that_are_not_a_face_are_refused():
    q = standing(EQUI)
    q[8, 2] += 0.2  # lift node 9 and put node 1 down: 1, 10, 12 close no face
    q[0, 2] = R
    assert not any(sorted(f.tolist()) == [0, 9, 11] for f in topo.FACES)
    with pytest.raises(ct.ContactError, match=r"\(1, 10, 12\), are not a face"):
        ct.contact_face(q, Terrain.flat(), R)


def test_bad_input_is_refused():
    p = standing(EQUI)
    q = p.copy()
    q[3, 1] = np.nan
    with pytest.raises(ValueError, match="NaN"):
        ct.analyse(q, Terrain.flat(), R)
    with pytest.raises(ValueError, match="free mode"):
        ct.analyse(p, Terrain.none(), R)
    with pytest.raises(ValueError, match="nothing under node"):
        ct.clearance(p + [5.0, 0, 0], Terrain.random(seed=1, size=1.0), R)
    with pytest.raises(ValueError, match="unknown face"):
        ct.judge(p, (1, 2, 3))
    with pytest.raises(ValueError, match="shape"):
        ct.clearance(p[:10], Terrain.flat(), R)
