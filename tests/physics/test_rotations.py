"""The rotations of physics.state, as dynamics offers them (numpy, so that a job need not import
scipy.spatial) agree with SciPy's Rotation, and place the robot as SciPy's did."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from tensegrity.physics import dynamics as d
from tensegrity.physics import frames
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.physics.terrain import Terrain


def test_axes_are_scipys_matrices_of_any_quaternion():
    q = np.random.default_rng(3).normal(size=(4, 6, 4)) * 2.5  # not unit: both normalise
    want = Rotation.from_quat(q.reshape(-1, 4), scalar_first=True).as_matrix().reshape(4, 6, 3, 3)
    np.testing.assert_allclose(d.axes(q), want, atol=1e-15)
    for k in range(3):  # one body axis alone: the matrix's column
        np.testing.assert_allclose(d.axes(q, k), want[..., k], atol=1e-15)


@pytest.mark.parametrize("b", [[0.0, 0.0, -1.0], [0.3, -0.4, 0.866], [-0.6, 0.0, -0.8]])
def test_align_is_the_smallest_rotation_of_a_onto_b(b):
    rng = np.random.default_rng(5)
    b = np.asarray(b) / np.linalg.norm(b)
    for a in [*rng.normal(size=(20, 3)), b, -b]:
        a = a / np.linalg.norm(a)
        R = frames.align(a, b)
        np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-14)
        assert np.linalg.det(R) == pytest.approx(1.0, abs=1e-14)
        np.testing.assert_allclose(R @ a, b, atol=1e-14)
        if abs(a @ b) < 1 - 1e-9:  # the smallest: by the angle between them, about a x b
            angle = np.arccos(np.clip((np.trace(R) - 1) / 2, -1, 1))
            assert angle == pytest.approx(np.arccos(a @ b), abs=1e-9)
            np.testing.assert_allclose(R @ np.cross(a, b), np.cross(a, b), atol=1e-14)


@pytest.mark.parametrize(
    "terrain", [None, Terrain.slope(15.0, 30.0), Terrain.random(2, amplitude=0.05)], ids=["flat", "slope", "rough"]
)
def test_stand_on_places_the_robot_as_scipy_did(terrain):
    """The face's outward normal turned onto the ground's downward normal, then yaw about it:
    the old SciPy placement (align_vectors, from_rotvec) node for node."""
    prm = Params()
    S = prm.strut_length
    p0 = topo.reference_nodes(S)
    up = terrain.normal_at(0.0, 0.0) if terrain else np.array([0.0, 0.0, 1.0])
    for face in (1, 9, 15, 20):
        for yaw in (0.0, 37.0):
            tri = p0[topo.FACES[face - 1]]
            out = np.cross(tri[1] - tri[0], tri[2] - tri[0])
            out *= np.sign(out @ tri.mean(0)) / np.linalg.norm(out)
            rot = Rotation.from_rotvec(np.radians(yaw) * up) * Rotation.align_vectors([-up], [out])[0]
            want = rot.apply(p0)
            got = d.nodes(*(lambda s: (s.x, s.q))(d.stand_on(prm, face, terrain, yaw_deg=yaw)), S)[0]
            shift = (got - want).mean(0)  # stand_on then lifts the robot onto the ground
            np.testing.assert_allclose(got - shift, want, atol=1e-12)
