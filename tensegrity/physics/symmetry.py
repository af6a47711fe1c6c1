"""The symmetry group of the structure, computed from the geometry (docs/design.md §1).

An element is an orthogonal 3x3 map that permutes the nodes and keeps the sets of struts and
cables. Each carries its node, cable, face and pair permutations (0-based: perm[i] is the image
of item i).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from itertools import permutations

import numpy as np

from . import topology as topo


@dataclass(frozen=True)
class Symmetry:
    matrix: np.ndarray  # (3, 3) orthogonal map acting on world vectors
    nodes: np.ndarray  # (12,) image of each node
    cables: np.ndarray  # (24,) image of each cable
    faces: np.ndarray  # (20,) image of each face
    pairs: np.ndarray  # (12,) image of each actuator pair


def _edge_perm(edges: np.ndarray, nodes: np.ndarray) -> np.ndarray | None:
    key = {frozenset(e): k for k, e in enumerate(edges.tolist())}
    img = [key.get(frozenset(nodes[e].tolist())) for e in edges]
    return None if any(i is None for i in img) else np.array(img)


def _pair_perm(nodes: np.ndarray, cables: np.ndarray) -> np.ndarray | None:
    key = {frozenset(c.tolist()): k for k, c in enumerate(topo.PAIR_CABLES)}
    img = [key.get(frozenset(cables[c].tolist())) for c in topo.PAIR_CABLES]
    return None if any(i is None for i in img) else np.array(img)


@lru_cache(maxsize=1)
def group() -> tuple[Symmetry, ...]:
    """All orthogonal maps preserving struts and cables (the pyritohedral group Th, order 24)."""
    p = topo.reference_nodes()
    basis = [0, 1, 4]  # three nodes with linearly independent positions
    inv = np.linalg.inv(p[basis].T)
    out = []
    for img in permutations(range(topo.N_NODES), 3):
        m = p[list(img)].T @ inv
        if not np.allclose(m @ m.T, np.eye(3), atol=1e-9):
            continue
        q = p @ m.T
        d = np.linalg.norm(q[:, None, :] - p[None, :, :], axis=-1)
        nodes = np.argmin(d, axis=1)
        if not np.allclose(d[np.arange(topo.N_NODES), nodes], 0, atol=1e-9):
            continue
        if len(set(nodes.tolist())) != topo.N_NODES or _edge_perm(topo.STRUTS, nodes) is None:
            continue
        cables = _edge_perm(topo.CABLES, nodes)
        if cables is None:
            continue
        faces = _edge_perm(topo.FACES, nodes)
        pairs = _pair_perm(nodes, cables)
        if faces is None or pairs is None:
            continue
        out.append(Symmetry(m, nodes, cables, faces, pairs))
    return tuple(out)


def maps_between(face_from: int, face_to: int) -> list[Symmetry]:
    """Group elements carrying 1-based face `face_from` onto `face_to` (with its reference vertex
    onto the reference vertex, so that support frames correspond)."""
    a, b = face_from - 1, face_to - 1
    ref_a = topo.FACES[a, topo.FACE_REFERENCE[a]]
    ref_b = topo.FACES[b, topo.FACE_REFERENCE[b]]
    return [s for s in group() if s.faces[a] == b and s.nodes[ref_a] == ref_b]
