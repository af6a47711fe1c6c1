"""Contact and stability of a robot on a terrain (paper III.B, Fig. 8-10; docs/design.md §6).

Pure functions on node positions (12, 3) m and a `Terrain`. The contact face is the three nodes
nearest the terrain, each within a tolerance of touching it, and they must be one of the 20
faces. The CoG (the mean of the nodes, equal strut masses) is projected *along gravity* onto the
plane of the three contact nodes, so that slopes are handled as in the paper's Fig. 10; the robot
stands while that projection is inside the contact triangle (margin > 0) and otherwise rolls over
the edge it has crossed onto the other face sharing that edge.

Edges are named by their two 1-based node numbers, smaller first, e.g. (10, 12).
"""

from __future__ import annotations

import functools
import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from . import frames
from . import topology as topo
from .terrain import Terrain

GRAVITY_DIR = np.array([0.0, 0.0, -1.0])  # world frame, z up (docs/design.md §2)

__all__ = [
    "ContactError",
    "Contact",
    "check_nodes",
    "clearance",
    "contact_face",
    "resting_face",
    "face_from_gaps",
    "project_along_gravity",
    "edge_outward",
    "judge",
    "analyse",
    "past_edge",
    "GRAVITY_DIR",
]


class ContactError(ValueError):
    """No valid contact face: fewer than three nodes touch, or the three do not form a face."""


def check_nodes(nodes: ArrayLike) -> np.ndarray:
    """Node positions as a finite (12, 3) float array, m; ValueError otherwise."""
    p = np.asarray(nodes, dtype=float)
    if p.shape != (topo.N_NODES, 3):
        raise ValueError(f"node positions must have shape (12, 3) m, got {p.shape}")
    if not np.all(np.isfinite(p)):
        raise ValueError("node positions hold NaN or inf: the state is not finite")
    return p


def clearance(nodes: ArrayLike, terrain: Terrain, radius: float) -> np.ndarray:
    """Gap (..., 12) m between each node's contact sphere (radius m) and the terrain, for node
    positions (..., 12, 3) m, measured along the normal of the terrain triangle under the node as
    the simulator does (negative when the sphere penetrates). Raises ValueError for NaN nodes,
    the free mode (no terrain) or a node with no terrain under it."""
    p = np.asarray(nodes, dtype=float)
    if p.shape[-2:] != (topo.N_NODES, 3):
        raise ValueError(f"node positions must have shape (..., 12, 3) m, got {p.shape}")
    if not np.all(np.isfinite(p)):
        raise ValueError("node positions hold NaN or inf: the state is not finite")
    if terrain.kind == "none":
        raise ValueError("terrain 'none' (the free mode) has no ground to stand on")
    h, n = terrain.height_and_normal(p[..., 0], p[..., 1])
    if np.any(np.isnan(h)):
        k = np.argwhere(np.isnan(h))[0]
        q = p[tuple(k)]
        raise ValueError(f"terrain has nothing under node {k[-1] + 1} at ({q[0]:.3f}, {q[1]:.3f}) m")
    return (p[..., 2] - h) * n[..., 2] - radius


def contact_face(nodes: ArrayLike, terrain: Terrain, radius: float, tol: float | None = None) -> int:
    """1-based face resting on the terrain: the three nodes of least clearance, each within
    `tol` m of touching (default: the radius), forming one of the 20 faces. Raises ContactError
    otherwise (the robot is in the air, tipping, or rests on three nodes that are not a face)."""
    return face_from_gaps(clearance(nodes, terrain, radius), radius if tol is None else tol)


_FACE_OF_NODES = {tuple(sorted(c.tolist())): f + 1 for f, c in enumerate(topo.FACES)}
# the same as a table: [a, b, c] -> face (0: not a face) for 0-based nodes a, b, c in any order
_FACE_TABLE = np.zeros((topo.N_NODES,) * 3, np.int64)
for _nodes, _face in _FACE_OF_NODES.items():
    for _order in itertools.permutations(_nodes):
        _FACE_TABLE[_order] = _face


def resting_face(gap: ArrayLike, tol: float) -> np.ndarray:
    """The one rule for "the robot stands on face F": the three nodes of least clearance
    `gap` (..., 12) m each within `tol` m of touching, and forming one of the 20 faces.
    Returns the 1-based face (...,) int, 0 where no face rests on the terrain."""
    gap = np.asarray(gap, float)
    low = np.argsort(gap, axis=-1, kind="stable")[..., :3]  # the three least, least first
    touching = np.take_along_axis(gap, low[..., 2:], axis=-1)[..., 0] <= np.asarray(tol, float)
    return np.where(touching, _FACE_TABLE[low[..., 0], low[..., 1], low[..., 2]], 0)


def face_from_gaps(gap: ArrayLike, tol: float) -> int:
    """`resting_face` of one robot's clearances (12,) m; ContactError when no face rests."""
    gap = np.asarray(gap, float)
    face = int(resting_face(gap, tol))
    if face:
        return face
    low = np.argsort(gap, kind="stable")[:3]
    if np.any(gap[low] > tol):
        raise ContactError(
            f"only {int(np.sum(gap <= tol))} node(s) within {tol * 1e3:.1f} mm of the terrain: no face rests on it"
        )
    raise ContactError(f"the nodes touching the terrain, {tuple(sorted(int(k) + 1 for k in low))}, are not a face")


def project_along_gravity(
    point: ArrayLike, plane_point: ArrayLike, plane_normal: ArrayLike, gravity: ArrayLike = GRAVITY_DIR
) -> np.ndarray:
    """Point (..., 3) m moved along `gravity` (..., 3), a vector of any length, onto the plane
    through plane_point (..., 3) m with unit normal plane_normal (..., 3) (paper Fig. 10)."""
    g, n = np.asarray(gravity, float), np.asarray(plane_normal, float)
    along = np.sum(n * g, axis=-1, keepdims=True)
    if np.any(np.abs(along) < 1e-9 * np.linalg.norm(g, axis=-1, keepdims=True)):
        raise ValueError("support plane is parallel to gravity: no projection")
    s = np.sum(n * (np.asarray(plane_point, float) - point), axis=-1, keepdims=True) / along
    return point + s * g


def edge_outward(tri: ArrayLike) -> np.ndarray:
    """Unit outward normals (3, 3) of the edges of triangle `tri` (3, 3) m, in its plane; row k
    belongs to the edge joining corners k and k+1 (mod 3), as in frames.edge_distances."""
    tri = np.asarray(tri, float)
    c = tri.mean(axis=0)
    n = np.cross(tri[1] - tri[0], tri[2] - tri[0])
    out = np.empty((3, 3))
    for k in range(3):
        e = tri[(k + 1) % 3] - tri[k]
        o = np.cross(e, n)
        o *= np.sign(np.dot(o, tri[k] - c))
        out[k] = o / np.linalg.norm(o)
    return out


@dataclass(frozen=True)
class Contact:
    """Where and how a robot stands (paper Fig. 8-10). Lengths in m, world frame unless noted.

    face: 1-based contact face; nodes: its node numbers in topology.FACES order;
    cog (3,): centre of gravity; projection (3,): the CoG projected along gravity onto the plane
    of the three contact nodes; projection_2d (2,) and support (3, 2): that projection and the
    support triangle in the face's support frame (docs/design.md §2); normal (3,): the support plane's
    unit normal, into the robot; margin: signed distance of the projection to the triangle's
    boundary (positive inside); stands: margin > 0; edge: the crossed edge (1-based nodes) or
    None; next_face: the face across that edge, or None; clearance (12,): gaps to the terrain
    (None when judged without one)."""

    face: int
    nodes: tuple[int, int, int]
    cog: np.ndarray
    projection: np.ndarray
    projection_2d: np.ndarray
    support: np.ndarray
    normal: np.ndarray
    margin: float
    stands: bool
    edge: tuple[int, int] | None
    next_face: int | None
    clearance: np.ndarray


def judge(nodes: ArrayLike, face: int | Sequence[int]) -> Contact:
    """Stability of a robot with node positions `nodes` (12, 3) m on `face` (1..20 or three node
    numbers), without a terrain: the CoG projected along gravity onto the face's plane, the
    margin, the crossed edge and the next face. `clearance` is None."""
    return _judge(check_nodes(nodes), topo.face_number(face), None)


def analyse(
    nodes: ArrayLike, terrain: Terrain, radius: float, tol: float | None = None, face: int | Sequence[int] | None = None
) -> Contact:
    """Contact face on `terrain` (see contact_face), CoG projection along gravity, margin, and
    the edge the robot rolls over if it does not stand. `face` (1..20 or three node numbers)
    skips the detection and judges stability on that face (for a robot that is tipping)."""
    p = check_nodes(nodes)
    gap = clearance(p, terrain, radius)
    f = contact_face(p, terrain, radius, tol) if face is None else topo.face_number(face)
    return _judge(p, f, gap)


def _judge(p: np.ndarray, f: int, gap) -> Contact:
    corners = topo.FACES[f - 1]
    cog = p.mean(axis=0)
    origin, rot = frames.face_frame(p, f)
    proj = project_along_gravity(cog, origin, rot[2])
    projection_2d = frames.to_frame(proj, origin, rot)[:2]
    support = frames.to_frame(p[corners], origin, rot)[:, :2]
    margin = float(frames.margin_2d(projection_2d, support))
    k = frames.crossed_edge(projection_2d, support)
    edge = None if k is None else topo.edge_nodes(f, k)
    return Contact(
        f,
        tuple(int(n) + 1 for n in corners),
        cog,
        proj,
        projection_2d,
        support,
        rot[2],
        margin,
        bool(margin > 0),
        edge,
        None if edge is None else topo.neighbour(f, edge),
        gap,
    )


def past_edge(nodes: ArrayLike, face: int | Sequence[int], pivot: Sequence[int], strut_length: float) -> float:
    """How far (m) the CoG of the *unactuated* robot, posed like `nodes` (12, 3) m while
    pivoting on the edge `pivot` (two 1-based nodes) of `face`, lies beyond that edge,
    horizontally (negative: on the face's side). Positive means that releasing the muscles now
    lets gravity finish the roll. The pose is fitted to the symmetric shape (strut length m) by
    the pivot edge's direction and the face's normal, so the muscles' deformation, which relaxes
    on release, is left out. For the symmetric robot at rest on flat ground it is minus the
    distance of the CoG projection to the edge (88.4 mm for an equilateral face, S = 0.5 m)."""
    p = check_nodes(nodes)
    a_i, b_i, c_i = _pivot_nodes(topo.face_number(face), tuple(int(n) for n in pivot))
    k = _pivot_offset(float(strut_length), a_i, b_i, c_i)
    a, b, c = p[a_i].tolist(), p[b_i].tolist(), p[c_i].tolist()
    frame = _pivot_frame(a, b, c, p.mean(axis=0).tolist())
    gx, gy = (sum(axis[i] * kj for axis, kj in zip(frame, k)) for i in (0, 1))  # the CoG from the edge's middle
    e = frame[0]
    h = math.hypot(e[0], e[1])  # outward: horizontal, across the edge, away from the third node
    ux, uy = e[0] / h, e[1] / h
    wx, wy = 0.5 * (a[0] + b[0]) - c[0], 0.5 * (a[1] + b[1]) - c[1]
    d = wx * ux + wy * uy
    wx, wy = wx - d * ux, wy - d * uy
    return (gx * wx + gy * wy) / math.hypot(wx, wy)


@functools.lru_cache(maxsize=256)
def _pivot_offset(strut_length: float, a_i: int, b_i: int, c_i: int) -> tuple[float, float, float]:
    """The symmetric shape's CoG offset from the pivot edge's midpoint in its pivot frame, m:
    `past_edge`'s reference, the same for every call on that edge."""
    ref = topo.reference_nodes(strut_length)
    frame = _pivot_frame(ref[a_i].tolist(), ref[b_i].tolist(), ref[c_i].tolist(), [0.0, 0.0, 0.0])
    g = (ref.mean(axis=0) - 0.5 * (ref[a_i] + ref[b_i])).tolist()
    return tuple(sum(u * v for u, v in zip(axis, g)) for axis in frame)


def _pivot_frame(a: list, b: list, c: list, centre: list) -> tuple[tuple[float, float, float], ...]:
    """The pivot frame of points a, b (the pivot edge) and c (the face's third node), m (x, y, z):
    the edge's direction a -> b, the face's normal toward `centre` and their cross product, in
    floats (a call per check of a roll: numpy's overhead would be most of it)."""
    ex, ey, ez = b[0] - a[0], b[1] - a[1], b[2] - a[2]
    le = math.sqrt(ex * ex + ey * ey + ez * ez)
    ex, ey, ez = ex / le, ey / le, ez / le
    fx, fy, fz = c[0] - a[0], c[1] - a[1], c[2] - a[2]
    nx, ny, nz = ey * fz - ez * fy, ez * fx - ex * fz, ex * fy - ey * fx
    ln = math.sqrt(nx * nx + ny * ny + nz * nz)
    if nx * (centre[0] - a[0]) + ny * (centre[1] - a[1]) + nz * (centre[2] - a[2]) < 0:
        ln = -ln
    nx, ny, nz = nx / ln, ny / ln, nz / ln
    return (ex, ey, ez), (nx, ny, nz), (ey * nz - ez * ny, ez * nx - ex * nz, ex * ny - ey * nx)


@functools.lru_cache(maxsize=256)
def _pivot_nodes(f: int, pivot: tuple[int, int]) -> tuple[int, int, int]:
    """0-based nodes a, b of the edge `pivot` (1-based nodes) of face f and c, the face's third."""
    a_i, b_i = (n - 1 for n in pivot)
    others = [int(n) for n in topo.FACES[f - 1] if n not in (a_i, b_i)]
    if len(others) != 1:
        raise ValueError(f"edge {pivot} is not an edge of face {topo.face_label(f)}")
    return a_i, b_i, others[0]


def roll_over(nodes: ArrayLike, face: int | Sequence[int], edge: Sequence[int]) -> tuple[int, np.ndarray]:
    """The face across `edge` (two 1-based nodes) of `face` and the nodes (12, 3) m rotated
    rigidly about that edge until that face lies in the plane `face` lies in now: where the
    robot lands when it rolls over the edge without deforming."""
    p = check_nodes(nodes)
    f = topo.face_number(face)
    to = topo.neighbour(f, tuple(int(n) for n in edge))
    a, b = (int(n) - 1 for n in edge)
    centre = p.mean(axis=0)

    def inward(tri):  # unit normal of a triangle of nodes, pointing into the robot
        n = np.cross(p[tri[1]] - p[tri[0]], p[tri[2]] - p[tri[0]])
        return n / np.linalg.norm(n) * np.sign(np.dot(n, centre - p[tri[0]]))

    axis = (p[b] - p[a]) / np.linalg.norm(p[b] - p[a])
    u, v = inward(topo.FACES[to - 1]), inward(topo.FACES[f - 1])  # turn u onto v about the edge
    ang = np.arctan2(np.dot(axis, np.cross(u, v)), np.dot(u, v) - np.dot(u, axis) * np.dot(v, axis))
    return to, (p - p[a]) @ frames.turn(axis, ang).T + p[a]
