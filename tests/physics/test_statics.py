"""Static-equilibrium solver (tensegrity.physics.statics): symmetric state, gradient, force balance,
and the tipping pressures of docs/design.md §4."""

import math

import numpy as np
import pytest

from tensegrity.physics import statics as st
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params

P = Params()
EQ_FACE, ISO_FACE = (9, 10, 12), (10, 11, 12)


def _pressure(**pairs):
    p = np.zeros(topo.N_PAIRS)
    for name, val in pairs.items():
        p[int(name[1:]) - 1] = val
    return p


def _tensions(params, nodes, pressure):
    """Cable tensions (24,) N straight from eq. 2 with eq. 1 (a = 1, zero velocity)."""
    K, L = params.cable_stiffness, params.cable_rest_length
    ln = np.linalg.norm(nodes[topo.CABLES[:, 1]] - nodes[topo.CABLES[:, 0]], axis=1)
    out = np.empty(topo.N_CABLES)
    for j, (l, pair) in enumerate(zip(ln, topo.CABLE_PAIR)):
        act = params.muscle_gain * pressure[pair] * max(0.0, l - params.muscle_min_length)
        out[j] = max(0.0, K * (l - L) + act)
    return out


def test_zero_pressure_is_the_symmetric_state():
    nodes = st.equilibrium(P, np.zeros(topo.N_PAIRS))
    ln = np.linalg.norm(nodes[topo.CABLES[:, 1]] - nodes[topo.CABLES[:, 0]], axis=1)
    np.testing.assert_allclose(ln, P.strut_length * math.sqrt(6) / 4, rtol=0, atol=1e-7)
    struts = np.linalg.norm(nodes[topo.STRUTS[:, 0]] - nodes[topo.STRUTS[:, 1]], axis=1)
    np.testing.assert_allclose(struts, P.strut_length, rtol=0, atol=1e-12)
    # the gauge (centroid at origin, best-fit rotation) returns the reference coordinates
    np.testing.assert_allclose(nodes, topo.reference_nodes(P.strut_length), rtol=0, atol=1e-7)


def test_gradient_matches_finite_differences():
    rng = np.random.default_rng(1)
    ref = topo.reference_nodes(P.strut_length)
    a, b = ref[topo.STRUTS[:, 0]], ref[topo.STRUTS[:, 1]]
    x = 0.5 * (a + b) + 0.01 * rng.standard_normal((6, 3))
    d = (a - b) * rng.uniform(1.5, 3.0, (6, 1)) + 0.05 * rng.standard_normal((6, 3))  # |d| != 1
    k, lstar = st.cable_law(P, _pressure(p10=3.0, p4=1.0))
    U, gx, gd = st.cable_energy(x, d, P.strut_length, k, lstar)
    assert U > 0
    h = 1e-7
    for var, grad in ((x, gx), (d, gd)):
        fd = np.empty_like(var)
        for idx in np.ndindex(var.shape):
            var[idx] += h
            up = st.cable_energy(x, d, P.strut_length, k, lstar)[0]
            var[idx] -= 2 * h
            dn = st.cable_energy(x, d, P.strut_length, k, lstar)[0]
            var[idx] += h
            fd[idx] = (up - dn) / (2 * h)
        # central differences: truncation ~h^2 * U''' and round-off ~1e-16 U / h, both < 1e-5 N
        np.testing.assert_allclose(grad, fd, rtol=1e-6, atol=1e-5)


@pytest.mark.parametrize("pressure", [_pressure(p10=2.4), _pressure(p11=4.0, p3=1.5, p7=0.8)])
def test_equilibrium_balances_every_strut(pressure):
    nodes = st.equilibrium(P, pressure)
    t = _tensions(P, nodes, pressure)
    assert t.max() > 20.0  # the cables are loaded, so a zero residual is not trivial
    force = np.zeros((topo.N_NODES, 3))
    for j, (n1, n2) in enumerate(topo.CABLES):
        u = (nodes[n2] - nodes[n1]) / np.linalg.norm(nodes[n2] - nodes[n1])
        force[n1] += t[j] * u
        force[n2] -= t[j] * u
    for s, (na, nb) in enumerate(topo.STRUTS):
        centre = 0.5 * (nodes[na] + nodes[nb])
        net = force[na] + force[nb]
        torque = np.cross(nodes[na] - centre, force[na]) + np.cross(nodes[nb] - centre, force[nb])
        # The solver converges to round-off; 1e-8 N (1e-9 of the tensions) is far below what a
        # 1e-7 m shape error would leave (~ K * 1e-7 m = 1e-4 N).
        assert np.abs(net).max() < 1e-8, f"strut {s + 1}: net force {net} N"
        assert np.abs(torque).max() < 1e-8, f"strut {s + 1}: net torque {torque} N m"
        assert abs(np.linalg.norm(nodes[na] - nodes[nb]) - P.strut_length) < 1e-12


def test_solution_does_not_depend_on_the_start():
    pressure = _pressure(p10=3.0)
    rng = np.random.default_rng(2)
    start = topo.reference_nodes(P.strut_length) + 0.01 * rng.standard_normal((12, 3))
    np.testing.assert_allclose(st.equilibrium(P, pressure, start=start), st.equilibrium(P, pressure), rtol=0, atol=1e-9)


@pytest.mark.parametrize("face, ref_node", [(EQ_FACE, 9), (ISO_FACE, 10)])
def test_support_frame_of_the_deformed_face(face, ref_node):
    nodes = st.equilibrium(P, _pressure(p10=2.4))
    cog, tri = st.support_cog(nodes, face)
    np.testing.assert_array_equal(st.support_cog(nodes, topo.face_number(face))[0], cog)
    np.testing.assert_allclose(tri[:, 2], 0.0, atol=1e-12)  # corners in the face plane
    np.testing.assert_allclose(tri.mean(axis=0), 0.0, atol=1e-12)  # origin at the centroid
    ref = tri[list(topo.FACES[topo.face_number(face) - 1] + 1).index(ref_node)]
    assert abs(ref[0]) < 1e-12 and ref[1] > 0  # reference vertex on +y
    assert cog[2] > 0  # z points into the robot
    # frame is rigid: distances from the CoG to the corners are those in the world
    np.testing.assert_allclose(
        np.linalg.norm(tri - cog, axis=1),
        np.linalg.norm(nodes[topo.FACES[topo.face_number(face) - 1]] - nodes.mean(axis=0), axis=1),
        atol=1e-12,
    )


def test_tipping_pressures():
    lev = np.arange(0.2, 4.61, 0.2)
    _, m10 = st.static_workspace(P, EQ_FACE, 10, lev)
    _, m11 = st.static_workspace(P, ISO_FACE, 11, lev)

    def first_crossing(m):
        i = np.flatnonzero(m < 0)
        assert i.size and i[0] > 0 and np.all(m[: i[0]] > 0)
        k = i[0]
        return lev[k - 1] + (lev[k] - lev[k - 1]) * m[k - 1] / (m[k - 1] - m[k])

    at = {round(v, 1): m for v, m in zip(lev, m10)}
    assert at[4.0] > 0 > at[4.4]  # design.md: #10 tips over 10-12 at about 4.2 MPa
    assert st.static_workspace(P, EQ_FACE, 10, [4.5])[1][0] < 0
    assert first_crossing(m11) < first_crossing(m10)


def test_bad_input_is_refused():
    with pytest.raises(ValueError, match="pressure"):
        st.equilibrium(P, _pressure(p10=-1.0))
    with pytest.raises(ValueError, match="shape"):
        st.equilibrium(P, np.zeros(3))
    with pytest.raises(ValueError, match="pair"):
        st.static_workspace(P, EQ_FACE, 13, [1.0])
    with pytest.raises(NotImplementedError):
        st.equilibrium(P.replace(cable_exponent=2.0), np.zeros(topo.N_PAIRS))
