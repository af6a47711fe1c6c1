"""The pieces of the interactive page (render.page) as plotly traces, drawn from arrays: the
robot, a support triangle, a pair's CoG cloud and fitted curve (paper Figs. 6-7 in 3D), and a
run's terrain, CoG track, contact faces, start and goal (docs/design.md §7).

Every function returns a list of traces as plain dicts (plotly's figure schema: the page is
written unchecked, plotly's checking of 200 traces took seconds) with the given `scene` ("scene"
or "scene2") and `legend`; lengths are drawn in the unit of the points given.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..physics import topology as topo
from .scene import CABLE_COLOUR, PAIR_COLOURS, STRUT_COLOURS

__all__ = ["robot", "triangle", "pair", "terrain", "track", "marker", "circle", "segments"]

STRUT_WIDTH, CABLE_WIDTH, CURVE_WIDTH = 9, 3, 6  # px


def segments(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Segments from a (n, 3) to b (n, 3) as one polyline (3n, 3), NaN between segments (plotly
    draws a NaN row as a gap)."""
    out = np.full((3 * len(a), 3), np.nan)
    out[0::3], out[1::3] = a, b
    return out


def _xyz(p: np.ndarray) -> dict:
    """x, y, z of points (n, 3) as lists (NaN -> None: a gap), rounded to 1e-7 of their unit (0.1 um
    in m, less in mm): far below a pixel, and the page stays small and byte-identical."""
    p = np.round(np.asarray(p, float), 7)
    return {k: [None if not np.isfinite(v) else float(v) for v in p[:, i]] for i, k in enumerate("xyz")}


def robot(nodes: np.ndarray, *, scene: str, legend: str, name: str = "robot", opacity: float = 1.0) -> list:
    """The robot at nodes (12, 3): 6 struts coloured as in Fig. 1, 24 cables, nodes numbered 1-12."""
    nodes = np.asarray(nodes, float)
    common = dict(scene=scene, legend=legend, legendgroup=name, opacity=opacity, hoverinfo="name")
    out = [
        dict(
            type="scatter3d",
            **_xyz(nodes[[a, b]]),
            mode="lines",
            line=dict(color=STRUT_COLOURS[k], width=STRUT_WIDTH),
            name=f"{name}: strut {a + 1}-{b + 1}",
            showlegend=k == 0,
            **common,
        )
        for k, (a, b) in enumerate(topo.STRUTS)
    ]
    out[0]["name"] = name  # the legend entry of the whole robot
    cables = np.asarray(topo.CABLES)
    out.append(
        dict(
            type="scatter3d",
            **_xyz(segments(nodes[cables[:, 0]], nodes[cables[:, 1]])),
            mode="lines",
            line=dict(color=CABLE_COLOUR, width=CABLE_WIDTH),
            name=f"{name}: cables",
            showlegend=False,
            **common,
        )
    )
    out.append(
        dict(
            type="scatter3d",
            **_xyz(nodes),
            mode="markers+text",
            marker=dict(size=3, color="black"),
            text=[str(i + 1) for i in range(topo.N_NODES)],
            textposition="top center",
            textfont=dict(size=11, color="black"),
            name=f"{name}: nodes",
            showlegend=False,
            **common,
        )
    )
    return out


def triangle(
    tri: np.ndarray, *, scene: str, legend: str, name: str, colour: str, labels: Sequence[int] | None = None
) -> list:
    """A filled triangle (3, 3) with its outline; corners labelled by `labels` (3 node numbers)."""
    tri = np.asarray(tri, float)
    common = dict(scene=scene, legend=legend, legendgroup=name, name=name, hoverinfo="name")
    out = [
        dict(type="mesh3d", **_xyz(tri), i=[0], j=[1], k=[2], color=colour, opacity=0.35, flatshading=True, **common),
        dict(
            type="scatter3d",
            **_xyz(tri[[0, 1, 2, 0]]),
            mode="lines+text" if labels is not None else "lines",
            text=None if labels is None else [f"({n})" for n in labels] + [""],
            textposition="bottom center",
            line=dict(color=colour, width=5),
            showlegend=False,
            **common,
        ),
    ]
    out[0]["showlegend"] = True
    return out


def pair(p: int, cloud: np.ndarray, curve: np.ndarray, nominal: np.ndarray, *, scene: str, legend: str) -> list:
    """Pair #p: its CoG samples cloud (n, 3) (Fig. 6), fitted curve (k, 3) from the unactuated
    CoG (Fig. 7) and nominal CoGs (m, 3), in the pair's colour; one legend entry toggles all."""
    colour = PAIR_COLOURS[p - 1]
    common = dict(scene=scene, legend=legend, legendgroup=f"#{p}", hoverinfo="name")
    return [
        dict(
            type="scatter3d",
            **_xyz(curve),
            mode="lines",
            line=dict(color=colour, width=CURVE_WIDTH),
            name=f"#{p}",
            **common,
        ),
        dict(
            type="scatter3d",
            **_xyz(cloud),
            mode="markers",
            marker=dict(size=1.5, color=colour, opacity=0.5),
            name=f"#{p} CoG samples",
            showlegend=False,
            **common,
        ),
        dict(
            type="scatter3d",
            **_xyz(nominal),
            mode="markers",
            marker=dict(size=4, color=colour, symbol="diamond"),
            name=f"#{p} nominal CoG",
            showlegend=False,
            **common,
        ),
    ]


def terrain(verts: np.ndarray, tris: np.ndarray, *, scene: str, legend: str, relief: bool) -> list:
    """The terrain's triangles (verts (n, 3), tris (m, 3) indices): coloured by height where
    `relief` (a height field), else one sand colour."""
    colour = dict(intensity=np.round(verts[:, 2], 7).tolist(), colorscale="Earth", showscale=False) if relief else {}
    return [
        dict(
            type="mesh3d",
            **_xyz(verts),
            i=tris[:, 0].tolist(),
            j=tris[:, 1].tolist(),
            k=tris[:, 2].tolist(),
            color=None if relief else "#d9d4c7",
            opacity=0.9,
            name="terrain",
            hoverinfo="skip",
            scene=scene,
            legend=legend,
            **colour,
        )
    ]


def track(points: np.ndarray, *, scene: str, legend: str, name: str, colour: str, width: int = 5) -> list:
    """A polyline through points (n, 3) (NaN rows: gaps)."""
    return [
        dict(
            type="scatter3d",
            **_xyz(points),
            mode="lines",
            line=dict(color=colour, width=width),
            name=name,
            scene=scene,
            legend=legend,
        )
    ]


def marker(
    points: np.ndarray, *, scene: str, legend: str, name: str, colour: str, size: int = 7, symbol: str = "circle"
) -> list:
    """Points (3,) or (n, 3) as markers."""
    return [
        dict(
            type="scatter3d",
            **_xyz(np.asarray(points, float).reshape(-1, 3)),
            mode="markers",
            marker=dict(size=size, color=colour, symbol=symbol),
            name=name,
            scene=scene,
            legend=legend,
        )
    ]


def circle(
    centre: np.ndarray,
    radius: float,
    *,
    scene: str,
    legend: str,
    name: str,
    colour: str,
    normal: Sequence[float] = (0, 0, 1),
) -> list:
    """A circle of `radius` about centre (3,) in the plane of the unit `normal` (3,), 64 segments."""
    n = np.asarray(normal, float) / np.linalg.norm(normal)
    u = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    v = np.cross(n, u)
    a = np.linspace(0.0, 2 * np.pi, 65)[:, None]
    pts = np.asarray(centre, float) + radius * (np.cos(a) * u + np.sin(a) * v)
    return [
        dict(
            type="scatter3d",
            **_xyz(pts),
            mode="lines",
            line=dict(color=colour, width=3),
            name=name,
            showlegend=False,
            scene=scene,
            legend=legend,
        )
    ]
