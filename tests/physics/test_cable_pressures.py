"""One pressure (or voltage) per cable, (B, 24), beside one per pair, (B, 12) (issue 30 item 1:
the prototype's 24 actuators), tested as physics: a pair level is the same level on both its
cables, to the bit; one cable of a pair alone is another action, and the structure's mirror
symmetry carries driving one cable onto driving its mirror partner; tensions are never negative."""

import numpy as np
import pytest

from tensegrity.physics import actuator, kernel
from tensegrity.physics import dynamics as d
from tensegrity.physics import symmetry as sym
from tensegrity.physics import topology as topo
from tensegrity.physics.params import IDX, Params
from tensegrity.physics.schedule import MAX_PRESSURE, Schedule
from tensegrity.physics.terrain import Terrain
from tensegrity.physics.twisted import TwistedString, Voltages

ISO = topo.face_number(topo.CONTACT_FACES["isosceles"])  # (10,11,12)
DT = 1e-4


def _mirror() -> sym.Symmetry:
    """The mirror of the group that keeps the isosceles face (10,11,12) (its stabiliser's element
    of determinant -1, tests/physics/test_symmetry): it swaps the two cables of pair #10."""
    (m,) = [s for s in sym.group() if s.faces[ISO - 1] == ISO - 1 and np.linalg.det(s.matrix) < 0]
    return m


def _cable(a: int, b: int) -> int:
    """The 0-based index of the cable between 1-based nodes a and b."""
    return int(np.flatnonzero((np.sort(topo.CABLES, 1) == sorted((a - 1, b - 1))).all(1))[0])


@pytest.mark.parametrize("batch", [1, 3])  # one robot alone, and a group of lanes (kernel.driver)
@pytest.mark.parametrize("kind", ["pneumatic", "twisted_string"])
def test_cables_at_their_pairs_levels_give_the_pair_result_bit_for_bit(batch, kind):
    """Two segments of random pair levels on flat ground, against the same levels lifted to
    their cables (topology.cable_levels): every recorded and final number identical."""
    params, rng = Params(), np.random.default_rng(45)
    motors = TwistedString() if kind == "twisted_string" else None
    top, cls = (6.0, Voltages) if motors else (2.0, Schedule)
    pair = rng.uniform(0.0, top, (batch, 2, topo.N_PAIRS)) * (rng.random((batch, 2, topo.N_PAIRS)) < 0.4)
    state = d.stand_on(params, ISO, Terrain.flat(), batch=batch)
    runs = [
        d.simulate(params, state, cls(np.array([0.1, 0.1]), p), Terrain.flat(), DT, motors=motors)
        for p in (pair, topo.cable_levels(pair))
    ]
    (s12, t12), (s24, t24) = runs
    for name in ("x", "v", "q", "w", "anchor", "stuck", "motor_angle", "motor_speed"):
        np.testing.assert_array_equal(getattr(s12, name), getattr(s24, name), err_msg=name)
    np.testing.assert_array_equal(t12.x, t24.x)
    np.testing.assert_array_equal(t12.q, t24.q)
    assert t12.pressure.shape[-1] == 12 and t24.pressure.shape[-1] == 24
    np.testing.assert_array_equal(topo.cable_levels(t12.pressure), t24.pressure)
    assert np.abs(t12.x - state.x[:, None]).max() > 1e-4  # the levels moved the robots
    if motors is None:  # the other entry points: step, tensions, energy
        p = pair[:, 1]
        np.testing.assert_array_equal(d.tensions(params, s12, p), d.tensions(params, s12, topo.cable_levels(p)))
        np.testing.assert_array_equal(d.energy(params, s12, p), d.energy(params, s12, topo.cable_levels(p)))
        a, b = d.step(params, s12, p, DT), d.step(params, s12, topo.cable_levels(p), DT)
        np.testing.assert_array_equal(a.x, b.x)
        np.testing.assert_array_equal(a.w, b.w)


def test_one_cable_differs_from_its_pair_and_mirror_partners_move_as_mirror_images():
    """Standing on (10,11,12) under gravity: pair #10 at 3 MPa, its cable (6,10) alone, and its
    cable (9,10) alone. The face's mirror maps (6,10) onto (9,10) and keeps the vertical and the
    flat ground, so the two one-cable robots move as mirror images (node n of one at the mirror
    image of node s.nodes[n] of the other), and the pair's robot is its own mirror image. The
    nodes move by 0.1-0.2 m; the images agree to 2e-15 m (rounding over 4000 steps), asserted
    to 1e-9 m."""
    params, s = Params(), _mirror()
    a, b = _cable(6, 10), _cable(9, 10)
    assert s.cables[a] == b and topo.CABLE_PAIR[a] == topo.CABLE_PAIR[b] == 9
    levels = np.zeros((3, topo.N_CABLES))
    levels[0, topo.PAIR_CABLES[9]] = levels[1, a] = levels[2, b] = 3.0
    state = d.stand_on(params, ISO, Terrain.flat(), batch=3, yaw_deg=30.0)
    end, tr = d.simulate(params, state, Schedule.constant(levels, 0.4), Terrain.flat(), DT)
    P = tr.nodes(params.strut_length)  # (3, T, 12, 3)
    # the mirror in the world: the map of the start's nodes about their centre onto their images
    X = P[0, 0] - P[0, 0].mean(0)
    Mw = np.linalg.lstsq(X, X[s.nodes], rcond=None)[0].T
    np.testing.assert_allclose(Mw @ Mw.T, np.eye(3), atol=1e-12)
    np.testing.assert_allclose(Mw[2], [0.0, 0.0, 1.0], atol=1e-12)  # gravity and ground kept
    c = P[0, 0].mean(0)

    def mirrored(Q):
        out = np.empty_like(Q)
        out[:, s.nodes] = (Q - c) @ Mw.T + c
        return out

    moved = np.abs(P[1] - P[1, :1]).max()
    assert moved > 0.05  # metres
    assert np.abs(P[1] - P[0]).max() > 0.2 * moved  # one cable is not its pair
    np.testing.assert_allclose(mirrored(P[1]), P[2], rtol=0, atol=1e-9)
    np.testing.assert_allclose(mirrored(P[0]), P[0], rtol=0, atol=1e-9)
    # and in the tensions at the end: cable j of one is cable s.cables[j] of the other
    T = d.tensions(params, end, levels)
    np.testing.assert_allclose(T[2, s.cables], T[1], rtol=0, atol=1e-9)  # N
    assert np.all(T >= 0.0) and not np.signbit(T).any()


def test_kernel_cable_stage_with_cable_pressures_equals_the_numpy_law_never_negative():
    """kernel.tensions with 24 independent pressures (a third 0, the rest up to MAX_PRESSURE) on
    random node states, against the NumPy law (`actuator.tensions`; the tolerance of
    tests/physics/test_twins): equal, and never negative (a slack cable pulls 0.0, not -0.0)."""
    rng = np.random.default_rng(46)
    B = 16
    params = Params(cable_stiffness=rng.uniform(500, 2000, B), muscle_gain=rng.uniform(200, 900, B))
    P = topo.reference_nodes(params.strut_length) * rng.uniform(0.7, 1.3, (B, 1, 1))
    P = P + rng.normal(0, 0.02, P.shape)
    U = rng.normal(0, 0.3, P.shape)
    pres = rng.uniform(0.0, MAX_PRESSURE, (B, topo.N_CABLES)) * (rng.random((B, topo.N_CABLES)) < 2 / 3)
    prm = params.pack(B)
    T = kernel.tensions(P, U, prm, pres)[0]
    e = P[:, topo.CABLES[:, 1]] - P[:, topo.CABLES[:, 0]]
    ln = np.linalg.norm(e, axis=-1)
    ldot = np.sum(e * (U[:, topo.CABLES[:, 1]] - U[:, topo.CABLES[:, 0]]), -1) / ln
    col = IDX[actuator.NAMES[0]]
    values = prm[:, col : col + len(actuator.NAMES)].T[..., None]
    act = actuator.activations(values[actuator.NAMES.index("muscle_gain")], pres)
    np.testing.assert_allclose(T, actuator.tensions(ln, ldot, act, actuator.constants(values)), rtol=1e-12, atol=1e-10)
    assert 0 < np.mean(T == 0.0) < 0.9 and not np.signbit(T).any()


def test_levels_of_neither_12_nor_24_columns_raise():
    with pytest.raises(ValueError, match="12 or 24"):
        Schedule.constant(np.zeros(13), 0.1)
    with pytest.raises(ValueError, match="12 or 24"):
        topo.cable_levels(np.zeros((2, 6)))
    state = d.stand_on(Params(), ISO)
    with pytest.raises(ValueError, match="24"):  # the kernel reads one level per cable
        kernel.advance(*(state.x, state.v, state.q, state.w, state.anchor, state.stuck), Params().pack(1),
                       np.zeros((1, 12)), *Terrain.flat().packed(), 1, 1, DT, np.empty((1, 1, 6, 3)),
                       np.empty((1, 1, 6, 4)), np.zeros(1, np.int64), np.zeros(1, np.int64))  # fmt: skip
