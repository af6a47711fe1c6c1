"""The path of a rolling run over its terrain (from above and in 3D), drawn off-screen with
PyVista (docs/design.md §7), and what it shares with the run's animation (render.animation):
the run's arrays checked, the ground shown, the oblique camera, the track's and goal's colours.

Drawing only, from arrays: the node positions of the run's samples (T, 12, 3) m in the world
frame, the faces it settled on, a goal and a `Terrain`; nothing here reads a file or knows a
run dataset (tensegrity.stages.locomotion_paths and locomotion_animation read the runs). Each
function writes one file and returns a dict saying what was drawn.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pyvista as pv
from numpy.typing import ArrayLike

from ..physics import topology as topo
from ..physics.terrain import Terrain
from .scene import LABEL, WINDOW, finish, fit_camera, plotter, robot
from .terrain import add_terrain, terrain_mesh

__all__ = ["fig_path"]

PATH = "#111111"  # the CoG track
GOAL = "#e6194b"
# The CoG track of a path figure is drawn through fewer of its samples, none of them further
# than this from the drawn line: well under a pixel (the smallest ground shown, 1.2 m across
# 900 px, is 1.4 mm per pixel). A track of thousands of samples cost most of a figure's render.
TRACK_TOLERANCE = 0.001  # m


def check_run(nodes: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Node positions (T, 12, 3) m as floats, and the CoG track (T, 3) m (mean of the nodes).
    NaN samples are let through: a run that failed is still drawn up to its failure."""
    nodes = np.asarray(nodes, float)
    if nodes.ndim != 3 or nodes.shape[1:] != (topo.N_NODES, 3) or len(nodes) == 0:
        raise ValueError(f"nodes must be a (T, 12, 3) array in m, T > 0, got shape {nodes.shape}")
    return nodes, nodes.mean(axis=1)


def goal_or_none(goal: ArrayLike | None) -> np.ndarray | None:
    """The goal (3,) m, or None for none (None or NaN)."""
    if goal is None:
        return None
    goal = np.asarray(goal, float).reshape(3)
    return goal if np.all(np.isfinite(goal)) else None


def area_shown(cog: np.ndarray, goal: np.ndarray | None) -> tuple[np.ndarray, float]:
    """Centre (2,) m and half-width (m) of the ground shown: the CoG track and the goal,
    plus 0.6 m."""
    pts = cog[:, :2] if goal is None else np.vstack([cog[:, :2], goal[None, :2]])
    centre = 0.5 * (pts.min(axis=0) + pts.max(axis=0))
    return centre, 0.5 * float(np.max(pts.max(axis=0) - pts.min(axis=0))) + 0.6


def rdp_indices(points: np.ndarray, tol: float) -> np.ndarray:
    """Indices (k,) of the rows of points (n, 3) m that draw the polyline within `tol` m of
    every row (Ramer-Douglas-Peucker; the first and last rows are kept). All rows if any is
    not finite."""
    p = np.asarray(points, float)
    if len(p) < 3 or not np.isfinite(p).all():
        return np.arange(len(p))
    keep = np.zeros(len(p), bool)
    keep[[0, -1]] = True
    todo = [(0, len(p) - 1)]
    while todo:
        a, b = todo.pop()
        if b - a < 2:
            continue
        seg, rel = p[b] - p[a], p[a + 1 : b] - p[a]
        along = np.clip(rel @ seg / (seg @ seg), 0.0, 1.0) if seg @ seg > 0 else 0.0
        dist = np.linalg.norm(rel - np.multiply.outer(along, seg), axis=1)
        i = a + 1 + int(np.argmax(dist))
        if dist[i - a - 1] > tol:
            keep[i] = True
            todo += [(a, i), (i, b)]
    return np.flatnonzero(keep)


def oblique_camera(pl: pv.Plotter, centre: ArrayLike, cog: np.ndarray, distance: float) -> None:
    """Look at the run from the -x, -y side, 40 deg up, from `distance` m (3D path, animation)."""
    c = np.array([centre[0], centre[1], float(np.nanmean(cog[:, 2]))])
    d = np.array([-0.55, -0.75, 0.62])
    pl.camera.focal_point = c
    pl.camera.position = c + distance * d / np.linalg.norm(d)
    pl.camera.up = (0, 0, 1)
    pl.camera.view_angle = 30.0


def _top_camera(pl: pv.Plotter, centre, extent: float) -> None:
    """From above with a parallel projection; a 0.5 m scale bar and the world x, y axes in the
    lower right corner."""
    pl.enable_parallel_projection()
    pl.camera.focal_point = (centre[0], centre[1], 0.0)
    pl.camera.position = (centre[0], centre[1], 10.0)
    pl.camera.up = (0, 1, 0)
    pl.camera.parallel_scale = 1.05 * extent
    x0 = centre[0] + 0.95 * extent * WINDOW[0] / WINDOW[1] - 0.75
    y0 = centre[1] - 0.85 * extent
    pl.add_mesh(pv.Line((x0, y0, 1.2), (x0 + 0.5, y0, 1.2)).tube(radius=0.01), color="black", name="scale bar")
    pl.add_point_labels(
        np.array([[x0 + 0.25, y0 + 0.06, 1.2]]),
        ["0.5 m"],
        font_size=16,
        name="scale label",
        **{**LABEL, "shape_opacity": 0.0},
    )
    for axis, label in (((1, 0, 0), "x"), ((0, 1, 0), "y")):
        pl.add_mesh(
            pv.Arrow(
                start=(x0 - 0.3, y0, 1.2),
                direction=axis,
                scale=0.22,
                tip_length=0.3,
                tip_radius=0.1,
                shaft_radius=0.035,
            ),
            color="black",
            name=f"axis {label}",
        )
        pl.add_point_labels(
            np.array([[x0 - 0.3 + 0.27 * axis[0], y0 + 0.27 * axis[1], 1.2]]),
            [label],
            font_size=16,
            name=f"axis {label} label",
            **{**LABEL, "shape_opacity": 0.0},
        )


def fig_path(
    nodes: np.ndarray,
    terrain: Terrain,
    path: str | Path,
    title: str,
    *,
    faces: ArrayLike = (),
    step_end: ArrayLike = (),
    goal: ArrayLike | None = None,
    view: str = "top",
) -> dict:
    """The path of a run over its terrain, `view` "top" (from above, parallel projection) or
    "3d": the CoG track, the contact triangles the robot settled on after each step, the
    start, the goal with its 0.3 m arrival circle, and the robot at the end (3d: also, faint,
    at the start).

    nodes: (T, 12, 3) node positions of the run's samples, world, m (the CoG track is their
    mean); faces: (n,) 1-based face the robot rests on after each step (0: none, not drawn);
    step_end: (n,) index of each step's last sample in nodes; goal: (3,) world, m (None or
    NaN: no goal). Returns {"path", "size", "title", "actors", "contacts" (triangles drawn),
    "view"}.
    """
    if view not in ("top", "3d"):
        raise ValueError(f"unknown view {view!r}: use 'top' or '3d'")
    nodes, cog = check_run(nodes)
    faces, step_end = np.asarray(faces, int).reshape(-1), np.asarray(step_end, int).reshape(-1)
    if faces.shape != step_end.shape:
        raise ValueError(f"faces {faces.shape} and step_end {step_end.shape} differ in length")
    goal = goal_or_none(goal)
    centre, extent = area_shown(cog, goal)
    pl = plotter(title)
    # 3d: only the ground near the run, all of it in the picture (below the title)
    ground = 1.45 * extent if view == "top" else 1.1 * extent
    add_terrain(pl, terrain, centre, ground, coloured=True)
    lift = 0.02
    track = cog + [0, 0, lift] if view == "3d" else np.column_stack([cog[:, :2], np.full(len(cog), 1.0)])
    drawn = track[rdp_indices(track, TRACK_TOLERANCE)]
    pl.add_mesh(pv.lines_from_points(drawn).tube(radius=0.007), color=PATH, name="cog track")
    contacts = 0
    for k, (i, f) in enumerate(zip(step_end, faces)):
        if f <= 0:
            continue
        support = nodes[i][topo.FACES[f - 1]]
        if view == "top":
            support = np.column_stack([support[:, :2], np.full(3, 0.9)])
        pl.add_mesh(
            pv.PolyData(support, faces=[3, 0, 1, 2]).extract_all_edges().tube(radius=0.006),
            color="#ff7f0e",
            name=f"contact {k + 1}",
        )
        contacts += 1
    start = cog[0] if view == "3d" else np.array([*cog[0, :2], 1.1])
    pl.add_mesh(pv.Sphere(radius=0.05, center=start), color="#2ca02c", name="start")
    if goal is not None:
        gz = goal[2] + lift if view == "3d" else 1.1
        pl.add_mesh(pv.Sphere(radius=0.05, center=(goal[0], goal[1], gz)), color=GOAL, name="goal")
        up = terrain.normal_at(goal[0], goal[1]) if view == "3d" else np.array([0, 0, 1.0])
        ring = pv.Disc(center=(goal[0], goal[1], gz), inner=0.29, outer=0.31, normal=up, c_res=64)
        pl.add_mesh(ring, color=GOAL, name="arrival circle")
    robot(pl, nodes[-1], name="robot at the end")
    if view == "3d":
        robot(pl, nodes[0], opacity=0.35, name="robot at the start")
        oblique_camera(pl, centre, cog, 2.6 * extent)
        fit_camera(
            pl,
            np.vstack([terrain_mesh(terrain, centre, ground).points, nodes[0], nodes[-1], track]),
            right=0.7 if terrain.kind == "heightfield" else 0.95,
        )  # the colour bar
    else:
        _top_camera(pl, centre, extent)
    pl.renderer.ResetCameraClippingRange()
    pl.add_text(
        "black: CoG track   orange: contact faces after each roll\ngreen: start   red: goal and arrival circle",
        position="lower_left",
        font_size=11,
        color="black",
        name="legend",
    )
    return finish(pl, path, title, contacts=contacts, view=view)
