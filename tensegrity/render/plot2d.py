"""2-D plots in a support frame, drawn with VTK (Figs. 6, 7 and the insets of Figs. 8-10).

The support plane is the x-y plane of the scene, seen along -z with a parallel projection; the
figures draw in mm. Helpers: the view and camera of a renderer, round axis boxes, clipping of
the support triangle to a view, discs and corner labels (axes: render.axes), and the figures' points checked,
dashed and thinned.
A `box` is a view region (xmin, xmax, ymin, ymax) in the figure's length unit.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pyvista as pv
from numpy.typing import ArrayLike

from .scene import LABEL, WINDOW

__all__ = [
    "view_2d",
    "camera_2d",
    "nice_box",
    "clip_polygon",
    "clip_segment",
    "closest_on_segment",
    "segment_distance",
    "support_2d",
    "disc",
    "corner_labels",
    "check_points",
    "dashed",
    "drop_close_points",
]

Box = tuple[float, float, float, float]
_MARGINS = (0.04, 0.04, 0.04, 0.04)


def _aspect(pl: pv.Plotter, k: int) -> float:
    x0, y0, x1, y1 = pl.renderers[k].GetViewport()
    return (x1 - x0) * WINDOW[0] / ((y1 - y0) * WINDOW[1])


def view_2d(pl: pv.Plotter, k: int, box: Box, margins: tuple[float, float, float, float] = _MARGINS) -> Box:
    """The region (xmin, xmax, ymin, ymax) that renderer k shows when `box` fills it less
    margins (left, right, bottom, top, fractions of the viewport), equal scales on x and y."""
    x0, x1, y0, y1 = box
    ml, mr, mb, mt = margins
    aspect = _aspect(pl, k)
    height = max((y1 - y0) / (1 - mb - mt), (x1 - x0) / (1 - ml - mr) / aspect)
    width = height * aspect
    cx = (x0 + x1) / 2 + width * (mr - ml) / 2
    cy = (y0 + y1) / 2 + height * (mt - mb) / 2
    return cx - width / 2, cx + width / 2, cy - height / 2, cy + height / 2


def camera_2d(pl: pv.Plotter, k: int, box: Box, margins: tuple[float, float, float, float] = _MARGINS) -> None:
    """Renderer k looks down -z with a parallel projection at view_2d(pl, k, box, margins)."""
    v = view_2d(pl, k, box, margins)
    cx, cy = (v[0] + v[1]) / 2, (v[2] + v[3]) / 2
    cam = pl.renderers[k].camera
    cam.parallel_projection = True
    cam.focal_point = (cx, cy, 0.0)
    cam.position = (cx, cy, 1e4)
    cam.up = (0.0, 1.0, 0.0)
    cam.parallel_scale = (v[3] - v[2]) / 2
    pl.renderers[k].ResetCameraClippingRange()


def nice_box(lo: ArrayLike, hi: ArrayLike, n: int = 5) -> tuple[Box, int, int]:
    """Extend [lo, hi] (2,) to multiples of a round step (1, 2 or 5 x 10^k) giving about n
    ticks per axis; returns (box, number of ticks x, number of ticks y)."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    span = max(float(np.max(hi - lo)), 1e-9)
    raw = span / (n - 1)
    mag = 10 ** np.floor(np.log10(raw))
    step = mag * min((1, 2, 5, 10), key=lambda m: abs(np.log(m * mag / raw)))
    a, b = np.floor(lo / step) * step, np.ceil(hi / step) * step
    ticks = np.rint((b - a) / step).astype(int) + 1
    return (a[0], b[0], a[1], b[1]), int(ticks[0]), int(ticks[1])


def clip_polygon(poly: np.ndarray, box: Box) -> np.ndarray:
    """Convex polygon (k, 2) clipped to box (Sutherland-Hodgman); (j, 2), j = 0 if outside."""
    out = np.asarray(poly, float)
    for axis, bound, keep_below in ((0, box[0], False), (0, box[1], True), (1, box[2], False), (1, box[3], True)):
        if len(out) == 0:
            break
        inside = (out[:, axis] <= bound) if keep_below else (out[:, axis] >= bound)
        res = []
        for i in range(len(out)):
            p, q = out[i], out[(i + 1) % len(out)]
            ip, iq = inside[i], inside[(i + 1) % len(out)]
            if ip:
                res.append(p)
            if ip != iq:
                t = (bound - p[axis]) / (q[axis] - p[axis])
                res.append(p + t * (q - p))
        out = np.array(res).reshape(-1, 2)
    return out


def clip_segment(a: ArrayLike, b: ArrayLike, box: Box) -> tuple[np.ndarray, np.ndarray] | None:
    """Segment a-b (2,) clipped to box, or None if it misses it (Liang-Barsky)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    d = b - a
    t0, t1 = 0.0, 1.0
    for p, q in ((-d[0], a[0] - box[0]), (d[0], box[1] - a[0]), (-d[1], a[1] - box[2]), (d[1], box[3] - a[1])):
        if p == 0:
            if q < 0:
                return None
            continue
        t = q / p
        if p < 0:
            t0 = max(t0, t)
        else:
            t1 = min(t1, t)
        if t0 > t1:
            return None
    return a + t0 * d, a + t1 * d


def closest_on_segment(q: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The point of segment a-b (2,) nearest to q (2,)."""
    e = b - a
    t = np.clip(np.dot(q - a, e) / np.dot(e, e), 0.0, 1.0)
    return a + t * e


def segment_distance(q: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    """Distance of q (2,) to segment a-b (2,)."""
    return float(np.linalg.norm(q - closest_on_segment(q, a, b)))


def support_2d(
    pl: pv.Plotter,
    support: np.ndarray,
    box: Box,
    width: float,
    name: str,
    fill: str = "#fff6d5",
    edge: str = "#b8860b",
    corner_labels: Sequence[int] | np.ndarray | None = None,
    avoid: np.ndarray | None = None,
) -> int:
    """The support triangle `support` (3, 2+) (x, y of its corners, mm), filled and outlined,
    clipped to box; with corner_labels (three node numbers), each visible edge is named
    ("edge 10-12") on its visible part: at its middle, or with `avoid` (n, 2) (points that
    labels are drawn at, say) at whichever of 15, 50 or 85 % of it is furthest from them.
    Returns the number of edges drawn."""
    poly = clip_polygon(support[:, :2], box)
    if len(poly) >= 3:
        faces = np.hstack([[len(poly)], np.arange(len(poly))])
        pl.add_mesh(
            pv.PolyData(np.column_stack([poly, np.full(len(poly), -3.0)]), faces=faces),
            color=fill,
            lighting=False,
            name=name + " fill",
        )
    n = 0
    for k in range(3):
        seg = clip_segment(support[k, :2], support[(k + 1) % 3, :2], box)
        if seg is not None:
            pl.add_lines(
                np.array([[*seg[0], -2.0], [*seg[1], -2.0]]), color=edge, width=width, name=f"{name} edge {k + 1}"
            )
            n += 1
            if corner_labels is not None:
                a, b = sorted((int(corner_labels[k]), int(corner_labels[(k + 1) % 3])))
                mid = 0.5 * (seg[0] + seg[1])
                if avoid is not None and len(avoid):
                    cand = [seg[0] + f * (seg[1] - seg[0]) for f in (0.5, 0.15, 0.85)]
                    mid = max(cand, key=lambda q: np.min(np.linalg.norm(np.asarray(avoid)[:, :2] - q, axis=1)))
                pl.add_point_labels(
                    np.array([[*mid, 5.0]]),
                    [f"edge {a}-{b}"],
                    font_size=16,
                    name=f"{name} edge label {k + 1}",
                    **{**LABEL, "text_color": edge},
                )
    return n


def disc(centre_xy: Sequence[float] | np.ndarray, radius: float, z: float, inner: float = 0.0) -> pv.PolyData:
    """A flat disc (ring if inner > 0) at centre_xy (2,), height z, facing +z."""
    return pv.Disc(center=(centre_xy[0], centre_xy[1], z), inner=inner, outer=radius, normal=(0, 0, 1), c_res=48)


def corner_labels(
    pl: pv.Plotter, support: np.ndarray, labels: Sequence[int] | np.ndarray, z: float, font_size: int, name: str
) -> None:
    """The node numbers `labels` (3,) just outside the corners of `support` (3, 2+), at z."""
    c = support[:, :2].mean(axis=0)
    out = support[:, :2] - c
    pos = support[:, :2] + 0.1 * np.linalg.norm(out, axis=1).max() * out / np.linalg.norm(out, axis=1, keepdims=True)
    pl.add_point_labels(
        np.column_stack([pos, np.full(3, z)]), [str(s) for s in labels], font_size=font_size, name=name, **LABEL
    )


def check_points(a: ArrayLike, name: str, n: int | None = None) -> np.ndarray:
    """`a` as a finite (k, 3) float array in m, k = n if given; else a ValueError naming it `name`."""
    a = np.asarray(a, float)
    if a.ndim != 2 or a.shape[1] != 3 or (n is not None and len(a) != n) or not np.all(np.isfinite(a)):
        want = f"({n}, 3)" if n is not None else "(n, 3)"
        raise ValueError(f"{name} must be a finite {want} array in m, got shape {a.shape}")
    return a


def dashed(a: np.ndarray, b: np.ndarray, dash: float) -> np.ndarray:
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
