"""Fig. 6 of the paper: the CoG cloud of a pressure sweep, in the support frame, in mm, viewed
along -z, with the nominal CoG of every pressure level.

A pure drawing function on numpy arrays (lengths in m): it writes one PNG (scene.WINDOW px) and
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
from . import axes, plot2d
from .scene import LABEL, WINDOW, finish, plotter

__all__ = ["fig_cog_cloud", "level_colours"]


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
    unit: str = "MPa",
) -> dict:
    """Fig. 6: the CoG during a pressure sweep, projected on the support plane (mm): samples
    as a point cloud coloured by pressure level, nominal CoGs (level averages, paper III.A)
    as circles labelled with their pressure; the main view is zoomed on the cloud with the
    nearest triangle edge, a side panel shows the whole support triangle.

    samples: (T, 3) CoG in the support frame, m; nominal: (n, 3) m; levels: (n,) MPa;
    support: (3, 3) support triangle in the support frame, m (corners in face order);
    sample_pressure: (T,) MPa of each sample (default: n equal consecutive blocks);
    corner_labels: three node numbers for the support's corners; unit: of the levels (MPa, or V
    for the twisted-string actuator's motor voltages).
    Returns {"path", "size", "title", "actors", "samples", "nominal", "labels" (every level;
    the legend), "labelled" (those written beside their marker: the others would overlap),
    "support_edges" (edges in the main view), "view_mm" (xmin, xmax, ymin, ymax), "scale_bars"
    {name: axes.scale_bar} (the context panel's)}.
    """
    pair = topo.check_pair(pair)
    s = plot2d.check_points(samples, "samples") * 1e3
    levels = np.asarray(levels, float).reshape(-1)
    nom = plot2d.check_points(nominal, "nominal", len(levels)) * 1e3
    t = plot2d.check_points(support, "support", 3) * 1e3
    lvl = _sample_levels(len(s), levels, sample_pressure)
    cols = level_colours(len(levels))
    if title is None:
        title = (
            f"Fig. 6  CoG path when #{pair} works, face {face_label}, "
            f"{levels.min():g}-{levels.max():g} {unit} (support frame, top view)"
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

    labels = [f"{p:g} {unit}" for p in levels]
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
    margins = (0.13, 0.04, 0.1, 0.03)
    axes.axes_2d(pl, 0, box, nx, ny, margins)
    plot2d.camera_2d(pl, 0, box, margins)

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
    context = (0.12, 0.12, 0.2, 0.15)  # room below the triangle for the scale bar
    near = np.vstack([axes.outline_points(t), axes.outline_points(frame), s[:: max(1, len(s) // 200), :2]])
    bar = axes.scale_bar(pl, 1, tb, context, "context scale bar", avoid=near)
    plot2d.camera_2d(pl, 1, tb, context)

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
        scale_bars={"context scale bar": bar},
    )
