"""Fig. 7 of the paper: the kinematic workspace of a contact face, in the support frame, in mm,
viewed along -z: every pair's CoG curve, where it leaves its support, and a zoom on the start;
and `at_pressure`, which gives the tipping point and deformed support between pressure levels.

A pure drawing function on numpy arrays (lengths in m): it writes one PNG (scene.WINDOW px) and
returns a dict saying what was drawn, so that tests can check the scene.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from ..physics import topology as topo
from . import axes, plot2d
from .scene import LABEL, PAIR_COLOURS, WINDOW, finish, plotter

__all__ = ["fig_workspace", "at_pressure"]


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


def fig_workspace(
    cog_paths: dict,
    support: np.ndarray,
    path: str | Path,
    title: str,
    tip_points: dict | None = None,
    corner_labels: Sequence[int] | np.ndarray | None = None,
    zoom_mm: float | None = None,
    tip_supports: dict | None = None,
    unit: str = "MPa",
) -> dict:
    """Fig. 7: the kinematic workspace of one contact face, viewed from above (support-frame z
    toward the camera, CoG projected on the support plane, mm): each pair's CoG curve as a
    coloured line labelled "#v" at its far end, the support triangle of the unactuated robot
    with its corners' node numbers (corner_labels), and where a curve leaves its support
    (tip_points) as a red ring. The ring is judged against the pair's DEFORMED support at the
    tipping pressure, not the triangle drawn filled: tip_supports gives it, drawn dashed in the
    pair's colour; the legend says so. A side panel zooms on the curves' common start, where
    the short curves are, with a scale bar; a legend names every pair with its reach.

    cog_paths: {pair: (m, 3) CoG points along its curve, support frame, m, from low to high
    pressure}; support: (3, 3) support triangle in the support frame, m; tip_points:
    {pair: (3,) m or None}; tip_supports: {pair: (3, 3) m or None}, the deformed support at
    the tipping pressure; corner_labels: three node numbers for the support's corners;
    zoom_mm: half-width of the zoom panel, mm (default: from the short curves); unit: of the
    actuation level at the curves' start (MPa, or V for the twisted-string actuator).
    Returns {"path", "size", "title", "actors", "cog_paths" {pair: number of points},
    "labels" (main view), "zoom_labels", "tips" [pairs], "tip_points" {pair: (2,) mm},
    "tip_supports" {pair: (3, 2) mm}, "legend" [entries], "zoom_mm", "view_mm", "scale_bars"
    {name: axes.scale_bar}}.
    """
    curves = {
        topo.check_pair(v): plot2d.check_points(c, f"curve of pair {v}") * 1e3 for v, c in sorted(cog_paths.items())
    }
    if not curves:
        raise ValueError("cog_paths is empty: give at least one pair's CoG path")
    t = plot2d.check_points(support, "support", 3) * 1e3
    tips = {
        topo.check_pair(v): plot2d.check_points(np.reshape(q, (1, 3)), f"tip of pair {v}")[0] * 1e3
        for v, q in (tip_points or {}).items()
        if q is not None
    }
    deformed = {
        topo.check_pair(v): plot2d.check_points(s, f"tip support of pair {v}", 3) * 1e3
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
            c = plot2d.drop_close_points(c, 1.5 * px)
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
        dashes = np.concatenate([plot2d.dashed(s[k, :2], s[(k + 1) % 3, :2], 0.035 * circum) for k in range(3)])
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
    margins = (0.12, 0.03, 0.1, 0.02)
    axes.axes_2d(pl, 0, box, nx, ny, margins)
    plot2d.camera_2d(pl, 0, box, margins)

    pl.subplot(0, 1)
    zoom_margins = (0.02, 0.02, 0.02, 0.1)
    zoom_labels = draw(
        "zoom ", plot2d.view_2d(pl, 1, zb, zoom_margins), 4, list(curves), 16, 0.12 * zoom_mm, 0.05 * zoom_mm
    )
    pl.add_point_labels(
        np.array([[*(start + [0.0, -0.12 * zoom_mm]), 5.0]]),
        [f"0 {unit}"],
        font_size=13,
        name="zoom start label",
        **{**LABEL, "shape_opacity": 0.0},
    )
    pl.add_text(
        f"zoom: start +-{zoom_mm:.0f} mm", position="upper_edge", font_size=10, color="black", name="zoom caption"
    )
    near = [axes.outline_points(c, closed=False, n=8) for c in curves.values()]
    bar = axes.scale_bar(pl, 1, zb, zoom_margins, "zoom scale bar", avoid=np.vstack([start[None], *near]))
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
        scale_bars={"zoom scale bar": bar},
    )
