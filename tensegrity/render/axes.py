"""Axes and scale bars of the 2-D plots in a support frame (render.plot2d's views, mm), drawn
with VTK text actors placed in the plane, so that each label's box on the picture is known
after a render (scene.text_boxes) and can be checked: no two tick labels overlap, and a
scale bar says its own length.

A `box` is a view region (xmin, xmax, ymin, ymax) in mm; margins as in plot2d.view_2d.
Text sizes are VTK font sizes (about the cap-to-descender height in px at VTK's 72 dpi).
"""

from __future__ import annotations

import numpy as np
import pyvista as pv

from . import plot2d
from .scene import WINDOW

__all__ = ["axes_2d", "scale_bar", "round_length", "outline_points"]

Box = tuple[float, float, float, float]
Margins = tuple[float, float, float, float]  # left, right, bottom, top: fractions of the viewport
TICK = 6.0  # px: tick marks out of the axes
GAP = 4.0  # px: between a tick and its label


def _mm_per_px(pl: pv.Plotter, k: int, box: Box, margins: Margins) -> tuple[Box, float]:
    """The view of renderer k (plot2d.view_2d) and its scale (mm per px)."""
    view = plot2d.view_2d(pl, k, box, margins)
    _, y0, _, y1 = pl.renderers[k].GetViewport()
    return view, (view[3] - view[2]) / ((y1 - y0) * WINDOW[1])


def _text(pl: pv.Plotter, text: str, xy, name: str, size: int, h: str, v: str, colour="black", angle=0.0) -> pv.Text:
    """A text actor anchored at the plane point xy (2,) mm (justified h, v there)."""
    actor = pv.Text(text)
    coord = actor.GetPositionCoordinate()
    coord.SetCoordinateSystemToWorld()
    coord.SetValue(float(xy[0]), float(xy[1]), 8.0)
    prop = actor.prop
    prop.font_size, prop.color, prop.orientation = size, colour, angle
    prop.justification_horizontal, prop.justification_vertical = h, v
    pl.add_actor(actor, name=name)
    return actor


def axes_2d(pl: pv.Plotter, k: int, box: Box, nx: int, ny: int, margins: Margins, font_size: int = 16) -> list[str]:
    """x and y axes (mm) with nx and ny ticks along the lower and left sides of box, in renderer
    k seen with plot2d.camera_2d(pl, k, box, margins). An x label hangs below its tick by more
    than half a label's height and a y label is centred on its tick, left of it, so the first
    labels of x and y (both at the corner) cannot meet. Returns the names of the tick labels."""
    pl.subplot(0, k)
    _, mm = _mm_per_px(pl, k, box, margins)
    x0, x1, y0, y1 = box
    tick = TICK * mm
    xs, ys = np.linspace(x0, x1, nx), np.linspace(y0, y1, ny)
    segs = [[x0, y0], [x1, y0], [x0, y0], [x0, y1]]
    segs += [p for x in xs for p in ([x, y0], [x, y0 - tick])]
    segs += [p for y in ys for p in ([x0, y], [x0 - tick, y])]
    pl.add_lines(np.column_stack([segs, np.full(len(segs), 7.0)]), color="black", width=1.5, name="axes lines")
    below = (TICK + GAP + 0.35 * font_size) * mm  # the top of an x label below the axis
    names = [f"tick label x {x:+.6g}" for x in xs] + [f"tick label y {y:+.6g}" for y in ys]
    for x, name in zip(xs, names):
        _text(pl, f"{x + 0.0:.0f}", (x, y0 - below), name, font_size, "center", "top")
    for y, name in zip(ys, names[nx:]):
        _text(pl, f"{y + 0.0:.0f}", (x0 - tick - GAP * mm, y), name, font_size, "right", "center")
    _text(
        pl,
        "x (mm)",
        ((x0 + x1) / 2, y0 - below - (1.3 * font_size + GAP) * mm),
        "axis title x",
        font_size,
        "center",
        "top",
    )
    widest = max(len(f"{y + 0.0:.0f}") for y in ys)
    left = x0 - tick - (2 * GAP + 0.62 * font_size * widest + 0.4 * font_size) * mm
    _text(pl, "y (mm)", (left, (y0 + y1) / 2), "axis title y", font_size, "center", "bottom", angle=90.0)
    return names


def round_length(limit: float) -> float:
    """The longest round length (1, 2 or 5 x 10^k) not longer than `limit` > 0."""
    mag = 10 ** np.floor(np.log10(limit))
    return float(max(m * mag for m in (1, 2, 5) if m * mag <= limit * (1 + 1e-12)))


def outline_points(poly: np.ndarray, closed: bool = True, n: int = 24) -> np.ndarray:
    """n points (2,) along each side of the polygon (closed) or polyline poly (k, 2+), as
    (n k, 2) or (n (k - 1) + 1, 2): what a scale bar should keep clear of."""
    p = np.asarray(poly, float)[:, :2]
    q = np.vstack([p, p[:1]]) if closed else p
    t = np.linspace(0.0, 1.0, n, endpoint=False)[:, None]
    out = [q[i] + t * (q[i + 1] - q[i]) for i in range(len(q) - 1)]
    return np.concatenate(out + ([] if closed else [q[-1:]]))


def scale_bar(
    pl: pv.Plotter, k: int, box: Box, margins: Margins, name: str, avoid: np.ndarray | None = None, font_size: int = 14
) -> dict:
    """A scale bar in renderer k seen with plot2d.camera_2d(pl, k, box, margins): a round
    length (about a quarter of the view's width) as a black bar with end ticks, labelled
    "<L> mm" to its left, on a white plate, in whichever lower corner (left, middle, right)
    keeps furthest from the points `avoid` (n, 2) mm. Returns {"length" mm, "start", "end"
    (2,) mm, "plate" (xmin, xmax, ymin, ymax) mm, "mm_per_px" (the view's scale)}."""
    pl.subplot(0, k)
    view, mm = _mm_per_px(pl, k, box, margins)
    L = round_length(0.25 * (view[1] - view[0]))
    text = f"{L:g} mm"
    pad, label_w, h = 6 * mm, (0.62 * font_size * len(text) + 6) * mm, 1.3 * font_size * mm
    width = label_w + L + 2 * pad
    bottom = view[2] + 0.02 * (view[3] - view[2])
    lefts = [
        view[0] + 0.03 * (view[1] - view[0]),
        (view[0] + view[1] - width) / 2,
        view[1] - 0.03 * (view[1] - view[0]) - width,
    ]
    pts = np.zeros((0, 2)) if avoid is None else np.asarray(avoid, float)[:, :2]

    def clearance(left: float) -> float:  # distance of the nearest point to avoid from the plate
        if not len(pts):
            return np.inf
        dx = np.maximum(np.maximum(left - pts[:, 0], pts[:, 0] - (left + width)), 0.0)
        dy = np.maximum(np.maximum(bottom - pts[:, 1], pts[:, 1] - (bottom + h + 2 * pad)), 0.0)
        return float(np.min(np.hypot(dx, dy)))

    left = max(lefts, key=clearance)  # the first of equals: deterministic
    plate = (left, left + width, bottom, bottom + h + 2 * pad)
    quad = np.array(
        [[plate[0], plate[2], 6.0], [plate[1], plate[2], 6.0], [plate[1], plate[3], 6.0], [plate[0], plate[3], 6.0]]
    )
    pl.add_mesh(
        pv.PolyData(quad, faces=[4, 0, 1, 2, 3]), color="white", opacity=0.85, lighting=False, name=name + " plate"
    )
    y = bottom + pad + 0.5 * h
    start, end = np.array([plate[1] - pad - L, y]), np.array([plate[1] - pad, y])
    tick = 0.35 * h
    segs = [
        [*start, 7],
        [*end, 7],
        [start[0], y - tick, 7],
        [start[0], y + tick, 7],
        [end[0], y - tick, 7],
        [end[0], y + tick, 7],
    ]
    pl.add_lines(np.array(segs, float), color="black", width=3, name=name)
    _text(pl, text, (start[0] - pad, y), name + " label", font_size, "right", "center")
    return {"length": L, "start": start, "end": end, "plate": plate, "mm_per_px": mm}
