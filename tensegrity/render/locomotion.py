"""Figures of a robot standing or rolling on a terrain, drawn off-screen with PyVista (paper
Figs. 8-10; docs/design.md §7): a stable state with the CoG projection inside the support
triangle (Fig. 8), a rolling state with it outside (Fig. 9) and the slope case (Fig. 10).
The path and animation of a whole run are in render.runs and render.animation.

Drawing only, from arrays: node positions (12, 3) m in the world frame, a face and a
`Terrain`; nothing here reads a file (tensegrity.stages.locomotion_states picks the samples
from the run datasets). Each figure writes one PNG and returns a dict saying what was drawn,
so tests can check the scene. The plumbing is render.scene's, so the figures match Figs. 1-7.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pyvista as pv
from numpy.typing import ArrayLike

from ..physics import contact as ct
from ..physics import frames
from ..physics import topology as topo
from ..physics.terrain import Terrain
from . import axes, plot2d
from .scene import finish, lines, node_labels, plotter, robot, strut_length, tube
from .terrain import add_terrain, extent_in_view

__all__ = ["fig_state", "fig_slope"]

STANDS, ROLLS = "#2e9d3a", "#d62728"  # support triangle: CoG projection inside / outside
GRAVITY = "#1f4fd6"
INSET_FONT = 15  # text of the side panels: readable at the figure's 1200 x 900 px
ARROW_MM = 60.0  # length of the inset's arrow, mm in the support frame


# --- scene pieces ----------------------------------------------------------------------------


def _support(pl, p, face, colour, name="support triangle"):
    support = p[topo.FACES[face - 1]]
    pl.add_mesh(pv.PolyData(support, faces=[3, 0, 1, 2]), color=colour, opacity=0.55, lighting=False, name=name)
    pl.add_mesh(
        lines(support, np.array([[0, 1], [1, 2], [2, 0]])).tube(radius=0.004 * strut_length(p)),
        color=colour,
        name=name + " edges",
    )


def _gravity_line(pl, cog, proj, S):
    pl.add_mesh(tube(cog, proj, 0.004 * S), color=GRAVITY, name="gravity line")
    pl.add_points(cog[None], color="black", point_size=18, render_points_as_spheres=True, name="cog")
    pl.add_points(proj[None], color=GRAVITY, point_size=18, render_points_as_spheres=True, name="cog projection")


def _ground(pl, terrain, p, extent):
    """The ground under the robot (nodes p (12, 3) m) as large as fits the main view, at most
    `extent` m each side: it ends inside the picture, not at the side panels. Camera first."""
    centre = p.mean(axis=0)[:2]
    add_terrain(pl, terrain, centre, extent_in_view(pl, terrain, centre, extent), coloured=False)
    pl.renderer.ResetCameraClippingRange()


def _side_camera(pl, p, up, toward, zoom=1.0):
    """Camera looking at the robot from beside the direction `toward`, raised by 38 deg."""
    S = strut_length(p)
    c = p.mean(axis=0)
    toward = np.asarray(toward, float) - np.dot(toward, up) * up
    toward /= np.linalg.norm(toward)
    side = np.cross(up, toward)
    d = math.cos(math.radians(38)) * (0.85 * side - 0.53 * toward) + math.sin(math.radians(38)) * up
    d /= np.linalg.norm(d)
    pl.camera.focal_point = c - 0.25 * S * up
    pl.camera.position = c + 3.4 * S / zoom * d
    pl.camera.up = up
    pl.camera.view_angle = 30.0
    pl.renderer.ResetCameraClippingRange()


def _inset(pl, k, contact: ct.Contact, colour, arrow=None, normal_xy=None) -> dict:
    """Renderer k: the support triangle seen from above in its support frame (mm), with the
    CoG projection, a scale bar and, optionally, an arrow (2-D unit vector) from the crossed
    edge. Returns the scale bar (axes.scale_bar)."""
    pl.subplot(0, k)
    support = contact.support * 1e3
    q = contact.projection_2d * 1e3
    tip = [] if arrow is None else [q + ARROW_MM * np.asarray(arrow, float)]
    pts = np.vstack([support, q[None], *tip] + ([] if normal_xy is None else [np.asarray(normal_xy)[None] * 1e3]))
    box, _, _ = plot2d.nice_box(pts.min(axis=0) - 25, pts.max(axis=0) + 25)
    margins = (0.06, 0.06, 0.16, 0.2)  # room for the text above and the scale bar below
    plot2d.support_2d(
        pl, support, box, 3, "inset triangle", fill="#eef7ee" if colour == STANDS else "#fbe9e9", edge=colour
    )
    plot2d.corner_labels(pl, support, contact.nodes, 5.0, 18, "inset corner labels")
    pl.add_mesh(plot2d.disc(q, 6.0, 2.0), color=GRAVITY, name="inset projection")
    if normal_xy is not None:
        pl.add_mesh(plot2d.disc(np.asarray(normal_xy) * 1e3, 5.0, 1.5), color="#8c8c8c", name="inset normal projection")
    if arrow is not None:
        a = np.asarray(arrow, float)
        pl.add_mesh(
            pv.Arrow(
                start=(q[0], q[1], 3.0),
                direction=(a[0], a[1], 0.0),
                scale=ARROW_MM,
                tip_length=0.3,
                tip_radius=0.12,
                shaft_radius=0.04,
            ),
            color=ROLLS,
            name="inset arrow",
        )
    bar = axes.scale_bar(pl, k, box, margins, "inset scale bar", avoid=np.vstack([axes.outline_points(support), pts]))
    plot2d.camera_2d(pl, k, box, margins)
    pl.add_text(
        f"from above (support frame)\nCoG projection (blue):\nmargin {contact.margin * 1e3:+.1f} mm",
        position="upper_left",
        font_size=INSET_FONT,
        color="black",
        name=f"inset {k} text",
    )
    pl.subplot(0, 0)
    return bar


# --- Fig. 8, 9 and 10 ------------------------------------------------------------------------


def fig_state(
    nodes: np.ndarray,
    terrain: Terrain,
    face: int | Sequence[int],
    path: str | Path,
    title: str,
    arrow: ArrayLike | None = None,
) -> dict:
    """A robot (nodes (12, 3) m) on `terrain` judged on `face`: the CoG, its projection along
    gravity onto the plane of the face's nodes, the support triangle green if the projection is
    inside (Fig. 8: stable) or red with an arrow over the crossed edge if not (Fig. 9: rolling);
    an inset shows the triangle and the projection in the support frame (mm). `face`: 1..20
    or three node numbers; `arrow`: a world direction (3,) to draw from the middle of the
    edge it points across (e.g. the target). Returns {"path", "size", "title", "actors",
    "face", "margin" m, "stands", "edge" (two node numbers or None), "next_face"}."""
    p = ct.check_nodes(nodes)
    f = topo.face_number(face)
    c = ct.judge(p, f)
    S = strut_length(p)
    colour = STANDS if c.stands else ROLLS
    pl = plotter(title, panels=3)
    robot(pl, p)
    _support(pl, p, f, colour)
    _gravity_line(pl, c.cog, c.projection, S)
    node_labels(pl, p, topo.FACES[f - 1], font_size=22, name="corner labels")
    arrow2 = None
    out_world = ct.edge_outward(p[topo.FACES[f - 1]])
    if c.edge is not None:
        k = frames.crossed_edge(c.projection_2d, c.support)
        mid = p[[n - 1 for n in c.edge]].mean(axis=0) + 0.06 * S * c.normal
        pl.add_mesh(
            pv.Arrow(
                start=mid, direction=out_world[k], scale=0.45 * S, tip_length=0.25, tip_radius=0.08, shaft_radius=0.03
            ),
            color=ROLLS,
            name="rolling arrow",
        )
        _, rot = frames.face_frame(p, f)
        arrow2 = (rot @ out_world[k])[:2]
    if arrow is not None:  # the target direction, from the middle of the best-matching edge
        a = np.asarray(arrow, float)
        a = a / np.linalg.norm(a)
        k = int(np.argmax(out_world @ a))
        mid = p[topo.FACES[f - 1]][[k, (k + 1) % 3]].mean(axis=0) + 0.06 * S * c.normal
        pl.add_mesh(
            pv.Arrow(start=mid, direction=a, scale=0.45 * S, tip_length=0.25, tip_radius=0.08, shaft_radius=0.03),
            color="#ff7f0e",
            name="target arrow",
        )
    up = c.normal if terrain.kind == "none" else terrain.normal_at(*c.cog[:2])
    toward = out_world[int(np.argmin(frames.edge_distances(c.projection_2d, c.support)))]
    _side_camera(pl, p, up, toward)
    _ground(pl, terrain, p, 1.12 * S)
    bar = _inset(pl, 1, c, colour, arrow2)
    pl.subplot(0, 2)
    legend = (
        "black: CoG\nblue: its projection along gravity\n"
        + ("orange arrow: target direction\n" if arrow is not None else "")
        + f"{'green' if c.stands else 'red'} triangle: contact face\n{topo.face_label(f)}; "
        + (
            "the projection is inside:\nthe robot stands"
            if c.stands
            else f"the projection is outside,\nover edge {c.edge[0]}-{c.edge[1]}: it rolls onto "
            f"{topo.face_label(c.next_face)}\nred arrows (both views): the way\nit rolls, out across "
            f"edge {c.edge[0]}-{c.edge[1]}"
        )
    )
    pl.add_text(legend, position="upper_left", font_size=INSET_FONT, color="black", name="legend")
    pl.subplot(0, 0)
    return finish(
        pl,
        path,
        title,
        face=f,
        margin=c.margin,
        stands=c.stands,
        edge=c.edge,
        next_face=c.next_face,
        legend=legend,
        scale_bars={"inset scale bar": bar},
    )


def fig_slope(nodes: np.ndarray, terrain: Terrain, face: int | Sequence[int], path: str | Path, title: str) -> dict:
    """Fig. 10: a robot standing on a slope; the CoG projected along gravity (blue, the
    paper's construction) and along the face normal (grey), which differ by h tan(angle)
    downhill. nodes: (12, 3) world, m; face: 1..20 or three node numbers.
    Returns {"path", "size", "title", "actors", "face", "margin" m, "shift" m, "angle" deg}."""
    p = ct.check_nodes(nodes)
    f = topo.face_number(face)
    c = ct.judge(p, f)
    S = strut_length(p)
    tri = p[topo.FACES[f - 1]]
    h = float(np.dot(c.cog - tri.mean(axis=0), c.normal))
    normal_foot = c.cog - h * c.normal
    shift = float(np.linalg.norm(c.projection - normal_foot))
    angle = math.degrees(math.acos(min(1.0, abs(float(c.normal[2])))))
    pl = plotter(title, panels=3)
    robot(pl, p, opacity=0.35)
    _support(pl, p, f, STANDS if c.stands else ROLLS)
    _gravity_line(pl, c.cog, c.projection, S)
    pl.add_mesh(tube(c.cog, normal_foot, 0.003 * S), color="#8c8c8c", name="normal line")
    pl.add_points(
        normal_foot[None], color="#8c8c8c", point_size=14, render_points_as_spheres=True, name="normal projection"
    )
    downhill = np.array([-terrain.normal[0], -terrain.normal[1], 0.0])
    downhill = downhill / np.linalg.norm(downhill) if np.linalg.norm(downhill) > 1e-9 else np.array([1.0, 0, 0])
    view = np.cross([0, 0, 1.0], downhill)  # horizontal, across the slope: downhill runs sideways
    centre = c.cog - 0.3 * h * np.array([0, 0, 1.0])
    pl.camera.focal_point = centre
    pl.camera.position = centre + 3.6 * S * (
        math.cos(math.radians(8)) * view + math.sin(math.radians(8)) * np.array([0, 0, 1.0])
    )
    pl.camera.up = (0, 0, 1)
    pl.camera.view_angle = 30.0
    _ground(pl, terrain, p, 1.4 * S)
    origin, rot = frames.face_frame(p, f)
    bar = _inset(pl, 1, c, STANDS if c.stands else ROLLS, normal_xy=frames.to_frame(c.cog, origin, rot)[:2])
    pl.subplot(0, 2)
    legend = (
        f"slope {angle:.1f} deg, seen across it\n(downhill to the side)\n"
        f"blue: projection along gravity\n(paper Fig. 10)\n"
        f"grey: along the face normal\nthey differ by h tan(angle)\n= {shift * 1e3:.1f} mm "
        f"downhill\n(h = {h * 1e3:.0f} mm: CoG height\nabove the face)"
    )
    pl.add_text(legend, position="upper_left", font_size=INSET_FONT, color="black", name="legend")
    pl.subplot(0, 0)
    return finish(
        pl,
        path,
        title,
        face=f,
        margin=c.margin,
        shift=shift,
        angle=angle,
        legend=legend,
        scale_bars={"inset scale bar": bar},
    )
