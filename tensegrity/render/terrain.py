"""The terrain under a robot or a run (docs/design.md §7): its triangles near a point as a
mesh, and that mesh drawn, a height field coloured by height with its grid and a colour bar,
or plain sand. Lengths in m, world frame.
"""

from __future__ import annotations

import numpy as np
import pyvista as pv
from numpy.typing import ArrayLike

from ..physics.terrain import Terrain

__all__ = ["terrain_mesh", "add_terrain", "extent_in_view"]


def terrain_mesh(terrain: Terrain, centre: ArrayLike, extent: float) -> pv.PolyData:
    """The terrain's triangles within `extent` m of `centre` (2,) m, world (a height field is
    cut to that square), with the point data "height (m)"."""
    verts, tris = terrain.triangles(extent=extent, centre=centre)
    mesh = pv.PolyData(verts, faces=np.hstack([np.full((len(tris), 1), 3), tris]).ravel())
    mesh["height (m)"] = verts[:, 2]
    if terrain.kind == "heightfield":
        c = np.asarray(centre, float)
        lo, hi = verts[:, 2].min() - 1.0, verts[:, 2].max() + 1.0
        cut = mesh.clip_box(
            (c[0] - extent, c[0] + extent, c[1] - extent, c[1] + extent, lo, hi), invert=False
        ).extract_surface(algorithm="dataset_surface")
        if cut.n_points:
            mesh = cut
    return mesh


def add_terrain(pl: pv.Plotter, terrain: Terrain, centre: ArrayLike, extent: float, coloured: bool) -> None:
    """Draw terrain_mesh(terrain, centre, extent) (actor "terrain"): a height field coloured by
    height with its grid and a colour bar if `coloured`, else one sand colour."""
    mesh = terrain_mesh(terrain, centre, extent)
    if coloured and terrain.kind == "heightfield":
        pl.add_mesh(
            mesh,
            scalars="height (m)",
            cmap="gist_earth",
            opacity=1.0,
            name="terrain",
            scalar_bar_args={
                "title": "terrain height (m)",
                "color": "black",
                "vertical": True,
                "position_x": 0.88,
                "position_y": 0.2,
                "title_font_size": 16,
                "label_font_size": 14,
                "fmt": "%.2f",
            },
        )
        pl.add_mesh(mesh.extract_all_edges(), color="#5a5a5a", opacity=0.35, name="terrain grid")
    else:
        pl.add_mesh(mesh, color="#d9d4c7", opacity=0.9, name="terrain")


def extent_in_view(pl: pv.Plotter, terrain: Terrain, centre: ArrayLike, extent: float, margin: float = 0.03) -> float:
    """The largest half-width (m), at most `extent`, of the square of terrain around `centre`
    (2,) m whose edges the active renderer's camera (set it first) shows inside its viewport,
    `margin` (a fraction of the half-size) clear of its sides: the ground then ends inside the
    picture, not where a side panel cuts it. Edges checked at 16 points a side (a height field
    may bulge between them by less than a cell's relief). Bisection to 0.1 % of `extent`."""
    r = pl.renderer
    m = r.GetActiveCamera().GetCompositeProjectionTransformMatrix(r.GetTiledAspectRatio(), -1, 1)
    proj = np.array([[m.GetElement(i, j) for j in range(4)] for i in range(4)])
    t = np.linspace(-1.0, 1.0, 17)[:-1]
    ring = np.concatenate([np.column_stack([t, -np.ones(16)]), np.column_stack([np.ones(16), t])])
    ring = np.concatenate([ring, -ring])  # the square's boundary, half-width 1
    c = np.asarray(centre, float)

    def inside(s: float) -> bool:
        xy = c + s * ring
        h = np.column_stack([xy, terrain.height(xy[:, 0], xy[:, 1]), np.ones(len(xy))]) @ proj.T
        return bool((h[:, 3] > 0).all() and np.abs(h[:, :2] / h[:, 3:]).max() <= 1.0 - margin)

    lo, hi = 0.0, float(extent)
    if inside(hi):
        return hi
    while hi - lo > 1e-3 * extent:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if inside(mid) else (lo, mid)
    return lo
