"""The paper's figures of the robot and its workspace (docs/design.md §7): Fig. 1 and 4 (the
robot, its actuator pairs), Fig. 5 (the support frame), Fig. 6 (the CoG cloud of a sweep) and
Fig. 7 (the kinematic workspace of a face).

Pure drawing functions on numpy arrays: each writes one PNG (scene.WINDOW px) and returns a
dict saying what was drawn, so that tests can check the scene. Lengths are taken in m; the
support-frame figures (6, 7) show mm.
"""
from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pyvista as pv
from numpy.typing import ArrayLike
from matplotlib import colormaps  # a PyVista dependency

from ..physics import frames, topology as topo
from ..physics.contact import check_nodes
from . import plot2d
from .scene import (AXIS_COLOURS, CABLE_COLOUR, LABEL, PAIR_COLOURS, STRUT_COLOURS, finish,
                    lines, node_labels, plotter, robot_camera, strut_length, struts)

__all__ = ["fig_robot", "fig_support_frame", "fig_cog_cloud", "fig_workspace", "level_colours"]


# --- Fig. 1 and 4 ----------------------------------------------------------------------------

def fig_robot(nodes: np.ndarray, path: str | Path, highlight_pairs: Sequence[int] | None = None,
              title: str | None = None) -> dict:
    """Fig. 1 (or Fig. 4 with highlight_pairs): the robot, struts as thick tubes, one colour
    each, the 24 cables as thin brown tubes and the 12 nodes numbered.

    nodes: (12, 3) node positions, m (any pose). highlight_pairs: 1-based pair numbers; their
    two cables are drawn thick, one colour per pair, labelled "#v" near node v, the other
    cables thin grey and the struts grey (paper Fig. 4).
    Returns {"path", "size", "title", "actors", "struts", "cables", "node_labels",
    "highlighted": {pair: [cable index (0-based), ...]}, "pair_labels"}.
    """
    p = check_nodes(nodes)
    pairs = [] if highlight_pairs is None else [topo.check_pair(v) for v in highlight_pairs]
    if len(set(pairs)) != len(pairs):
        raise ValueError(f"highlight_pairs has repeated pairs: {pairs}")
    if title is None:
        title = ("Fig. 4  Actuator pairs " + ", ".join(f"#{v}" for v in pairs)) if pairs else \
            "Fig. 1  Six-strut tensegrity robot: struts (thick), cables (brown), nodes 1-12"
    S = strut_length(p)
    pl = plotter(title)
    robot_camera(pl, p)
    n_struts = struts(pl, p, ["#9a9a9a"] * 6 if pairs else STRUT_COLOURS)
    hot = {v: topo.PAIR_CABLES[v - 1].tolist() for v in pairs}
    cold = np.setdiff1d(np.arange(topo.N_CABLES), [c for cs in hot.values() for c in cs])
    n_cables = 0
    if len(cold):
        mesh = lines(p, topo.CABLES[cold]).tube(radius=(0.003 if pairs else 0.0045) * S,
                                                n_sides=12)
        pl.add_mesh(mesh, color="#b4b4b4" if pairs else CABLE_COLOUR, name="cables")
        n_cables += len(cold)
    pair_labels, label_pos, label_col = [], [], []
    for v, cs in hot.items():
        colour = PAIR_COLOURS[v - 1]
        mesh = lines(p, topo.CABLES[cs]).tube(radius=0.011 * S, n_sides=20)
        pl.add_mesh(mesh, color=colour, smooth_shading=True, name=f"pair #{v}")
        n_cables += len(cs)
        # "#v" between the pair's two cables, a third of the way from node v
        far = [c[1] if c[0] == v - 1 else c[0] for c in topo.CABLES[cs]]
        label_pos.append(p[v - 1] + 0.34 * (p[far].mean(axis=0) - p[v - 1]))
        pair_labels.append(f"#{v}")
        label_col.append(colour)
    numbers = node_labels(pl, p, np.arange(topo.N_NODES), font_size=22 if pairs else 24)
    pl.add_points(p, color="black", point_size=11, render_points_as_spheres=True, name="nodes")
    for k, (pos, text, colour) in enumerate(zip(label_pos, pair_labels, label_col)):
        pl.add_point_labels(pos[None], [text], font_size=26, name=f"pair label {k}",
                            **{**LABEL, "text_color": colour, "shape_opacity": 0.85})
    robot_camera(pl, p)  # adding meshes may have reset it
    return finish(pl, path, title, struts=n_struts, cables=n_cables, node_labels=numbers,
                  highlighted=hot, pair_labels=pair_labels)


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


def fig_support_frame(nodes: np.ndarray, face: int | Sequence[int], path: str | Path,
                      title: str | None = None) -> dict:
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
        title = (f"Fig. 5  Supporting-triangle frame of face {f} {topo.face_label(f)} "
                 f"({topo.FACE_TYPES[f - 1]})")
    S = strut_length(p)
    pl = plotter(title)
    _frame_camera(pl, p, origin, rot)
    struts(pl, p, STRUT_COLOURS, opacity=0.15)
    pl.add_mesh(lines(p, topo.CABLES).tube(radius=0.004 * S, n_sides=10), color=CABLE_COLOUR,
                opacity=0.18, name="cables")
    pl.add_mesh(pv.PolyData(support, faces=[3, 0, 1, 2]), color="#ffd54a", opacity=0.85,
                lighting=False, name="support triangle")
    pl.add_mesh(lines(support, np.array([[0, 1], [1, 2], [2, 0]])).tube(radius=0.005 * S),
                color="#b8860b", name="support triangle edges")
    length = 0.62 * float(np.min(np.linalg.norm(support - origin, axis=1)))
    tips = []
    for k, name in enumerate("xyz"):
        arrow = pv.Arrow(start=origin, direction=rot[k], scale=length, tip_length=0.22,
                         tip_radius=0.07, shaft_radius=0.028)
        pl.add_mesh(arrow, color=AXIS_COLOURS[name], name=f"axis {name}")
        tips.append(origin + 1.12 * length * rot[k] + 0.16 * length * rot[(k + 2) % 3])
    pl.add_point_labels(np.array(tips), list("xyz"), font_size=34, name="axis labels",
                        **{**LABEL, "shape_opacity": 0.0})
    pl.add_point_labels(origin[None] - 0.12 * length * (rot[0] + rot[1]), ["O"], font_size=24,
                        name="origin label", **{**LABEL, "shape_opacity": 0.0})
    pl.add_points(cog[None], color="black", point_size=16, render_points_as_spheres=True,
                  name="cog")
    pl.add_point_labels(cog[None] + 0.05 * S * rot[0], ["CoG"], font_size=22, name="cog label",
                        **LABEL)
    node_labels(pl, p, corners, font_size=28, name="corner labels", offset=0.09)
    pl.add_points(support, color="black", point_size=12, render_points_as_spheres=True,
                  name="corners")
    _frame_camera(pl, p, origin, rot)
    return finish(pl, path, title, face=f, corners=(corners + 1).tolist(), axes=rot,
                  origin=origin)


# --- Fig. 6 and 7: support-frame plots (mm, viewed along -z) ---------------------------------

def level_colours(n: int) -> np.ndarray:
    """RGB (n, 3) in 0..1 of n pressure levels, low to high (viridis, the yellow end left out)."""
    return colormaps["viridis"](np.linspace(0.0, 0.85, n))[:, :3]


def _sample_levels(n_samples: int, levels: np.ndarray, sample_pressure) -> np.ndarray:
    if sample_pressure is None:  # the paper's staircase: equal holds, in order
        return np.minimum(np.arange(n_samples) * len(levels) // n_samples, len(levels) - 1)
    sp = np.asarray(sample_pressure, float).reshape(-1)
    if sp.size != n_samples:
        raise ValueError(f"sample_pressure has {sp.size} values for {n_samples} samples")
    return np.argmin(np.abs(sp[:, None] - levels[None, :]), axis=1)


def _check_points(a, name: str, n: int | None = None) -> np.ndarray:
    a = np.asarray(a, float)
    if a.ndim != 2 or a.shape[1] != 3 or (n is not None and len(a) != n) or \
            not np.all(np.isfinite(a)):
        want = f"({n}, 3)" if n is not None else "(n, 3)"
        raise ValueError(f"{name} must be a finite {want} array in m, got shape {a.shape}")
    return a


def fig_cog_cloud(samples: np.ndarray, nominal: np.ndarray, levels: ArrayLike, support: np.ndarray,
                  path: str | Path, pair: int, face_label: str, sample_pressure: ArrayLike | None = None,
                  corner_labels: Sequence[int] | np.ndarray | None = None,
                  title: str | None = None) -> dict:
    """Fig. 6: the CoG during a pressure sweep, projected on the support plane (mm): samples
    as a point cloud coloured by pressure level, nominal CoGs (level averages, paper III.A)
    as circles labelled with their pressure; the main view is zoomed on the cloud with the
    nearest triangle edge, a side panel shows the whole support triangle.

    samples: (T, 3) CoG in the support frame, m; nominal: (n, 3) m; levels: (n,) MPa;
    support: (3, 3) support triangle in the support frame, m (corners in face order);
    sample_pressure: (T,) MPa of each sample (default: n equal consecutive blocks);
    corner_labels: three node numbers for the support's corners.
    Returns {"path", "size", "title", "actors", "samples", "nominal", "labels",
    "support_edges" (edges in the main view), "view_mm" (xmin, xmax, ymin, ymax)}.
    """
    pair = topo.check_pair(pair)
    s = _check_points(samples, "samples") * 1e3
    levels = np.asarray(levels, float).reshape(-1)
    nom = _check_points(nominal, "nominal", len(levels)) * 1e3
    t = _check_points(support, "support", 3) * 1e3
    lvl = _sample_levels(len(s), levels, sample_pressure)
    cols = level_colours(len(levels))
    if title is None:
        title = (f"Fig. 6  CoG path when #{pair} works, face {face_label}, "
                 f"{levels.min():g}-{levels.max():g} MPa (support frame, top view)")
    pl = plotter(title, panels=3)

    # Main view: the cloud, the nominal CoGs, the frame origin and the nearest edge's stretch.
    pts = np.vstack([s[:, :2], nom[:, :2], [[0.0, 0.0]]])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    span = max(hi - lo)
    edges = [(t[k, :2], t[(k + 1) % 3, :2]) for k in range(3)]
    some = pts[::max(1, len(pts) // 400)]
    dist = [min(plot2d.segment_distance(q, a, b) for q in some) for a, b in edges]
    k_near = int(np.argmin(dist))
    if dist[k_near] < 1.5 * span:  # show the edge the CoG is heading for
        a, b = edges[k_near]
        foot = [plot2d.closest_on_segment(q, a, b) for q in (nom[-1, :2], lo, hi)]
        lo = np.minimum(lo, np.min(foot, axis=0))
        hi = np.maximum(hi, np.max(foot, axis=0))
    size = hi - lo
    box, nx, ny = plot2d.nice_box(lo - 0.06 * size.max(), hi + 0.06 * size.max(), n=8)
    r = 0.016 * max(box[1] - box[0], box[3] - box[2])

    n_edges = plot2d.support_2d(pl, t, box, 5, "triangle", corner_labels=corner_labels)
    cloud = pv.PolyData(np.column_stack([s[:, :2], np.zeros(len(s))]))
    cloud["rgb"] = (cols[lvl] * 255).astype(np.uint8)
    pl.add_mesh(cloud, scalars="rgb", rgb=True, point_size=4, render_points_as_spheres=True,
                name="cog samples")
    for k in range(len(levels)):
        pl.add_mesh(plot2d.disc(nom[k], r, 2.0), color=cols[k], name=f"nominal {k}",
                    lighting=False)
        pl.add_mesh(plot2d.disc(nom[k], r, 2.5, inner=0.72 * r), color="black",
                    name=f"nominal ring {k}", lighting=False)
    labels = [f"{p:g} MPa" for p in levels]
    direction = nom[-1, :2] - nom[0, :2]
    side = np.array([-direction[1], direction[0]]) / max(np.linalg.norm(direction), 1e-12)
    pl.add_point_labels(np.column_stack([nom[:, :2] + 3.2 * r * side, np.full(len(nom), 4.0)]),
                        labels, font_size=18, name="nominal labels", **LABEL)
    pl.add_points(np.array([[0.0, 0.0, 1.0]]), color="black", point_size=10,
                  render_points_as_spheres=True, name="origin")
    pl.add_point_labels(np.array([[0.0, 0.0, 4.0]]) + [r, -r, 0], ["centroid"], font_size=16,
                        name="origin label", **{**LABEL, "shape_opacity": 0.0})
    if corner_labels is not None:
        plot2d.corner_labels(pl, t, corner_labels, 4.0, 18, "corner labels")
    plot2d.axes_2d(pl, box, nx, ny)
    plot2d.camera_2d(pl, 0, box, margins=(0.13, 0.04, 0.1, 0.03))

    # Context panel: the whole triangle, the cloud and a box around the main view.
    pl.subplot(0, 1)
    tb = (t[:, 0].min(), t[:, 0].max(), t[:, 1].min(), t[:, 1].max())
    plot2d.support_2d(pl, t, tb, 3, "context triangle")
    pl.add_mesh(cloud.copy(), scalars="rgb", rgb=True, point_size=2, name="context samples")
    frame = np.array([[box[0], box[2], 1], [box[1], box[2], 1], [box[1], box[3], 1],
                      [box[0], box[3], 1], [box[0], box[2], 1]])
    pl.add_lines(frame, color="black", width=2, connected=True, name="context view box")
    if corner_labels is not None:
        plot2d.corner_labels(pl, t, corner_labels, 4.0, 14, "context corner labels")
    pl.add_text("whole support triangle", position="upper_edge", font_size=10, color="black",
                name="context caption")
    plot2d.camera_2d(pl, 1, tb, margins=(0.12, 0.12, 0.1, 0.15))

    # Legend panel: the pressure levels.
    pl.subplot(0, 2)
    pl.add_legend([[lab, tuple(c), "circle"] for lab, c in zip(labels, cols)], bcolor=None,
                  size=(0.5, 0.6), loc="center", name="legend")
    return finish(pl, path, title, samples=len(s), nominal=len(nom), labels=labels,
                  support_edges=n_edges, view_mm=tuple(float(v) for v in box))


def fig_workspace(cog_paths: dict, support: np.ndarray, path: str | Path, title: str,
                  tip_points: dict | None = None,
                  corner_labels: Sequence[int] | np.ndarray | None = None,
                  zoom_mm: float | None = None) -> dict:
    """Fig. 7: the kinematic workspace of one contact face, viewed from above (support-frame z
    toward the camera, CoG projected on the support plane, mm): each pair's CoG curve as a
    coloured line labelled "#v" at its far end, the support triangle with its corners' node
    numbers (corner_labels), and where a curve leaves the triangle (tip_points) as a red ring.
    A side panel zooms on the curves' common start, where the short curves are; a legend
    names every pair with its reach.

    cog_paths: {pair: (m, 3) CoG points along its curve, support frame, m, from low to high
    pressure}; support: (3, 3) support triangle in the support frame, m; tip_points:
    {pair: (3,) m or None}; corner_labels: three node numbers for the support's corners;
    zoom_mm: half-width of the zoom panel, mm (default: from the short curves).
    Returns {"path", "size", "title", "actors", "cog_paths" {pair: number of points},
    "labels" (main view), "zoom_labels", "tips" [pairs], "zoom_mm", "view_mm"}.
    """
    curves = {topo.check_pair(v): _check_points(c, f"curve of pair {v}") * 1e3
              for v, c in sorted(cog_paths.items())}
    if not curves:
        raise ValueError("cog_paths is empty: give at least one pair's CoG path")
    t = _check_points(support, "support", 3) * 1e3
    tips = {topo.check_pair(v): _check_points(np.reshape(q, (1, 3)), f"tip of pair {v}")[0] * 1e3
            for v, q in (tip_points or {}).items() if q is not None}
    pl = plotter(title, panels=3)
    circum = float(np.max(np.linalg.norm(t[:, :2] - t[:, :2].mean(axis=0), axis=1)))
    start = np.mean([c[0, :2] for c in curves.values()], axis=0)
    reach = {v: float(np.max(np.linalg.norm(c[:, :2] - start, axis=1))) for v, c in curves.items()}
    short = [v for v in curves if reach[v] < 0.15 * circum]
    if zoom_mm is None:
        zoom_mm = float(1.4 * max([reach[v] for v in short] or [0.05 * circum]))
    centroid = t[:, :2].mean(axis=0)
    pts = np.vstack([centroid + 1.12 * (t[:, :2] - centroid)] + [c[:, :2] for c in curves.values()])
    box, nx, ny = plot2d.nice_box(pts.min(axis=0) - 0.05 * circum,
                                  pts.max(axis=0) + 0.05 * circum, n=7)
    zb = (start[0] - zoom_mm, start[0] + zoom_mm, start[1] - zoom_mm, start[1] + zoom_mm)

    def draw(pre: str, view, width: float, label_pairs, font: int, off: float, ring: float):
        plot2d.support_2d(pl, t, view, 4 if not pre else 3, pre + "triangle")
        for v, c in curves.items():
            xy = np.column_stack([c[:, :2], np.full(len(c), 0.01 * v)])
            pl.add_lines(xy if len(xy) > 1 else np.vstack([xy, xy]), color=PAIR_COLOURS[v - 1],
                         width=width, connected=True, name=f"{pre}curve #{v}")
        texts = []
        for v in label_pairs:
            c = curves[v][:, :2]
            d = c[-1] - start
            d = d / max(np.linalg.norm(d), 1e-12)
            texts.append(f"#{v}")
            pl.add_point_labels(np.array([[*(c[-1] + off * d), 5.0]]), [texts[-1]],
                                font_size=font, name=f"{pre}label #{v}",
                                **{**LABEL, "text_color": PAIR_COLOURS[v - 1],
                                   "shape_opacity": 0.6})
        for v, q in tips.items():
            pl.add_mesh(plot2d.disc(q[:2], ring, 4.0, inner=0.6 * ring), color="red",
                        name=f"{pre}tip #{v}", lighting=False)
        pl.add_points(np.array([[*start, 3.0]]), color="black", point_size=10 if not pre else 12,
                      render_points_as_spheres=True, name=pre + "start")
        return texts

    labels = draw("", box, 6, [v for v in curves if v not in short], 22, 0.08 * circum,
                  0.022 * circum)
    pl.add_lines(np.array([[zb[0], zb[2], 2], [zb[1], zb[2], 2], [zb[1], zb[3], 2],
                           [zb[0], zb[3], 2], [zb[0], zb[2], 2]]), color="#555555", width=2,
                 connected=True, name="zoom box")
    if corner_labels is not None:
        plot2d.corner_labels(pl, t, corner_labels, 5.0, 24, "corner labels")
    plot2d.axes_2d(pl, box, nx, ny)
    plot2d.camera_2d(pl, 0, box, margins=(0.12, 0.03, 0.1, 0.02))

    pl.subplot(0, 1)
    zoom_margins = (0.02, 0.02, 0.02, 0.1)
    zoom_labels = draw("zoom ", plot2d.view_2d(pl, 1, zb, zoom_margins), 4, list(curves), 16,
                       0.12 * zoom_mm, 0.05 * zoom_mm)
    pl.add_point_labels(np.array([[*(start + [0.0, -0.12 * zoom_mm]), 5.0]]), ["0 MPa"],
                        font_size=13, name="zoom start label", **{**LABEL, "shape_opacity": 0.0})
    pl.add_text(f"zoom: start +-{zoom_mm:.0f} mm", position="upper_edge", font_size=10,
                color="black", name="zoom caption")
    plot2d.camera_2d(pl, 1, zb, zoom_margins)

    pl.subplot(0, 2)
    entries = [[f"#{v}  {reach[v]:.0f} mm", PAIR_COLOURS[v - 1], "-"] for v in curves]
    if tips:
        entries.append(["leaves triangle", "red", "circle"])
    pl.add_legend(entries, bcolor=None, size=(0.62, 0.95), loc="center", name="legend")
    return finish(pl, path, title, cog_paths={v: len(c) for v, c in curves.items()},
                  labels=labels, zoom_labels=zoom_labels, tips=sorted(tips), zoom_mm=zoom_mm,
                  view_mm=tuple(float(v) for v in box))
