"""Shared VTK plumbing of every figure (docs/design.md §7): the off-screen plotter, colours,
label style, tubes, struts, node numbers, the robot camera, a camera that fits given points
and the PNG writer.

Every figure is drawn off-screen: white background, a title, a fixed camera, WINDOW pixels.
Node, pair and face numbers shown are 1-based as in the paper; lengths are taken in m.

Off-screen rendering needs no X display. Without DISPLAY (or WAYLAND_DISPLAY) `offscreen()`
tells the VTK wheel to use its EGL window (Mesa's llvmpipe software renderer through libEGL;
Debian packages libegl1, libegl-mesa0 and libgl1-mesa-dri). It sets the environment variable
VTK_DEFAULT_OPENGL_WINDOW, which VTK reads when it creates a render window, so it is called by
`plotter()` just before the first window exists, not when the module is imported: importing
tensegrity.render changes no process-wide setting. Callers set nothing.
"""

from __future__ import annotations

import functools
import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pyvista as pv
from vtkmodules.vtkRenderingCore import vtkTextActor

from ..physics import topology as topo
from .files import atomic

__all__ = [
    "WINDOW",
    "STRUT_COLOURS",
    "CABLE_COLOUR",
    "PAIR_COLOURS",
    "AXIS_COLOURS",
    "LABEL",
    "offscreen",
    "plotter",
    "finish",
    "text_boxes",
    "tube",
    "lines",
    "strut_length",
    "struts",
    "robot",
    "node_labels",
    "robot_camera",
    "fit_camera",
]

WINDOW = (1200, 900)  # px
STRUT_COLOURS = ["#1f77b4", "#2ca02c", "#d62728", "#9467bd", "#ff7f0e", "#17becf"]
CABLE_COLOUR = "#8b4513"  # brown, as in the paper's Fig. 1
# One colour per pair #1..#12; the strongest contrasts go to the pairs that move the CoG most
# (#9, #10, #12, then #4, #6, #7 on the equilateral face; #5, #11 on the isosceles one).
PAIR_COLOURS = [
    "#42d4f4",
    "#9a6324",
    "#808000",
    "#f58231",
    "#000075",
    "#911eb4",
    "#f032e6",
    "#469990",
    "#e6194b",
    "#4363d8",
    "#d4a000",
    "#3cb44b",
]
AXIS_COLOURS = {"x": "#d62728", "y": "#2ca02c", "z": "#1f4fd6"}
# Style of every text label drawn at a point (pass as **LABEL to add_point_labels).
LABEL = dict(
    bold=True,
    text_color="black",
    shape_color="white",
    shape_opacity=0.75,
    show_points=False,
    always_visible=True,
    margin=2,
)
# Canonical view of the robot in its reference pose (direction from the centre to the camera,
# and the up vector): the direction that keeps the 12 projected nodes furthest apart.
_ROBOT_VIEW = (np.array([-0.441, -0.148, 0.885]), np.array([0.0, 1.0, 0.0]))


@functools.cache
def offscreen() -> None:
    """Once per process: without a display, make VTK open its EGL window directly (else it
    first tries X, warns "bad X server connection", then falls back to EGL)."""
    if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")


def plotter(title: str | None, panels: int = 1, size: tuple[int, int] = WINDOW) -> pv.Plotter:
    """A white off-screen plotter of `size` px with `title` on top (None: no title).

    panels = 3 gives a main view on the left (renderer 0), two side panels on the right
    (1: top, with a border; 2: bottom) and a title strip (3); renderer 0 is left active.
    """
    offscreen()
    pl = pv.Plotter(off_screen=True, window_size=size, shape=(1, 4 if panels == 3 else 1), border=False)
    # Edges smoothed by FXAA, a filter of the finished image, not by multisampling: MSAA x4 cost
    # 0.17 s a figure in software (llvmpipe), FXAA 0.04 s, and they look alike (compared side by
    # side). Set on the renderers: PyVista's enable_anti_aliasing("fxaa") turns to SSAA under EGL.
    pl.ren_win.SetMultiSamples(0)
    for r in pl.renderers:
        r.UseFXAAOn()
    pl.set_background("white")
    if panels == 3:
        ports = [(0.0, 0.0, 0.7, 0.93), (0.7, 0.45, 1.0, 0.93), (0.7, 0.0, 1.0, 0.45), (0.0, 0.93, 1.0, 1.0)]
        for r, port in zip(pl.renderers, ports):
            r.SetViewport(*port)
            r.set_background("white")
        pl.renderers[1].add_border(color="black", width=2)
        pl.subplot(0, 3)
        pl.add_text(title, position="upper_edge", font_size=13, color="black", name="title")
    elif title is not None:
        pl.add_title(title, font_size=13, color="black")
    pl.subplot(0, 0)
    return pl


def finish(pl: pv.Plotter, path: str | Path, title: str, **what: Any) -> dict:
    """Write the PNG `path` (folders made), close the plotter and return what was drawn:
    {"path", "size" (px), "title", "actors" (sorted actor names), "text_boxes" (text_boxes
    of the picture written), **what}. The PNG is written
    to a temporary file in the same folder and renamed, so that a process killed while writing
    leaves no partial file at `path`."""
    # PyVista names a point-label actor "<name>-labels"; report the name we gave it
    names = sorted(name.removesuffix("-labels") for r in pl.renderers for name in r.actors)
    try:
        with atomic(path) as tmp:
            pl.screenshot(str(tmp))
        boxes = text_boxes(pl)
    finally:
        pl.close()
    return {"path": str(path), "size": WINDOW, "title": title, "actors": names, "text_boxes": boxes, **what}


def text_boxes(pl: pv.Plotter) -> dict[str, tuple[float, float, float, float]]:
    """{name: (xmin, xmax, ymin, ymax)} in px from the picture's lower left corner, of every
    text actor (vtkTextActor: axis labels, scale bar labels, placed captions) of the last
    render; corner annotations and point labels are not text actors and are left out."""
    out = {}
    for r in pl.renderers:
        for name, actor in r.actors.items():
            if isinstance(actor, vtkTextActor):
                box = np.zeros(4)
                actor.GetBoundingBox(r, box)  # about the actor's anchor, which is added here
                x, y = actor.GetPositionCoordinate().GetComputedDisplayValue(r)
                out[name] = (box[0] + x, box[1] + x, box[2] + y, box[3] + y)
    return out


def tube(a: np.ndarray, b: np.ndarray, radius: float) -> pv.PolyData:
    """A capped tube of `radius` m from point a (3,) m to point b (3,) m."""
    return pv.Line(a, b).tube(radius=radius, n_sides=24, capping=True)


def lines(points: np.ndarray, segments: np.ndarray) -> pv.PolyData:
    """One PolyData of straight segments (k, 2) (0-based row indices) between rows of
    points (n, 3) m."""
    mesh = pv.PolyData(np.asarray(points, float))
    mesh.lines = np.hstack([np.full((len(segments), 1), 2), segments]).ravel()
    return mesh


def strut_length(nodes: np.ndarray) -> float:
    """Mean strut length (m) of node positions (12, 3) m: the scale of every figure."""
    return float(np.mean(np.linalg.norm(nodes[topo.STRUTS[:, 0]] - nodes[topo.STRUTS[:, 1]], axis=1)))


def struts(pl: pv.Plotter, nodes: np.ndarray, colours: Sequence[str], opacity: float = 1.0, prefix: str = "") -> int:
    """The six struts of nodes (12, 3) m as tubes of radius S/50, one colour each (colours:
    six colours); actors "<prefix>strut a-b". Returns the number drawn."""
    S = strut_length(nodes)
    for k, (a, b) in enumerate(topo.STRUTS):
        pl.add_mesh(
            tube(nodes[a], nodes[b], 0.02 * S),
            color=colours[k],
            opacity=opacity,
            smooth_shading=True,
            name=f"{prefix}strut {a + 1}-{b + 1}",
        )
    return len(topo.STRUTS)


def robot(pl: pv.Plotter, nodes: np.ndarray, opacity: float = 1.0, name: str = "robot") -> None:
    """The robot of nodes (12, 3) m as in Fig. 1, without numbers: struts one colour each
    (actors "<name> strut a-b") and the 24 cables as thin brown tubes ("<name> cables")."""
    struts(pl, nodes, STRUT_COLOURS, opacity, prefix=f"{name} ")
    pl.add_mesh(
        lines(nodes, topo.CABLES).tube(radius=0.0045 * strut_length(nodes), n_sides=10),
        color=CABLE_COLOUR,
        opacity=opacity,
        name=f"{name} cables",
    )


def robot_camera(pl: pv.Plotter, nodes: np.ndarray, zoom: float = 1.0) -> None:
    """The canonical view of the robot (nodes (12, 3) m) carried along with its pose, so that
    Fig. 1 looks the same whatever the robot's position and orientation."""
    from scipy.spatial.transform import Rotation  # 0.4 s to import: only the robot figures

    c = nodes.mean(axis=0)
    S = strut_length(nodes)
    rot, _ = Rotation.align_vectors(nodes - c, topo.reference_nodes(S))
    d, up = rot.apply(_ROBOT_VIEW[0]), rot.apply(_ROBOT_VIEW[1])
    cam = pl.camera
    c = c + 0.05 * S * up  # leave room for the title
    cam.focal_point = c
    cam.position = c + 3.2 * S / zoom * d
    cam.up = up
    cam.view_angle = 30.0
    pl.renderer.ResetCameraClippingRange()


def fit_camera(pl: pv.Plotter, points: np.ndarray, top: float = 0.86, right: float = 0.95) -> None:
    """Keep the camera's direction and view angle, and move it so that every row of points
    (n, 3) m is in the picture: within 95 % of the half-width and half-height, below `top`
    of the half-height (the title is above) and left of `right` of the half-width (a colour
    bar may be to the right). Perspective, found by bisection."""
    cam = pl.camera
    pos, focal = np.asarray(cam.position, float), np.asarray(cam.focal_point, float)
    d = (pos - focal) / np.linalg.norm(pos - focal)
    up = np.asarray(cam.up, float)
    up = up - np.dot(up, d) * d
    up /= np.linalg.norm(up)
    side = np.cross(up, d)
    tan = np.tan(np.radians(cam.view_angle) / 2)
    aspect = WINDOW[0] / WINDOW[1]
    pts = np.asarray(points, float)
    pts = pts[np.isfinite(pts).all(axis=1)]
    centre = 0.5 * (pts.min(axis=0) + pts.max(axis=0))

    def spread(c, dist):  # normalised image coordinates of the points
        rel = pts - (c + dist * d)
        depth = -(rel @ d)
        return rel @ side / (depth * tan * aspect), rel @ up / (depth * tan), depth

    size = float(np.max(np.linalg.norm(pts - centre, axis=1)))
    for _ in range(3):  # centre the points in the free part of the picture
        lo, hi = 0.1 * size, 20 * size
        for _ in range(40):
            mid = 0.5 * (lo + hi)
            x, y, depth = spread(centre, mid)
            ok = (depth > 0).all() and x.min() >= -0.95 and x.max() <= right and y.max() <= top and y.min() >= -0.95
            lo, hi = (lo, mid) if ok else (mid, hi)
        x, y, depth = spread(centre, hi)
        shift_y = 0.5 * (y.max() + y.min()) - 0.5 * (top - 0.95)
        shift_x = 0.5 * (x.max() + x.min()) - 0.5 * (right - 0.95)
        centre = centre + np.median(depth) * tan * (shift_y * up + shift_x * aspect * side)
    cam.focal_point = centre
    cam.position = centre + hi * d


def node_labels(
    pl: pv.Plotter,
    nodes: np.ndarray,
    idx: Sequence[int] | np.ndarray,
    font_size: int = 22,
    offset: float = 0.06,
    **kw: Any,
) -> list[str]:
    """Number the nodes idx (0-based) of nodes (12, 3) m 1-based, just outside the structure
    as seen by the camera (the offset, a fraction of S, is taken in the image plane).
    Set the camera first. Returns the labels."""
    c = nodes.mean(axis=0)
    S = strut_length(nodes)
    d = np.asarray(pl.camera.position) - np.asarray(pl.camera.focal_point)
    d /= np.linalg.norm(d)
    out = nodes[idx] - c
    out -= (out @ d)[:, None] * d
    norm = np.maximum(np.linalg.norm(out, axis=1, keepdims=True), 1e-9 * S)
    pos = nodes[idx] + offset * S * out / norm
    labels = [str(i + 1) for i in idx]
    pl.add_point_labels(pos, labels, font_size=font_size, name=kw.pop("name", "node labels"), **{**LABEL, **kw})
    return labels
