"""Topology and frames (docs/design.md §1-2)."""

import numpy as np
import pytest

from tensegrity.physics import frames
from tensegrity.physics import topology as topo


def test_lengths_of_the_symmetric_state():
    p = topo.reference_nodes(0.5)
    strut = np.linalg.norm(p[topo.STRUTS[:, 0]] - p[topo.STRUTS[:, 1]], axis=1)
    cable = np.linalg.norm(p[topo.CABLES[:, 0]] - p[topo.CABLES[:, 1]], axis=1)
    gap = np.linalg.norm(p[topo.GAPS[:, 0]] - p[topo.GAPS[:, 1]], axis=1)
    np.testing.assert_allclose(strut, 0.5, atol=1e-12)
    np.testing.assert_allclose(cable, 0.5 * np.sqrt(6) / 4, atol=1e-12)
    np.testing.assert_allclose(gap, 0.25, atol=1e-12)
    assert abs(strut[0] / cable[0] - np.sqrt(8 / 3)) < 1e-12


def test_faces_are_the_icosahedron_faces_and_every_cable_is_on_one_of_each_kind():
    edges = {frozenset(e) for e in np.concatenate([topo.CABLES, topo.GAPS]).tolist()}
    cables = {frozenset(e) for e in topo.CABLES.tolist()}
    count = {c: {"equilateral": 0, "isosceles": 0} for c in cables}
    for f, kind in zip(topo.FACES, topo.FACE_TYPES):
        sides = [frozenset((int(f[k]), int(f[(k + 1) % 3]))) for k in range(3)]
        assert all(s in edges for s in sides)
        n_cables = sum(s in cables for s in sides)
        assert n_cables == (3 if kind == "equilateral" else 2)
        for s in sides:
            if s in cables:
                count[s][kind] += 1
        if kind == "isosceles":  # written (gap a, gap b | apex)
            assert frozenset(f[:2].tolist()) not in cables
    assert all(v == {"equilateral": 1, "isosceles": 1} for v in count.values())
    assert len({frozenset(f.tolist()) for f in topo.FACES}) == 20


def test_pairs_partition_the_cables_and_meet_at_their_node():
    assert sorted(topo.PAIR_CABLES.ravel().tolist()) == list(range(24))
    for v, pair in enumerate(topo.PAIRS):
        assert all(v in c for c in pair.tolist())


def test_support_frame_is_right_handed_with_y_to_the_reference_vertex():
    p = topo.reference_nodes()
    for f in range(20):
        tri = p[topo.FACES[f]]
        o, R = frames.support_frame(tri, topo.FACE_REFERENCE[f], p.mean(0))
        np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-12)
        assert np.linalg.det(R) == pytest.approx(1.0)
        local = frames.to_frame(tri, o, R)
        assert np.allclose(local[:, 2], 0, atol=1e-12)
        ref = local[topo.FACE_REFERENCE[f]]
        assert abs(ref[0]) < 1e-12 and ref[1] > 0
        assert frames.to_frame(p.mean(0), o, R)[2] > 0  # the robot is on +z


def test_margin_is_signed_distance_to_the_triangle():
    tri = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    assert frames.margin_2d(np.array([0.1, 0.2]), tri) == pytest.approx(0.1)
    assert frames.margin_2d(np.array([0.5, -0.3]), tri) == pytest.approx(-0.3)
    assert frames.margin_2d(np.array([-0.3, -0.4]), tri) == pytest.approx(-0.5)  # nearest corner


@pytest.mark.parametrize("bad", [0, 21, 2.5, (1, 2, 3), True])
def test_unknown_face_is_refused(bad):
    with pytest.raises(ValueError, match="unknown face"):
        topo.face_number(bad)


@pytest.mark.parametrize("bad", [0, 13, -1, 1.5])
def test_unknown_pair_is_refused(bad):
    with pytest.raises(ValueError, match="unknown pair"):
        topo.check_pair(bad)
