"""The terrain under a robot or a run (docs/design.md §7): its triangles near a point as a
mesh, and that mesh drawn, a height field coloured by height with its grid and a colour bar,
or plain sand. Lengths in m, world frame.
"""

from __future__ import annotations

import numpy as np
import pyvista as pv
from numpy.typing import ArrayLike

from ..physics.terrain import Terrain

__all__ = ["terrain_mesh", "add_terrain"]


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
