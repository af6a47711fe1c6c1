"""Topology and reference geometry of the six-strut robot (design.md section 1).

Everything here is data: node coordinates, struts, cables, faces, actuator pairs. Indices in
arrays start at 0; the numbers a person sees (node, face, pair) start at 1.
"""
from __future__ import annotations

import numpy as np

N_NODES, N_STRUTS, N_CABLES, N_FACES, N_PAIRS = 12, 6, 24, 20, 12

# Node coordinates for S = 0.5 m, centre at the origin (design.md table), rows = nodes 1..12.
_NODES_S05 = np.array([
    [0, .25, -.125], [-.25, -.125, 0], [0, -.25, -.125], [0, -.25, .125],
    [-.125, 0, -.25], [-.25, .125, 0], [.125, 0, -.25], [.25, -.125, 0],
    [.25, .125, 0], [0, .25, .125], [-.125, 0, .25], [.125, 0, .25]])

# Struts (first node = centre + L c, second = centre - L c), 1-based node numbers.
STRUTS = np.array([(1, 3), (2, 8), (4, 10), (5, 11), (6, 9), (7, 12)]) - 1
GAPS = np.array([(1, 10), (2, 6), (3, 4), (5, 7), (8, 9), (11, 12)]) - 1
CABLES = np.array([
    (1, 5), (1, 6), (1, 7), (1, 9), (2, 3), (2, 4), (2, 5), (2, 11), (3, 5), (3, 7), (3, 8),
    (4, 8), (4, 11), (4, 12), (5, 6), (6, 10), (6, 11), (7, 8), (7, 9), (8, 12), (9, 10),
    (9, 12), (10, 11), (10, 12)]) - 1

# Faces 1..8 equilateral in actuation order (reference vertex first); faces 9..20 isosceles
# written (gap a, gap b, apex), reference vertex = apex.
FACES = np.array([
    (1, 6, 5), (1, 9, 7), (2, 5, 3), (2, 11, 4), (3, 8, 7), (4, 8, 12), (6, 11, 10), (9, 12, 10),
    (1, 10, 6), (1, 10, 9), (2, 6, 5), (2, 6, 11), (3, 4, 2), (3, 4, 8), (5, 7, 1), (5, 7, 3),
    (8, 9, 7), (8, 9, 12), (11, 12, 4), (11, 12, 10)]) - 1
FACE_TYPES = np.array(["equilateral"] * 8 + ["isosceles"] * 12)
FACE_REFERENCE = np.array([0] * 8 + [2] * 12)  # corner index of the reference vertex

# Actuator pair #v: the two cables driven by the motors at node v (1-based node numbers).
PAIRS = np.array([
    [(1, 9), (1, 6)], [(2, 11), (2, 5)], [(3, 8), (2, 3)], [(4, 8), (2, 4)], [(1, 5), (3, 5)],
    [(6, 11), (5, 6)], [(1, 7), (3, 7)], [(8, 12), (7, 8)], [(9, 12), (7, 9)],
    [(9, 10), (6, 10)], [(10, 11), (4, 11)], [(10, 12), (4, 12)]]) - 1

CONTACT_FACES = {"equilateral": (9, 10, 12), "isosceles": (10, 11, 12)}


def _cable_index(a: int, b: int) -> int:
    key = {tuple(sorted(c)): j for j, c in enumerate(CABLES.tolist())}
    return key[tuple(sorted((int(a), int(b))))]


PAIR_CABLES = np.array([[_cable_index(*c) for c in pair] for pair in PAIRS])  # (12, 2)
CABLE_PAIR = np.empty(N_CABLES, dtype=np.int64)  # pair index (0-based) of each cable
CABLE_PAIR[PAIR_CABLES.ravel()] = np.repeat(np.arange(N_PAIRS), 2)


def reference_nodes(strut_length: float = 0.5) -> np.ndarray:
    """Node positions of the symmetric state, (12, 3) m, centre at the origin."""
    return _NODES_S05 * (strut_length / 0.5)


def check_pair(pair: int) -> int:
    """Validate a 1-based pair number; return it as int."""
    if isinstance(pair, bool) or not float(pair).is_integer() or not 1 <= int(pair) <= N_PAIRS:
        raise ValueError(f"unknown pair {pair}: pairs are numbered 1..{N_PAIRS}")
    return int(pair)


def face_number(face) -> int:
    """1-based face number from a number 1..20 or three 1-based node numbers in any order."""
    if np.ndim(face) == 0:
        if isinstance(face, bool) or not float(face).is_integer() or not 1 <= int(face) <= N_FACES:
            raise ValueError(f"unknown face {face}: faces are numbered 1..{N_FACES} "
                             "or given as three node numbers")
        return int(face)
    key = sorted(int(n) for n in face)
    for k, f in enumerate(FACES):
        if sorted((f + 1).tolist()) == key:
            return k + 1
    raise ValueError(f"unknown face {tuple(face)!r}: no face has these three nodes")


def face_label(face: int) -> str:
    """Human label of a 1-based face number, e.g. '(9,10,12)'."""
    return "(" + ",".join(str(n) for n in sorted(FACES[face - 1] + 1)) + ")"


def support_frame(tri: np.ndarray, ref: int, inside: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Supporting-triangle frame (design.md section 2, paper Fig. 5).

    tri: (..., 3, 3) corner positions, m; ref: corner index of the reference vertex;
    inside: (..., 3) a point inside the robot (the CoG) that fixes the normal's sign.
    Returns origin (..., 3) and rotation (..., 3, 3) whose rows are the frame axes x, y, z
    in world components, so that local = rot @ (p - origin).
    """
    origin = tri.mean(axis=-2)
    n = np.cross(tri[..., 1, :] - tri[..., 0, :], tri[..., 2, :] - tri[..., 0, :])
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    side = np.sign(np.sum(n * (inside - origin), axis=-1, keepdims=True))
    z = n * np.where(side == 0, 1.0, side)
    y = tri[..., ref, :] - origin
    y = y - np.sum(y * z, axis=-1, keepdims=True) * z
    y /= np.linalg.norm(y, axis=-1, keepdims=True)
    x = np.cross(y, z)
    return origin, np.stack([x, y, z], axis=-2)


def to_frame(p: np.ndarray, origin: np.ndarray, rot: np.ndarray) -> np.ndarray:
    """Express world points p (..., 3) in a frame (origin (..., 3), rows-as-axes rot)."""
    return np.einsum("...ij,...j->...i", rot, p - origin)


def in_support_frame(nodes: np.ndarray, face) -> tuple[np.ndarray, np.ndarray]:
    """CoG (..., 3) m (mean of the nodes = mean of the strut centres, equal masses) and the
    face's corners (..., 3, 3) m, both in the supporting-triangle frame of the current, deformed
    `face` (1..20 or three node numbers); corners in the order of FACES."""
    f = face_number(face) - 1
    cog = nodes.mean(axis=-2)
    tri = nodes[..., FACES[f], :]
    origin, rot = support_frame(tri, int(FACE_REFERENCE[f]), cog)
    return to_frame(cog, origin, rot), to_frame(tri, origin[..., None, :], rot[..., None, :, :])


def edge_distances(point: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """Signed distances (m) of 2-D point(s) (..., 2) to the three edge lines of triangle(s)
    (..., 3, 2), positive on the inner side; edge k joins corners k and k+1 (mod 3)."""
    centroid = tri.mean(axis=-2)
    out = []
    for k in range(3):
        a, b = tri[..., k, :], tri[..., (k + 1) % 3, :]
        e = b - a
        nrm = np.stack([e[..., 1], -e[..., 0]], axis=-1) / np.linalg.norm(e, axis=-1)[..., None]
        s = np.sign(np.sum(nrm * (centroid - a), axis=-1))[..., None]
        out.append(np.sum(s * nrm * (point - a), axis=-1))
    return np.stack(out, axis=-1)


def margin_2d(point: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """Signed Euclidean distance (m) of 2-D point(s) (..., 2) to the boundary of triangle(s)
    (..., 3, 2): positive inside, negative outside."""
    seg = []
    for k in range(3):
        a, b = tri[..., k, :], tri[..., (k + 1) % 3, :]
        e = b - a
        t = np.clip(np.sum((point - a) * e, axis=-1) / np.sum(e * e, axis=-1), 0.0, 1.0)
        seg.append(np.linalg.norm(point - (a + t[..., None] * e), axis=-1))
    dist = np.min(np.stack(seg, axis=-1), axis=-1)
    inside = np.all(edge_distances(point, tri) >= 0, axis=-1)
    return np.where(inside, dist, -dist)
