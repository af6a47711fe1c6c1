"""The paper's figures of the robot (docs/design.md §7): Fig. 1 and 4 (the robot, its actuator
pairs) and Fig. 5 (the support frame). Figs. 6 and 7 are in `cog_cloud` and
`face_workspace`.

Pure drawing functions on numpy arrays: each writes one PNG (scene.WINDOW px) and returns a
dict saying what was drawn, so that tests can check the scene. Lengths are taken in m; the
support-frame figures (6, 7) show mm.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pyvista as pv

from ..physics import frames
from ..physics import topology as topo
from ..physics.contact import check_nodes
from .scene import (
    AXIS_COLOURS,
    CABLE_COLOUR,
    LABEL,
    PAIR_COLOURS,
    STRUT_COLOURS,
    finish,
    lines,
    node_labels,
    plotter,
    robot_camera,
    strut_length,
    struts,
)

__all__ = ["fig_robot", "fig_support_frame"]


# --- Fig. 1 and 4 ----------------------------------------------------------------------------


def fig_robot(
    nodes: np.ndarray, path: str | Path, highlight_pairs: Sequence[int] | None = None, title: str | None = None
) -> dict:
    """Fig. 1 (or Fig. 4 with highlight_pairs): the robot, struts as thick tubes, one colour
    each, the 24 cables as thin brown tubes and the 12 nodes numbered.

    nodes: (12, 3) node positions, m (any pose). highlight_pairs: 1-based pair numbers; their
    two cables are drawn thick, one colour per pair, labelled "#v" on one of them near node v
    (where it is clearest of the nodes, the other labels and the other pairs' cables), the
    other cables thin grey and the struts grey (paper Fig. 4).
    Returns {"path", "size", "title", "actors", "struts", "cables", "node_labels",
    "highlighted": {pair: [cable index (0-based), ...]}, "pair_labels",
    "pair_label_positions": {pair: (3,) m}, "shifted": [cable index (0-based) drawn moved
    across the view by a tube radius, to show beside a near-overlapping one]}.
    """
    p = check_nodes(nodes)
    pairs = [] if highlight_pairs is None else [topo.check_pair(v) for v in highlight_pairs]
    if len(set(pairs)) != len(pairs):
        raise ValueError(f"highlight_pairs has repeated pairs: {pairs}")
    if title is None:
        title = (
            ("Fig. 4  Actuator pairs " + ", ".join(f"#{v}" for v in pairs))
            if pairs
            else "Fig. 1  Six-strut tensegrity robot: struts (thick), cables (brown), nodes 1-12"
        )
    S = strut_length(p)
    pl = plotter(title)
    robot_camera(pl, p)
    n_struts = struts(pl, p, ["#9a9a9a"] * 6 if pairs else STRUT_COLOURS)
    hot = {v: topo.PAIR_CABLES[v - 1].tolist() for v in pairs}
    cold = np.setdiff1d(np.arange(topo.N_CABLES), [c for cs in hot.values() for c in cs])
    n_cables = 0
    if len(cold):
        mesh = lines(p, topo.CABLES[cold]).tube(radius=(0.003 if pairs else 0.0045) * S, n_sides=12)
        pl.add_mesh(mesh, color="#b4b4b4" if pairs else CABLE_COLOUR, name="cables")
        n_cables += len(cold)
    pair_labels, label_col = [], []
    shift = _overlap_shifts(pl, p, hot, 0.0075 * S)
    for v, cs in hot.items():
        colour = PAIR_COLOURS[v - 1]
        # thin, and moved apart where two pairs' cables nearly overlap in the view, so both show
        ends = np.concatenate([p[topo.CABLES[c]] + shift[c] for c in cs])
        mesh = lines(ends, np.arange(2 * len(cs)).reshape(-1, 2)).tube(radius=0.0075 * S, n_sides=20)
        pl.add_mesh(mesh, color=colour, smooth_shading=True, name=f"pair #{v}")
        n_cables += len(cs)
        pair_labels.append(f"#{v}")
        label_col.append(colour)
    label_pos = _pair_label_positions(pl, p, hot)
    numbers = node_labels(pl, p, np.arange(topo.N_NODES), font_size=22 if pairs else 24)
    pl.add_points(p, color="black", point_size=11, render_points_as_spheres=True, name="nodes")
    for k, (pos, text, colour) in enumerate(zip(label_pos, pair_labels, label_col)):
        pl.add_point_labels(
            pos[None],
            [text],
            font_size=26,
            name=f"pair label {k}",
            **{**LABEL, "text_color": colour, "shape_opacity": 0.85},
        )
    robot_camera(pl, p)  # adding meshes may have reset it
    return finish(
        pl,
        path,
        title,
        struts=n_struts,
        cables=n_cables,
        node_labels=numbers,
        highlighted=hot,
        pair_labels=pair_labels,
        pair_label_positions={v: q for v, q in zip(hot, label_pos)},
        shifted=sorted(c for c, sh in shift.items() if np.any(sh)),
    )


def _overlap_shifts(pl: pv.Plotter, p: np.ndarray, hot: dict, radius: float) -> dict:
    """{cable index: (3,) m} small shifts across the view for the highlighted cables of
    different pairs that leave the same node in nearly the same direction on screen (within
    12 deg): each is moved by one tube radius away from the other, so neither hides."""
    d = np.asarray(pl.camera.position) - np.asarray(pl.camera.focal_point)
    d /= np.linalg.norm(d)
    owner = {c: v for v, cs in hot.items() for c in cs}
    shift = {c: np.zeros(3) for c in owner}
    for c in owner:
        for o in owner:
            common = set(topo.CABLES[c]) & set(topo.CABLES[o])
            if owner[o] == owner[c] or not common:
                continue
            n0 = common.pop()
            dirs = []
            for k in (c, o):
                far = topo.CABLES[k][1] if topo.CABLES[k][0] == n0 else topo.CABLES[k][0]
                e = p[far] - p[n0]
                e -= np.dot(e, d) * d
                dirs.append(e / np.linalg.norm(e))
            if np.dot(dirs[0], dirs[1]) > np.cos(np.radians(12)):
                across = np.cross(d, dirs[0])
                shift[c] = shift[c] - radius * np.sign(np.dot(across, dirs[1])) * across
    return shift


def _pair_label_positions(pl: pv.Plotter, p: np.ndarray, hot: dict) -> list[np.ndarray]:
    """Where to write "#v" for each highlighted pair (hot: {v: cable indices}): on one of the
    pair's own cables, 25-55 % of the way from node v, at the candidate furthest (in the
    image plane) from the nodes, the labels placed so far and the other pairs' cables."""
    d = np.asarray(pl.camera.position) - np.asarray(pl.camera.focal_point)
    d /= np.linalg.norm(d)

    def flat(x):  # projection on the image plane
        x = np.atleast_2d(x)
        return x - (x @ d)[:, None] * d

    def seg_dist(q, a, b):
        e = b - a
        t = np.clip(np.dot(q - a, e) / max(np.dot(e, e), 1e-12), 0.0, 1.0)
        return np.linalg.norm(q - (a + t * e))

    nodes2 = flat(p)
    placed, out = [], []
    for v, cs in hot.items():
        others = [flat(p[topo.CABLES[c]]) for u, cc in hot.items() if u != v for c in cc]
        best = None
        for c in cs:
            far = topo.CABLES[c][1] if topo.CABLES[c][0] == v - 1 else topo.CABLES[c][0]
            for t in (0.25, 0.35, 0.45, 0.55):
                q = p[v - 1] + t * (p[far] - p[v - 1])
                q2 = flat(q)[0]
                score = min(
                    [np.min(np.linalg.norm(nodes2 - q2, axis=1))]
                    + [2.0 * np.linalg.norm(q2 - r) for r in placed]
                    + [seg_dist(q2, o[0], o[1]) for o in others]
                )
                if best is None or score > best[0]:
                    best = (score, q, q2)
        placed.append(best[2])
        out.append(best[1])
    return out


# --- Fig. 5 ----------------------------------------------------------------------------------


def _frame_camera(pl: pv.Plotter, nodes: np.ndarray, origin: np.ndarray, rot: np.ndarray) -> None:
    """Camera fixed in the support frame: 45 deg above the support plane on the side away from
    the reference vertex, so y points into the picture, x to the right and z (into the robot)
    up."""
    S = strut_length(nodes)
    h = 0.5 * rot[0] - rot[1]
    h /= np.linalg.norm(h)
    d = np.cos(np.radians(45)) * h + np.sin(np.radians(45)) * rot[2]
    centre = origin + 0.95 * (nodes.mean(axis=0) - origin)
    pl.camera.focal_point = centre
    pl.camera.position = centre + 3.15 * S * d
    pl.camera.up = rot[2]
    pl.camera.view_angle = 30.0
    pl.renderer.ResetCameraClippingRange()


def fig_support_frame(nodes: np.ndarray, face: int | Sequence[int], path: str | Path, title: str | None = None) -> dict:
    """Fig. 5: the support frame of `face` (1..20 or three node numbers): the robot faint,
    the support triangle filled, the x, y, z axes as arrows at its centroid (z into the robot,
    toward the CoG = mean of the nodes, y toward the reference vertex), corners numbered.

    nodes: (12, 3) m. Returns {"path", "size", "title", "actors", "face", "corners" (1-based
    node numbers), "axes" (3, 3) rows x, y, z in world components, "origin" (3,) m}.
    """
    p = check_nodes(nodes)
    f = topo.face_number(face)
    corners = topo.FACES[f - 1]
    support, cog = p[corners], p.mean(axis=0)
    origin, rot = frames.face_frame(p, f)
    if title is None:
        title = f"Fig. 5  Supporting-triangle frame of face {f} {topo.face_label(f)} ({topo.FACE_TYPES[f - 1]})"
    S = strut_length(p)
    pl = plotter(title)
    _frame_camera(pl, p, origin, rot)
    struts(pl, p, STRUT_COLOURS, opacity=0.15)
    pl.add_mesh(
        lines(p, topo.CABLES).tube(radius=0.004 * S, n_sides=10), color=CABLE_COLOUR, opacity=0.18, name="cables"
    )
    pl.add_mesh(
        pv.PolyData(support, faces=[3, 0, 1, 2]), color="#ffd54a", opacity=0.85, lighting=False, name="support triangle"
    )
    pl.add_mesh(
        lines(support, np.array([[0, 1], [1, 2], [2, 0]])).tube(radius=0.005 * S),
        color="#b8860b",
        name="support triangle edges",
    )
    length = 0.62 * float(np.min(np.linalg.norm(support - origin, axis=1)))
    tips = []
    for k, name in enumerate("xyz"):
        arrow = pv.Arrow(
            start=origin, direction=rot[k], scale=length, tip_length=0.22, tip_radius=0.07, shaft_radius=0.028
        )
        pl.add_mesh(arrow, color=AXIS_COLOURS[name], name=f"axis {name}")
        tips.append(origin + 1.12 * length * rot[k] + 0.16 * length * rot[(k + 2) % 3])
    pl.add_point_labels(
        np.array(tips), list("xyz"), font_size=34, name="axis labels", **{**LABEL, "shape_opacity": 0.0}
    )
    pl.add_point_labels(
        origin[None] - 0.12 * length * (rot[0] + rot[1]),
        ["O"],
        font_size=24,
        name="origin label",
        **{**LABEL, "shape_opacity": 0.0},
    )
    pl.add_points(cog[None], color="black", point_size=16, render_points_as_spheres=True, name="cog")
    pl.add_point_labels(cog[None] + 0.05 * S * rot[0], ["CoG"], font_size=22, name="cog label", **LABEL)
    node_labels(pl, p, corners, font_size=28, name="corner labels", offset=0.09)
    pl.add_points(support, color="black", point_size=12, render_points_as_spheres=True, name="corners")
    _frame_camera(pl, p, origin, rot)
    return finish(pl, path, title, face=f, corners=(corners + 1).tolist(), axes=rot, origin=origin)
