"""Figs. 6 and 7 of the paper: plots in a face's support frame, in mm, viewed along -z: the
CoG cloud of a sweep (Fig. 6) and the kinematic workspace of a face (Fig. 7).

Pure drawing functions on numpy arrays (lengths in m): each writes one PNG (scene.WINDOW px) and
returns a dict saying what was drawn, so that tests can check the scene.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pyvista as pv
from matplotlib import colormaps  # a PyVista dependency
from numpy.typing import ArrayLike

from ..physics import topology as topo
from . import plot2d
from .scene import LABEL, PAIR_COLOURS, WINDOW, finish, plotter

__all__ = ["fig_cog_cloud", "fig_workspace", "level_colours", "at_pressure"]


# --- Fig. 6 and 7: support-frame plots (mm, viewed along -z) ---------------------------------


def at_pressure(levels: ArrayLike, values: ArrayLike, pressure: float) -> np.ndarray:
    """values (P, ...) given at the pressure levels (P,) MPa, linearly interpolated at
    `pressure` MPa from the levels where they are finite (NaN: e.g. after a grounded robot
    rolled off its face); held constant outside those levels. NaN if no level is finite."""
    levels, values = np.asarray(levels, float), np.asarray(values, float)
    ok = np.isfinite(values.reshape(len(levels), -1)).all(axis=1)
    if not ok.any():
        return np.full(values.shape[1:], np.nan)
    flat = values[ok].reshape(int(ok.sum()), -1)
    out = [np.interp(pressure, levels[ok], flat[:, j]) for j in range(flat.shape[1])]
    return np.array(out).reshape(values.shape[1:])


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
    if a.ndim != 2 or a.shape[1] != 3 or (n is not None and len(a) != n) or not np.all(np.isfinite(a)):
        want = f"({n}, 3)" if n is not None else "(n, 3)"
        raise ValueError(f"{name} must be a finite {want} array in m, got shape {a.shape}")
    return a


def fig_cog_cloud(
    samples: np.ndarray,
    nominal: np.ndarray,
    levels: ArrayLike,
    support: np.ndarray,
    path: str | Path,
    pair: int,
    face_label: str,
    sample_pressure: ArrayLike | None = None,
    corner_labels: Sequence[int] | np.ndarray | None = None,
    title: str | None = None,
) -> dict:
    """Fig. 6: the CoG during a pressure sweep, projected on the support plane (mm): samples
    as a point cloud coloured by pressure level, nominal CoGs (level averages, paper III.A)
    as circles labelled with their pressure; the main view is zoomed on the cloud with the
    nearest triangle edge, a side panel shows the whole support triangle.

    samples: (T, 3) CoG in the support frame, m; nominal: (n, 3) m; levels: (n,) MPa;
    support: (3, 3) support triangle in the support frame, m (corners in face order);
    sample_pressure: (T,) MPa of each sample (default: n equal consecutive blocks);
    corner_labels: three node numbers for the support's corners.
    Returns {"path", "size", "title", "actors", "samples", "nominal", "labels" (every level;
    the legend), "labelled" (those written beside their marker: the others would overlap),
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
        title = (
            f"Fig. 6  CoG path when #{pair} works, face {face_label}, "
            f"{levels.min():g}-{levels.max():g} MPa (support frame, top view)"
        )
    pl = plotter(title, panels=3)

    # Main view: the cloud, the nominal CoGs, the frame origin and the nearest edge's stretch.
    pts = np.vstack([s[:, :2], nom[:, :2], [[0.0, 0.0]]])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    span = max(hi - lo)
    edges = [(t[k, :2], t[(k + 1) % 3, :2]) for k in range(3)]
    some = pts[:: max(1, len(pts) // 400)]
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

    labels = [f"{p:g} MPa" for p in levels]
    direction = nom[-1, :2] - nom[0, :2]
    side = np.array([-direction[1], direction[0]]) / max(np.linalg.norm(direction), 1e-12)
    label_xy = nom[:, :2] + 3.2 * r * side
    # label a level only if its label is clear of the last one labelled (about 26 px x 80 px)
    mm_px = (box[1] - box[0]) / (0.7 * WINDOW[0] * (1 - 0.13 - 0.04))
    shown = [0]
    for k in range(1, len(levels)):
        dx, dy = np.abs(label_xy[k] - label_xy[shown[-1]]) / mm_px
        if dx > 80 or dy > 26:
            shown.append(k)
    if shown[-1] != len(levels) - 1:  # the highest level is always labelled
        shown[-1] = len(levels) - 1
    n_edges = plot2d.support_2d(
        pl,
        t,
        box,
        5,
        "triangle",
        corner_labels=corner_labels,
        avoid=np.vstack([label_xy[shown], s[:: max(1, len(s) // 200), :2]]),
    )
    cloud = pv.PolyData(np.column_stack([s[:, :2], np.zeros(len(s))]))
    cloud["rgb"] = (cols[lvl] * 255).astype(np.uint8)
    pl.add_mesh(cloud, scalars="rgb", rgb=True, point_size=4, render_points_as_spheres=True, name="cog samples")
    for k in range(len(levels)):
        pl.add_mesh(plot2d.disc(nom[k], r, 2.0), color=cols[k], name=f"nominal {k}", lighting=False)
        pl.add_mesh(
            plot2d.disc(nom[k], r, 2.5, inner=0.72 * r), color="black", name=f"nominal ring {k}", lighting=False
        )
    pl.add_point_labels(
        np.column_stack([label_xy[shown], np.full(len(shown), 4.0)]),
        [labels[k] for k in shown],
        font_size=18,
        name="nominal labels",
        **LABEL,
    )
    pl.add_points(
        np.array([[0.0, 0.0, 1.0]]), color="black", point_size=10, render_points_as_spheres=True, name="origin"
    )
    pl.add_point_labels(
        np.array([[0.0, 0.0, 4.0]]) + [r, -r, 0],
        ["centroid"],
        font_size=16,
        name="origin label",
        **{**LABEL, "shape_opacity": 0.0},
    )
    if corner_labels is not None:
        plot2d.corner_labels(pl, t, corner_labels, 4.0, 18, "corner labels")
    plot2d.axes_2d(pl, box, nx, ny)
    plot2d.camera_2d(pl, 0, box, margins=(0.13, 0.04, 0.1, 0.03))

    # Context panel: the whole triangle, the cloud and a box around the main view.
    pl.subplot(0, 1)
    tb = (t[:, 0].min(), t[:, 0].max(), t[:, 1].min(), t[:, 1].max())
    plot2d.support_2d(pl, t, tb, 3, "context triangle")
    pl.add_mesh(cloud.copy(), scalars="rgb", rgb=True, point_size=2, name="context samples")
    frame = np.array(
        [[box[0], box[2], 1], [box[1], box[2], 1], [box[1], box[3], 1], [box[0], box[3], 1], [box[0], box[2], 1]]
    )
    pl.add_lines(frame, color="black", width=2, connected=True, name="context view box")
    if corner_labels is not None:
        plot2d.corner_labels(pl, t, corner_labels, 4.0, 14, "context corner labels")
    pl.add_text("whole support triangle", position="upper_edge", font_size=10, color="black", name="context caption")
    plot2d.camera_2d(pl, 1, tb, margins=(0.12, 0.12, 0.1, 0.15))

    # Legend panel: the pressure levels.
    pl.subplot(0, 2)
    pl.add_legend(
        [[lab, tuple(c), "circle"] for lab, c in zip(labels, cols)],
        bcolor=None,
        size=(0.5, 0.6),
        loc="center",
        name="legend",
    )
    return finish(
        pl,
        path,
        title,
        samples=len(s),
        nominal=len(nom),
        labels=labels,
        labelled=[labels[k] for k in shown],
        support_edges=n_edges,
        view_mm=tuple(float(v) for v in box),
    )


def _dashed(a: np.ndarray, b: np.ndarray, dash: float) -> np.ndarray:
    """Dashes (k, 2, 2) along segment a-b (2,): `dash` long, separated by gaps as long."""
    n = max(1, int(np.linalg.norm(b - a) / (2 * dash)))
    t = np.linspace(0.0, 1.0, 2 * n + 1)
    return np.stack([a + t[:-1:2, None] * (b - a), a + t[1::2, None] * (b - a)], axis=1)


def drop_close_points(c: np.ndarray, step: float) -> np.ndarray:
    """The points (m, 2+) of a curve, without those closer than `step` to the last kept one
    (the end is always kept): wide VTK lines of sub-pixel segments draw stripes."""
    keep = [0]
    for i in range(1, len(c)):
        if np.linalg.norm(c[i, :2] - c[keep[-1], :2]) >= step:
            keep.append(i)
    if keep[-1] != len(c) - 1:
        if len(keep) > 1 and np.linalg.norm(c[-1, :2] - c[keep[-1], :2]) < step:
            keep[-1] = len(c) - 1
        else:
            keep.append(len(c) - 1)
    return c[keep]


def fig_workspace(
    cog_paths: dict,
    support: np.ndarray,
    path: str | Path,
    title: str,
    tip_points: dict | None = None,
    corner_labels: Sequence[int] | np.ndarray | None = None,
    zoom_mm: float | None = None,
    tip_supports: dict | None = None,
) -> dict:
    """Fig. 7: the kinematic workspace of one contact face, viewed from above (support-frame z
    toward the camera, CoG projected on the support plane, mm): each pair's CoG curve as a
    coloured line labelled "#v" at its far end, the support triangle of the unactuated robot
    with its corners' node numbers (corner_labels), and where a curve leaves its support
    (tip_points) as a red ring. The ring is judged against the pair's DEFORMED support at the
    tipping pressure, not the triangle drawn filled: tip_supports gives it, drawn dashed in the
    pair's colour; the legend says so. A side panel zooms on the curves' common start, where
    the short curves are; a legend names every pair with its reach.

    cog_paths: {pair: (m, 3) CoG points along its curve, support frame, m, from low to high
    pressure}; support: (3, 3) support triangle in the support frame, m; tip_points:
    {pair: (3,) m or None}; tip_supports: {pair: (3, 3) m or None}, the deformed support at
    the tipping pressure; corner_labels: three node numbers for the support's corners;
    zoom_mm: half-width of the zoom panel, mm (default: from the short curves).
    Returns {"path", "size", "title", "actors", "cog_paths" {pair: number of points},
    "labels" (main view), "zoom_labels", "tips" [pairs], "tip_points" {pair: (2,) mm},
    "tip_supports" {pair: (3, 2) mm}, "legend" [entries], "zoom_mm", "view_mm"}.
    """
    curves = {topo.check_pair(v): _check_points(c, f"curve of pair {v}") * 1e3 for v, c in sorted(cog_paths.items())}
    if not curves:
        raise ValueError("cog_paths is empty: give at least one pair's CoG path")
    t = _check_points(support, "support", 3) * 1e3
    tips = {
        topo.check_pair(v): _check_points(np.reshape(q, (1, 3)), f"tip of pair {v}")[0] * 1e3
        for v, q in (tip_points or {}).items()
        if q is not None
    }
    deformed = {
        topo.check_pair(v): _check_points(s, f"tip support of pair {v}", 3) * 1e3
        for v, s in (tip_supports or {}).items()
        if s is not None
    }
    pl = plotter(title, panels=3)
    circum = float(np.max(np.linalg.norm(t[:, :2] - t[:, :2].mean(axis=0), axis=1)))
    start = np.mean([c[0, :2] for c in curves.values()], axis=0)
    reach = {v: float(np.max(np.linalg.norm(c[:, :2] - start, axis=1))) for v, c in curves.items()}
    short = [v for v in curves if reach[v] < 0.15 * circum]
    if zoom_mm is None:
        zoom_mm = float(1.4 * max([reach[v] for v in short] or [0.05 * circum]))
    centroid = t[:, :2].mean(axis=0)
    pts = np.vstack(
        [centroid + 1.12 * (t[:, :2] - centroid)]
        + [c[:, :2] for c in curves.values()]
        + [s[:, :2] for s in deformed.values()]
    )
    box, nx, ny = plot2d.nice_box(pts.min(axis=0) - 0.05 * circum, pts.max(axis=0) + 0.05 * circum, n=7)
    zb = (start[0] - zoom_mm, start[0] + zoom_mm, start[1] - zoom_mm, start[1] + zoom_mm)

    def draw(pre: str, view, width: float, label_pairs, font: int, off: float, ring: float):
        plot2d.support_2d(pl, t, view, 4 if not pre else 3, pre + "triangle")
        px = (view[1] - view[0]) / (0.7 * WINDOW[0] if not pre else 0.3 * WINDOW[0])  # mm/px
        for v, c in curves.items():
            c = drop_close_points(c, 1.5 * px)
            xy = np.column_stack([c[:, :2], np.full(len(c), 0.01 * v)])
            pl.add_lines(
                xy if len(xy) > 1 else np.vstack([xy, xy]),
                color=PAIR_COLOURS[v - 1],
                width=width,
                connected=True,
                name=f"{pre}curve #{v}",
            )
        texts = []
        for v in label_pairs:
            c = curves[v][:, :2]
            d = c[-1] - start
            d = d / max(np.linalg.norm(d), 1e-12)
            texts.append(f"#{v}")
            pl.add_point_labels(
                np.array([[*(c[-1] + off * d), 5.0]]),
                [texts[-1]],
                font_size=font,
                name=f"{pre}label #{v}",
                **{**LABEL, "text_color": PAIR_COLOURS[v - 1], "shape_opacity": 0.6},
            )
        for v, q in tips.items():
            pl.add_mesh(
                plot2d.disc(q[:2], ring, 4.0, inner=0.6 * ring), color="red", name=f"{pre}tip #{v}", lighting=False
            )
        pl.add_points(
            np.array([[*start, 3.0]]),
            color="black",
            point_size=10 if not pre else 12,
            render_points_as_spheres=True,
            name=pre + "start",
        )
        return texts

    labels = draw("", box, 6, [v for v in curves if v not in short], 22, 0.08 * circum, 0.022 * circum)
    for v, s in deformed.items():  # what each ring is judged against
        dashes = np.concatenate([_dashed(s[k, :2], s[(k + 1) % 3, :2], 0.035 * circum) for k in range(3)])
        seg = np.concatenate([dashes, np.full((len(dashes), 2, 1), -1.0 + 0.01 * v)], axis=2)
        pl.add_lines(seg.reshape(-1, 3), color=PAIR_COLOURS[v - 1], width=2.5, name=f"tip support #{v}")
    pl.add_lines(
        np.array([[zb[0], zb[2], 2], [zb[1], zb[2], 2], [zb[1], zb[3], 2], [zb[0], zb[3], 2], [zb[0], zb[2], 2]]),
        color="#555555",
        width=2,
        connected=True,
        name="zoom box",
    )
    if corner_labels is not None:
        plot2d.corner_labels(pl, t, corner_labels, 5.0, 24, "corner labels")
    plot2d.axes_2d(pl, box, nx, ny)
    plot2d.camera_2d(pl, 0, box, margins=(0.12, 0.03, 0.1, 0.02))

    pl.subplot(0, 1)
    zoom_margins = (0.02, 0.02, 0.02, 0.1)
    zoom_labels = draw(
        "zoom ", plot2d.view_2d(pl, 1, zb, zoom_margins), 4, list(curves), 16, 0.12 * zoom_mm, 0.05 * zoom_mm
    )
    pl.add_point_labels(
        np.array([[*(start + [0.0, -0.12 * zoom_mm]), 5.0]]),
        ["0 MPa"],
        font_size=13,
        name="zoom start label",
        **{**LABEL, "shape_opacity": 0.0},
    )
    pl.add_text(
        f"zoom: start +-{zoom_mm:.0f} mm", position="upper_edge", font_size=10, color="black", name="zoom caption"
    )
    plot2d.camera_2d(pl, 1, zb, zoom_margins)

    pl.subplot(0, 2)
    entries = [[f"#{v}  {reach[v]:.0f} mm", PAIR_COLOURS[v - 1], "-"] for v in curves]
    if tips:
        entries.append(["CoG leaves dashed triangle" if deformed else "leaves triangle", "red", "circle"])
    if deformed:
        entries.append(["- - deformed, at tipping", "#555555", None])
    # at most ~27 px a line: the panel is 0.45 of the window high
    height = min(0.97, len(entries) * 27 / (0.45 * WINDOW[1]))
    pl.add_legend(entries, bcolor=None, size=(0.95, height), loc="center", name="legend")
    return finish(
        pl,
        path,
        title,
        cog_paths={v: len(c) for v, c in curves.items()},
        labels=labels,
        zoom_labels=zoom_labels,
        tips=sorted(tips),
        tip_points={v: q[:2] for v, q in tips.items()},
        tip_supports={v: s[:, :2] for v, s in deformed.items()},
        legend=[e[0] for e in entries],
        zoom_mm=zoom_mm,
        view_mm=tuple(float(v) for v in box),
    )
