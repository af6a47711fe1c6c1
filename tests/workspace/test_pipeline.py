"""Nominal averaging, tipping, and the symmetry mapping of the workspace."""

import numpy as np
import pytest

from tensegrity.physics import frames
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.workspace import mapping, nominal, sweep

LEVELS = [1.2, 3.6]
PAIRS = [1, 4, 9, 10, 11, 12]


def test_nominal_averages_each_level_after_the_discarded_rise():
    t = np.arange(1, 201) * 0.01
    level = (t > 1.0).astype(int)
    cog = np.zeros((200, 3))
    cog[level == 1] = [0.01, 0.0, 0.2]
    cog[(t > 1.0) & (t <= 1.2)] = [5.0, 5.0, 5.0]  # the rise, to be left out
    sup = np.broadcast_to(np.array([[0, 0.1, 0], [0.1, -0.05, 0], [-0.1, -0.05, 0]]), (200, 3, 3))
    c, s, tri, m = nominal.nominal(t, level, cog, sup, 2, 1.0, discard=0.2)
    np.testing.assert_allclose(c[1], [0.01, 0.0, 0.2])
    assert m[1] == pytest.approx(0.0085 / np.hypot(0.1, 0.15))  # nearest edge: (0, .1)-(.1, -.05)
    with pytest.raises(ValueError, match="no samples"):
        nominal.nominal(t, level, cog, sup, 2, 1.0, discard=1.5)


def test_tip_pressure_interpolates_the_margin_crossing():
    assert frames.first_crossing([1.0, 2.0, 3.0], [0.02, 0.01, -0.01]) == pytest.approx((2.5, 2))
    assert np.isnan(frames.first_crossing([1.0, 2.0], [0.02, 0.01])[0])


def test_first_roll_ignores_a_hop_and_finds_the_roll():
    level = np.repeat([0, 1, 2], 5)
    on = np.ones(15, bool)
    on[6] = False  # a hop in level 1, back on the face by its end
    assert nominal.first_roll(level, on, 3) == 3
    on[14] = False  # off the face at the end of level 2
    assert nominal.first_roll(level, on, 3) == 2


def test_a_nominal_holds_every_pair_and_refuses_what_is_not_one():
    """`Nominal.of_pairs`: the swept pairs at their rows of all 12, NaN elsewhere; an unknown
    mode, face or shape raises."""
    cog, sup = np.full((2, 2, 3), 0.1), np.zeros((2, 2, 3, 3))
    n = nominal.Nominal.of_pairs("isosceles", 20, "grounded", LEVELS, [11, 4], cog, sup, np.ones((2, 2)))
    assert n.cog.shape == (12, 2, 3) and n.support.shape == (12, 2, 3, 3) and n.margin.shape == (12, 2)
    assert np.isfinite(n.margin).all(axis=1).nonzero()[0].tolist() == [3, 10]
    with pytest.raises(ValueError, match="mode must be one of"):
        nominal.Nominal.of_pairs("isosceles", 20, "dry", LEVELS, [11], cog[:1], sup[:1], np.ones((1, 2)))
    with pytest.raises(ValueError, match="unknown face 21"):
        nominal.Nominal.of_pairs("isosceles", 21, "free", LEVELS, [11], cog[:1], sup[:1], np.ones((1, 2)))
    with pytest.raises(ValueError, match=r"margin must have shape \(12, 2\)"):
        nominal.Nominal.of_pairs("isosceles", 20, "free", LEVELS, [11], cog[:1], sup[:1], np.ones((1, 3)))


@pytest.fixture(scope="module")
def canonical():
    """Free-mode staircase on both canonical faces (short holds)."""
    out = {}
    for kind, face in topo.CONTACT_FACES.items():
        res = sweep.run(Params(), face, PAIRS, sweep.SweepSetup(levels=tuple(LEVELS), hold=0.6))
        out[kind] = [
            nominal.nominal(res.t, res.level, res.cog[b], res.support[b], 2, 0.6, 0.2) for b in range(len(PAIRS))
        ]
    return out


@pytest.mark.parametrize(
    "face", [topo.face_number((1, 6, 5)), topo.face_number((1, 10, 9)), topo.face_number((3, 4, 8))]
)
def test_mapped_workspace_equals_a_direct_simulation_on_that_face(canonical, face):
    kind = str(topo.FACE_TYPES[face - 1])
    cog = np.full((12, 2, 3), np.nan)
    sup = np.full((12, 2, 3, 3), np.nan)
    for b, pair in enumerate(PAIRS):
        cog[pair - 1], sup[pair - 1] = canonical[kind][b][0], canonical[kind][b][2]
    mapped_cog, mapped_sup = mapping.map_face(face, cog, sup)
    pair_src = mapping.face_map(face)[0]
    pairs = [p + 1 for p in range(12) if pair_src[p] + 1 in PAIRS]
    direct = sweep.run(Params(), face, pairs, sweep.SweepSetup(levels=tuple(LEVELS), hold=0.6))
    for b, pair in enumerate(pairs):
        c, _, s, _ = nominal.nominal(direct.t, direct.level, direct.cog[b], direct.support[b], 2, 0.6, 0.2)
        assert np.abs(c - mapped_cog[pair - 1]).max() < 1e-4  # m
        assert np.abs(s - mapped_sup[pair - 1]).max() < 1e-4
    moved = np.linalg.norm(mapped_cog[np.array(pairs) - 1, -1, :2], axis=-1)
    assert moved.max() > 0.03  # some pair moves the CoG a lot: the comparison is not vacuous
