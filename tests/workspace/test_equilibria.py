"""The static free-mode workspace (tensegrity.workspace.equilibria): the mirror and 3-fold
symmetries of the robot, and tipping pressures that are roots of the independent statics' margin."""

import numpy as np
import pytest

from tensegrity.physics import statics
from tensegrity.physics import symmetry as sym
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.workspace import equilibria as wq

P = Params()
LEVELS = [1.2, 2.4, 3.6, 4.8]
EQ, ISO = topo.face_number((9, 10, 12)), topo.face_number((10, 11, 12))


@pytest.fixture(scope="module")
def ws():
    return wq.free_workspace([P, P.replace(cable_stiffness=800.0)], [EQ, ISO], range(1, 13), LEVELS)


def test_mirror_pairs_give_mirror_cogs(ws):
    """The mirror keeping (10,11,12) and its apex 10 swaps pairs; in the face's frame (y toward
    the apex, z normal) it is x -> -x."""
    (mirror,) = [s for s in sym.group() if s.faces[ISO - 1] == ISO - 1 and np.linalg.det(s.matrix) < 0]
    assert any(mirror.pairs[p] != p for p in range(12))
    for p in range(12):
        a, b = ws.cog[:, 1, p], ws.cog[:, 1, mirror.pairs[p]]
        np.testing.assert_allclose(b, a * [-1.0, 1.0, 1.0], rtol=0, atol=1e-12)
        np.testing.assert_allclose(ws.tip_pressure[:, 1, p], ws.tip_pressure[:, 1, mirror.pairs[p]], atol=1e-6)


def test_three_fold_orbit_tips_together(ws):
    """#9, #10, #12 are one orbit of the 3-fold rotation of (9,10,12): one tipping pressure,
    each over the edge its rotation carries 10-12 to."""
    tips = ws.tip_pressure[:, 0, [8, 9, 11]]
    assert np.all(np.isfinite(tips))
    np.testing.assert_allclose(tips, tips[:, :1].repeat(3, axis=1), rtol=0, atol=1e-6)
    assert ws.tip_edge[0, 0, 9].tolist() == [10, 12]
    assert {tuple(e) for e in ws.tip_edge[0, 0, [8, 9, 11]].tolist()} == {(9, 10), (10, 12), (9, 12)}


@pytest.mark.parametrize("face, pair", [(EQ, 10), (ISO, 11)])
def test_tipping_pressure_is_the_root_of_the_independent_margin(ws, face, pair):
    c = [EQ, ISO].index(face)
    tip = ws.tip_pressure[0, c, pair - 1]
    assert LEVELS[0] < tip < LEVELS[-1]
    # the oracle's margin changes sign within +-1e-5 MPa of the root (its slope ~ 10 mm/MPa)
    _, m = statics.static_workspace(P, face, pair, [tip - 1e-5, tip + 1e-5])
    assert m[0] > 0 > m[1]


def test_pairs_that_never_tip_and_bad_laws():
    assert np.all(np.isnan(wq.free_workspace([P], [EQ], [1], [0.4, 0.8]).tip_pressure))
    with pytest.raises(ValueError, match="cable_exponent"):
        wq.free_workspace([P.replace(cable_exponent=1.5)], [EQ], [1], [0.4, 0.8])
