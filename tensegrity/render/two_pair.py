"""The two-pair workspace figure: where the CoG projection can go with one pair and with two
(issue 10), drawn from arrays in the support frame of one contact face, seen from above (mm)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
from scipy.spatial import ConvexHull

from ..physics.frames import margin_2d
from . import axes, plot2d
from .scene import finish, plotter

ONE, TWO = "#1f77b4", "#ff7f0e"


def _hull(points: np.ndarray) -> np.ndarray:
    """Closed outline (k+1, 2) of the convex hull of 2-D points (n, 2), n >= 3 and not collinear;
    the points themselves otherwise."""
    try:
        h = ConvexHull(points)
    except Exception:  # fewer than 3 points, or all on a line: no area to outline
        return points
    return points[np.r_[h.vertices, h.vertices[:1]]]


def fig_two_pair(
    one: np.ndarray,
    two: np.ndarray,
    support: np.ndarray,
    corner_labels: Sequence[int] | np.ndarray,
    path: str | Path,
    title: str,
) -> dict:
    """CoG projections (x, y) reachable with one pair, `one` (n, 3) m (every swept pair and
    level), and with two pairs, `two` (m, 3) m (every combination and grid point), as points
    and convex hulls, over the unactuated support triangle `support` (3, 3) m with its corners'
    node numbers and edges named. Returns what was drawn ({"path", "title", "actors", "hull_one",
    "hull_two" (outline points, mm), "n_one", "n_two", "outside_two" (two-pair points outside
    the drawn triangle)})."""
    one, two, tri = (np.asarray(a, float)[:, :2] * 1e3 for a in (one, two, support))
    if not len(one) or not len(two):
        raise ValueError(f"nothing to draw: {len(one)} one-pair and {len(two)} two-pair points")
    pl = plotter(title)
    c = tri.mean(axis=0)
    pts = np.vstack([c + 1.15 * (tri - c), one, two])
    box, nx, ny = plot2d.nice_box(pts.min(axis=0), pts.max(axis=0), n=7)
    plot2d.support_2d(pl, tri, box, 4, "triangle", corner_labels=corner_labels)
    plot2d.corner_labels(pl, tri, corner_labels, 6.0, 22, "corners")
    hulls = {}
    for name, p, col, z, size in (("two", two, TWO, 1.0, 6), ("one", one, ONE, 2.0, 9)):
        pl.add_points(
            np.column_stack([p, np.full(len(p), z)]),
            color=col,
            point_size=size,
            render_points_as_spheres=True,
            name=f"points {name}",
        )
        h = hulls[name] = _hull(p)
        if len(h) > 1:
            pl.add_lines(
                np.column_stack([h, np.full(len(h), z)]), color=col, width=4, connected=True, name=f"hull {name}"
            )
    pl.add_points(np.array([[*c, 3.0]]), color="black", point_size=12, render_points_as_spheres=True, name="centroid")
    for k, (text, col) in enumerate(
        (
            ("blue: one pair (every pair and level)", ONE),
            ("orange: two pairs (every combination and grid point)", TWO),
            ("black: centroid; filled triangle: the unactuated support face; lines: convex hulls", "black"),
        )
    ):
        pl.add_text(text, position=(20, 70 - 28 * k), font_size=11, color=col, name=f"key {k}")
    margins = (0.1, 0.04, 0.16, 0.14)
    axes.axes_2d(pl, 0, box, nx, ny, margins)
    plot2d.camera_2d(pl, 0, box, margins)
    outside = int(np.sum(margin_2d(two, np.broadcast_to(tri, (len(two), 3, 2))) < 0))
    return finish(
        pl,
        path,
        title,
        hull_one=hulls["one"],
        hull_two=hulls["two"],
        n_one=len(one),
        n_two=len(two),
        outside_two=outside,
    )
