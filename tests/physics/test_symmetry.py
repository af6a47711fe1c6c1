"""The symmetry group computed from the geometry (docs/design.md §1)."""

import numpy as np

from tensegrity.physics import symmetry as sym
from tensegrity.physics import topology as topo


def test_order_rotations_and_closure():
    G = sym.group()
    assert len(G) == 24
    dets = np.array([np.linalg.det(s.matrix) for s in G])
    assert np.sum(dets > 0) == 12 and np.allclose(np.abs(dets), 1)
    mats = [s.matrix for s in G]
    assert any(np.allclose(m, -np.eye(3)) for m in mats)  # central inversion: Th, not T
    for a in mats:
        for b in mats:
            assert any(np.allclose(a @ b, c) for c in mats)


def test_permutations_agree_with_the_matrices():
    p = topo.reference_nodes()
    for s in sym.group():
        np.testing.assert_allclose(p @ s.matrix.T, p[s.nodes], atol=1e-12)  # M p_n = p_perm(n)
        for j, c in enumerate(topo.CABLES):
            assert set(s.nodes[c]) == set(topo.CABLES[s.cables[j]])


def test_orbits_and_stabilisers():
    G = sym.group()
    orbit = lambda f: {int(s.faces[f]) for s in G}
    assert orbit(0) == set(range(8)) and orbit(8) == set(range(8, 20))
    equi, iso = topo.face_number((9, 10, 12)) - 1, topo.face_number((10, 11, 12)) - 1
    st_e = [s for s in G if s.faces[equi] == equi]
    st_i = [s for s in G if s.faces[iso] == iso]
    assert len(st_e) == 3 and all(np.linalg.det(s.matrix) > 0 for s in st_e)
    assert len(st_i) == 2 and sorted(np.linalg.det(s.matrix).round() for s in st_i) == [-1, 1]
    pair_orbits = {frozenset(int(s.pairs[p]) + 1 for s in st_e) for p in range(12)}
    assert frozenset({9, 10, 12}) in pair_orbits and frozenset({4, 6, 7}) in pair_orbits
    assert all(len(o) == 3 for o in pair_orbits)


def test_maps_between_faces_carry_the_reference_vertex():
    for target in range(1, 21):
        src = 8 if target <= 8 else 20
        maps = sym.maps_between(src, target)
        assert len(maps) == (1 if target <= 8 else 2)
        for s in maps:
            f, t = topo.FACES[src - 1], topo.FACES[target - 1]
            assert s.nodes[f[topo.FACE_REFERENCE[src - 1]]] == t[topo.FACE_REFERENCE[target - 1]]
