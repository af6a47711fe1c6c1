"""Support frames, margins and the crossed edge (docs/design.md §2, paper Fig. 5).

One definition each: rotations about an axis and onto a direction (`turn`, `align`), the
support frame of a face on given nodes (`face_frame`), the CoG and support triangle in it
(`in_support_frame`, `rest_frame` for the unactuated robot), the signed margin of a CoG
projection (`margin_2d`), the edge it has crossed (`crossed_edge`), the least pressure at
which a margin turns negative (`first_crossing`) and both along a path (`crossing`).
"""

from __future__ import annotations

import functools
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from .topology import FACE_REFERENCE, FACES, N_FACES, edge_nodes, face_number, reference_nodes

_NEXT = [1, 2, 0]  # corner k+1 (mod 3): edge k joins corners k and k+1


def support_frame(tri: np.ndarray, ref: int, inside: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Supporting-triangle frame (docs/design.md §2, paper Fig. 5).

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


def turn(axis: ArrayLike, angle: float) -> np.ndarray:
    """Rotation matrix (3, 3) of `angle` rad about the unit vector `axis` (3,) (Rodrigues)."""
    k = np.asarray(axis, dtype=float)
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def align(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The smallest rotation (3, 3) taking the unit vector a (3,) onto the unit vector b (3,)
    (about a x b; about any axis normal to a when they are opposite)."""
    k = np.cross(a, b)
    s, c = float(np.linalg.norm(k)), float(np.dot(a, b))
    if s < 1e-12:
        if c > 0:
            return np.eye(3)
        k = np.cross(a, [1.0, 0.0, 0.0] if abs(a[0]) < 0.9 else [0.0, 1.0, 0.0])
        return turn(k / np.linalg.norm(k), np.pi)
    return turn(k / s, np.arctan2(s, c))


def to_frame(p: np.ndarray, origin: np.ndarray, rot: np.ndarray) -> np.ndarray:
    """Express world points p (..., 3) in a frame (origin (..., 3), rows-as-axes rot)."""
    return np.einsum("...ij,...j->...i", rot, p - origin)


def face_frame(nodes: np.ndarray, face: int | Sequence[int]) -> tuple[np.ndarray, np.ndarray]:
    """Support frame of `face` (1..20 or three node numbers) on node positions (..., 12, 3) m:
    origin (..., 3) m and rotation (..., 3, 3), rows = axes x, y, z (z into the robot)."""
    f = face_number(face) - 1
    nodes = np.asarray(nodes, float)
    return support_frame(nodes[..., FACES[f], :], int(FACE_REFERENCE[f]), nodes.mean(axis=-2))


def in_support_frame(
    nodes: np.ndarray, face: int | Sequence[int], frame: tuple[np.ndarray, np.ndarray] | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """CoG (..., 3) m (mean of the nodes = mean of the strut centres, equal masses) and the
    support triangle (..., 3, 3) m, both in the support frame of the current, deformed `face`
    (1..20 or three node numbers); corners in the order of FACES. `frame`: that frame's
    `face_frame(nodes, face)` if the caller has it already."""
    nodes = np.asarray(nodes, float)
    f = face_number(face) - 1
    cog, support = nodes.mean(axis=-2), nodes[..., FACES[f], :]
    origin, rot = support_frame(support, int(FACE_REFERENCE[f]), cog) if frame is None else frame
    return (to_frame(cog, origin, rot), to_frame(support, origin[..., None, :], rot[..., None, :, :]))


@functools.lru_cache(maxsize=64)
def _rest(strut_length: float) -> tuple[np.ndarray, np.ndarray]:
    out = [in_support_frame(reference_nodes(strut_length), f) for f in range(1, N_FACES + 1)]
    cog, support = np.stack([c for c, _ in out]), np.stack([s for _, s in out])
    cog.flags.writeable = support.flags.writeable = False
    return cog, support


def rest_frame(face: int | Sequence[int], strut_length: float) -> tuple[np.ndarray, np.ndarray]:
    """CoG (3,) m and support triangle (3, 3) m of the unactuated, symmetric robot of strut
    length `strut_length` m in the support frame of `face`: the 0 MPa point of every curve."""
    cog, support = _rest(float(strut_length))
    f = face_number(face) - 1
    return cog[f].copy(), support[f].copy()


def edge_distances(point: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """Signed distances (m) of 2-D point(s) (..., 2) to the three edge lines of triangle(s)
    (..., 3, 2), positive on the inner side; edge k joins corners k and k+1 (mod 3)."""
    point, tri = np.asarray(point), np.asarray(tri)
    e = tri[..., _NEXT, :] - tri  # (..., 3, 2): the three edges at once
    nrm = np.stack([e[..., 1], -e[..., 0]], axis=-1) / np.linalg.norm(e, axis=-1)[..., None]
    s = np.sign(np.sum(nrm * (tri.mean(axis=-2)[..., None, :] - tri), axis=-1))[..., None]
    return np.sum(s * nrm * (point[..., None, :] - tri), axis=-1)


def margin_2d(point: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """Signed Euclidean distance (m) of 2-D point(s) (..., 2) to the boundary of triangle(s)
    (..., 3, 2): positive inside, negative outside."""
    point, tri = np.asarray(point), np.asarray(tri)
    e, rel = tri[..., _NEXT, :] - tri, point[..., None, :] - tri  # (..., 3, 2): per edge
    t = np.clip(np.sum(rel * e, axis=-1) / np.sum(e * e, axis=-1), 0.0, 1.0)
    dist = np.min(np.linalg.norm(point[..., None, :] - (tri + t[..., None] * e), axis=-1), axis=-1)
    inside = np.all(edge_distances(point, tri) >= 0, axis=-1)
    return np.where(inside, dist, -dist)


def crossed_edge(point: np.ndarray, support: np.ndarray) -> int | None:
    """Index k of the edge (corners k, k+1 mod 3) that the 2-D CoG projection `point` (2,) m has
    crossed: the most violated edge line of the triangle `support` (3, 2) m; None inside.
    `topology.edge_nodes(face, k)` names it by its nodes."""
    dist = edge_distances(np.asarray(point, float), np.asarray(support, float))
    k = int(np.argmin(dist))
    return None if dist[k] >= 0 else k


def first_crossing(pressure: ArrayLike, margin: ArrayLike) -> tuple[float, int]:
    """Least pressure (MPa) at which `margin` (n,) m turns negative along `pressure` (n,) MPa,
    linearly interpolated, and the index of the first sample outside; (NaN, -1) if none is.
    A path that starts outside gives its first pressure (nothing to interpolate from)."""
    pressure, margin = np.asarray(pressure, float), np.asarray(margin, float)
    out = np.flatnonzero(margin < 0)
    if out.size == 0:
        return float("nan"), -1
    k = int(out[0])
    if k == 0:
        return float(pressure[0]), 0
    p0, p1, m0, m1 = pressure[k - 1], pressure[k], margin[k - 1], margin[k]
    return float(p0 + (p1 - p0) * m0 / (m0 - m1)), k


def crossing(
    pressure: ArrayLike, margin: ArrayLike, point: ArrayLike, support: ArrayLike, face: int
) -> tuple[float, int, tuple[int, int] | None]:
    """Where a path on `face` (1..20) leaves the triangle: pressure (n,) MPa, margin (n,) m of
    the CoG (projection) point (n, >=2) m against support (n, 3, >=2) m in the face's support
    frame. Returns the least pressure at which the margin turns negative, interpolated (MPa,
    NaN: never; `first_crossing`), the index of the first sample outside (-1: none) and the edge
    crossed there (two 1-based nodes, smaller first; `crossed_edge`), None if none is."""
    p, k = first_crossing(pressure, margin)
    if k < 0:
        return p, k, None
    e = crossed_edge(np.asarray(point)[k, :2], np.asarray(support)[k, :, :2])
    return p, k, None if e is None else edge_nodes(face, e)
