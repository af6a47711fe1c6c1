"""Topology and reference geometry of the six-strut robot (docs/design.md §1).

Everything here is data and numbering: node coordinates, struts, cables, faces, actuator pairs,
and which faces share an edge. Indices in arrays start at 0; the numbers a person sees (node,
face, pair) start at 1.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

N_NODES, N_STRUTS, N_CABLES, N_FACES, N_PAIRS = 12, 6, 24, 20, 12

# Node coordinates for S = 0.5 m, centre at the origin (design.md table), rows = nodes 1..12.
_NODES_S05 = np.array(
    [
        [0, 0.25, -0.125],
        [-0.25, -0.125, 0],
        [0, -0.25, -0.125],
        [0, -0.25, 0.125],
        [-0.125, 0, -0.25],
        [-0.25, 0.125, 0],
        [0.125, 0, -0.25],
        [0.25, -0.125, 0],
        [0.25, 0.125, 0],
        [0, 0.25, 0.125],
        [-0.125, 0, 0.25],
        [0.125, 0, 0.25],
    ]
)

# Struts (first node = centre + L c, second = centre - L c), 1-based node numbers.
STRUTS = np.array([(1, 3), (2, 8), (4, 10), (5, 11), (6, 9), (7, 12)]) - 1
GAPS = np.array([(1, 10), (2, 6), (3, 4), (5, 7), (8, 9), (11, 12)]) - 1
CABLES = (
    np.array(
        [
            (1, 5),
            (1, 6),
            (1, 7),
            (1, 9),
            (2, 3),
            (2, 4),
            (2, 5),
            (2, 11),
            (3, 5),
            (3, 7),
            (3, 8),
            (4, 8),
            (4, 11),
            (4, 12),
            (5, 6),
            (6, 10),
            (6, 11),
            (7, 8),
            (7, 9),
            (8, 12),
            (9, 10),
            (9, 12),
            (10, 11),
            (10, 12),
        ]
    )
    - 1
)

# Faces 1..8 equilateral in actuation order (reference vertex first); faces 9..20 isosceles
# written (gap a, gap b, apex), reference vertex = apex.
FACES = (
    np.array(
        [
            (1, 6, 5),
            (1, 9, 7),
            (2, 5, 3),
            (2, 11, 4),
            (3, 8, 7),
            (4, 8, 12),
            (6, 11, 10),
            (9, 12, 10),
            (1, 10, 6),
            (1, 10, 9),
            (2, 6, 5),
            (2, 6, 11),
            (3, 4, 2),
            (3, 4, 8),
            (5, 7, 1),
            (5, 7, 3),
            (8, 9, 7),
            (8, 9, 12),
            (11, 12, 4),
            (11, 12, 10),
        ]
    )
    - 1
)
FACE_TYPES = np.array(["equilateral"] * 8 + ["isosceles"] * 12)
FACE_REFERENCE = np.array([0] * 8 + [2] * 12)  # corner index of the reference vertex

# Actuator pair #v: the two cables driven by the motors at node v (1-based node numbers).
PAIRS = (
    np.array(
        [
            [(1, 9), (1, 6)],
            [(2, 11), (2, 5)],
            [(3, 8), (2, 3)],
            [(4, 8), (2, 4)],
            [(1, 5), (3, 5)],
            [(6, 11), (5, 6)],
            [(1, 7), (3, 7)],
            [(8, 12), (7, 8)],
            [(9, 12), (7, 9)],
            [(9, 10), (6, 10)],
            [(10, 11), (4, 11)],
            [(10, 12), (4, 12)],
        ]
    )
    - 1
)

CONTACT_FACES = {"equilateral": (9, 10, 12), "isosceles": (10, 11, 12)}  # the canonical faces
CONTACTS: tuple[str, ...] = tuple(CONTACT_FACES)  # the contact cases, in this order


def _cable_index(a: int, b: int) -> int:
    key = {tuple(sorted(c)): j for j, c in enumerate(CABLES.tolist())}
    return key[tuple(sorted((int(a), int(b))))]


PAIR_CABLES = np.array([[_cable_index(*c) for c in pair] for pair in PAIRS])  # (12, 2)
CABLE_PAIR = np.empty(N_CABLES, dtype=np.int64)  # pair index (0-based) of each cable
CABLE_PAIR[PAIR_CABLES.ravel()] = np.repeat(np.arange(N_PAIRS), 2)


def cable_levels(levels: ArrayLike) -> np.ndarray:
    """Actuation levels per cable (..., 24) (MPa, or V for twisted strings) of pair levels
    (..., 12), each pair's on both its cables (CABLE_PAIR: the same numbers, to the bit), or of
    levels (..., 24) already per cable (as given). Raises ValueError for another last axis."""
    a = np.asarray(levels, dtype=float)
    if a.ndim and a.shape[-1] == N_PAIRS:
        return a[..., CABLE_PAIR]
    if a.ndim and a.shape[-1] == N_CABLES:
        return a
    raise ValueError(f"levels must be per pair or per cable, (..., 12 or 24), got shape {a.shape}")


# node -> (strut, sign): node = strut centre + sign * (S/2) * axis (eq. 4), for kernel and statics
NODE_STRUT = np.empty(N_NODES, np.int64)
NODE_SIGN = np.empty(N_NODES, np.float64)
for _s, (_a, _b) in enumerate(STRUTS):
    NODE_STRUT[_a], NODE_SIGN[_a] = _s, 1.0
    NODE_STRUT[_b], NODE_SIGN[_b] = _s, -1.0


def reference_nodes(strut_length: float = 0.5) -> np.ndarray:
    """Node positions of the symmetric state, (12, 3) m, centre at the origin."""
    return _NODES_S05 * (strut_length / 0.5)


def check_pair(pair: int) -> int:
    """Validate a 1-based pair number; return it as int."""
    if isinstance(pair, bool) or not float(pair).is_integer() or not 1 <= int(pair) <= N_PAIRS:
        raise ValueError(f"unknown pair {pair}: pairs are numbered 1..{N_PAIRS}")
    return int(pair)


def face_number(face: int | Sequence[int]) -> int:
    """1-based face number from a number 1..20 or three 1-based node numbers in any order."""
    if np.ndim(face) == 0:
        if isinstance(face, bool) or not float(face).is_integer() or not 1 <= int(face) <= N_FACES:
            raise ValueError(f"unknown face {face}: faces are numbered 1..{N_FACES} or given as three node numbers")
        return int(face)
    key = sorted(int(n) for n in face)
    for k, f in enumerate(FACES):
        if sorted((f + 1).tolist()) == key:
            return k + 1
    raise ValueError(f"unknown face {tuple(np.asarray(face).tolist())!r}: no face has these three nodes")


def face_label(face: int) -> str:
    """Human label of a 1-based face number, e.g. '(9,10,12)'."""
    return "(" + ",".join(str(n) for n in sorted(FACES[face - 1] + 1)) + ")"


def edge_nodes(face: int, k: int) -> tuple[int, int]:
    """The 1-based nodes (smaller first) of edge k (corners k, k+1 mod 3) of 1-based `face`."""
    a, b = FACES[face - 1][k], FACES[face - 1][(k + 1) % 3]
    return (int(min(a, b)) + 1, int(max(a, b)) + 1)


def neighbour(face: int | Sequence[int], edge: Sequence[int]) -> int:
    """The 1-based face across `edge` (two 1-based node numbers) from `face`: the other face
    sharing that edge (every edge of the icosahedron lies on exactly two faces)."""
    f = face_number(face)
    e = {int(n) - 1 for n in edge}
    if len(e) != 2 or not e <= set(FACES[f - 1].tolist()):
        raise ValueError(f"edge {tuple(np.asarray(edge).tolist())} is not an edge of face {face_label(f)}")
    for k, corners in enumerate(FACES):
        if k + 1 != f and e <= set(corners.tolist()):
            return k + 1
    raise AssertionError("unreachable: every edge lies on two faces")


def common_edge(a: int | Sequence[int], b: int | Sequence[int]) -> tuple[int, int] | None:
    """The edge (1-based nodes) shared by faces a and b (1..20 or node triples), or None."""
    e = set(FACES[face_number(a) - 1].tolist()) & set(FACES[face_number(b) - 1].tolist())
    return tuple(sorted(n + 1 for n in e)) if len(e) == 2 else None
