"""Optimised actions of any set of pairs (issue 30, item 1): the weight-vector roll reduces to the
pair roll, and an action the linear programme finds on the statics rolls the grounded robot over
the edge it was chosen for, where its pairs alone do not (flat ground) or land elsewhere (20 deg)."""

import numpy as np
import pytest

from tensegrity.locomotion import actuation, control
from tensegrity.locomotion.settings import RollSettings
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.physics.terrain import Terrain
from tensegrity.workspace.slopes import place

S = RollSettings()
PARAMS = S.rolling(Params())
FACE = topo.face_number((9, 10, 12))


def _settled(terrain, heading=0.0):
    st, face = control.settle(PARAMS, place(PARAMS, FACE, terrain, (0.0, 0.0), heading), terrain, S)
    assert face == FACE
    return st


def test_unit_weights_are_the_pair_roll_and_bad_weights_are_refused():
    flat = Terrain.flat()
    st = _settled(flat)
    a = control.roll(PARAMS, st, flat, (10, 11), 2.0, S)
    b = control.roll(PARAMS, st, flat, None, 2.0, S, weights=np.isin(np.arange(1, 13), (10, 11)).astype(float))
    assert a.pairs == b.pairs == (10, 11)
    for name in ("t", "nodes", "pressure", "face"):
        assert np.array_equal(getattr(a.record, name), getattr(b.record, name)), name
    for bad in (np.full(12, 0.5), -np.eye(12)[0], np.ones(11)):
        with pytest.raises(ValueError, match="action weights"):
            control.action_weights(weights=bad)


def test_optimised_action_rolls_over_its_edge_at_the_predicted_pressure():
    """Flat ground, pressures up to 3 MPa: no single pair rolls the robot (each needs 4.1 MPa,
    control.roll), the least-total action of two pairs does, over its edge onto the face
    across it, tipping within 0.15 MPa of the statics' scale (the free model's error on flat
    ground is the free workspace's, ~0.1 MPa)."""
    flat = Terrain.flat()
    st = _settled(flat)
    cands = actuation.candidates(PARAMS, flat, st, FACE, (1.0, 0.0), actuation.ActuationSettings(), 3.0, deepest=False)
    assert len(cands) == 3  # by symmetry, every edge of the equilateral face
    c = cands[0]
    assert c.along == max(x.along for x in cands) and len(np.flatnonzero(c.weights)) >= 2
    r = control.roll(PARAMS, st, flat, None, 3.0, S, weights=c.weights)
    assert r.rolled and r.face_after == c.next_face
    assert topo.common_edge(FACE, r.face_after) == c.edge
    assert abs(r.tip_pressure - c.scale) < 0.15
    q = int(np.argmax(c.weights)) + 1  # its strongest pair alone
    assert not control.roll(PARAMS, st, flat, (q,), 3.0, S).rolled


def test_on_a_slope_the_optimised_action_lands_where_it_was_aimed():
    """20 deg, uphill along heading 0 of the face: across the slope over edge (10, 12) the
    programme combines pairs 6 and 10; it lands on the face across that edge, while pair 10
    alone (the edge's best single pair) throws the robot on to another face."""
    slope = Terrain.slope(20.0)
    st = _settled(slope)
    cands = actuation.candidates(PARAMS, slope, st, FACE, None, actuation.ActuationSettings(), 5.0, deepest=False)
    c = next(x for x in cands if x.edge == (10, 12))
    assert set(np.flatnonzero(c.weights) + 1) == {6, 10}
    r = control.roll(PARAMS, st, slope, None, 5.0, S, weights=c.weights)
    assert r.rolled and r.face_after == c.next_face
    alone = control.roll(PARAMS, st, slope, (10,), 5.0, S)
    assert alone.face_after != c.next_face
