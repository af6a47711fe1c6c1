"""Figures of rolling locomotion, drawn off-screen with PyVista (paper Fig. 8-10; design.md
section 7): a stable state with the CoG projection inside the support triangle (Fig. 8), a
rolling state with it outside (Fig. 9), the slope case (Fig. 10), the path of a run from above
and in 3D, and an animation of a run (GIF).

Drawing functions take node positions (12, 3) m and a Terrain, write one PNG and return a small
dict saying what was drawn (so tests can check the scene); `render_*` read run datasets
(results/locomotion/*.nc) and are what the workflow calls. The plumbing (plotter, tubes,
colours, off-screen set-up) is tensegrity.render's, so the figures match Fig. 1-7.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pyvista as pv

from ..physics import contact as ct
from ..physics import frames, topology as topo
from . import scene as rd
from ..physics.terrain import Terrain

STANDS, ROLLS = "#2e9d3a", "#d62728"  # support triangle: CoG projection inside / outside
GRAVITY = "#1f4fd6"
PATH = "#111111"
GOAL = "#e6194b"


# --- scene pieces ----------------------------------------------------------------------------

def _robot(pl: pv.Plotter, p: np.ndarray, opacity: float = 1.0, name: str = "robot") -> None:
    S = rd._strut_length(p)
    for k, (a, b) in enumerate(topo.STRUTS):
        pl.add_mesh(rd._tube(p[a], p[b], 0.02 * S), color=rd.STRUT_COLOURS[k], opacity=opacity,
                    smooth_shading=True, name=f"{name} strut {a + 1}-{b + 1}")
    pl.add_mesh(rd._lines(p, topo.CABLES).tube(radius=0.0045 * S, n_sides=10), color=rd.CABLE_COLOUR,
                opacity=opacity, name=f"{name} cables")


def _terrain_mesh(terrain: Terrain, centre, extent: float) -> pv.PolyData:
    verts, tris = terrain.triangles(extent=extent, centre=centre)
    mesh = pv.PolyData(verts, faces=np.hstack([np.full((len(tris), 1), 3), tris]).ravel())
    mesh["height (m)"] = verts[:, 2]
    return mesh


def _add_terrain(pl: pv.Plotter, terrain: Terrain, centre, extent: float, coloured: bool) -> None:
    mesh = _terrain_mesh(terrain, centre, extent)
    if coloured and terrain.kind == "heightfield":
        pl.add_mesh(mesh, scalars="height (m)", cmap="gist_earth", opacity=1.0, name="terrain",
                    scalar_bar_args={"title": "terrain height (m)", "color": "black",
                                     "vertical": True, "position_x": 0.88, "position_y": 0.2,
                                     "title_font_size": 16, "label_font_size": 14, "fmt": "%.2f"})
        pl.add_mesh(mesh.extract_all_edges(), color="#5a5a5a", opacity=0.35, name="terrain grid")
    else:
        pl.add_mesh(mesh, color="#d9d4c7", opacity=0.9, name="terrain")


def _support(pl, p, face, colour, name="support triangle"):
    tri = p[topo.FACES[face - 1]]
    pl.add_mesh(pv.PolyData(tri, faces=[3, 0, 1, 2]), color=colour, opacity=0.55, lighting=False,
                name=name)
    pl.add_mesh(rd._lines(tri, np.array([[0, 1], [1, 2], [2, 0]])).tube(
        radius=0.004 * rd._strut_length(p)), color=colour, name=name + " edges")


def _gravity_line(pl, cog, proj, S):
    pl.add_mesh(rd._tube(cog, proj, 0.004 * S), color=GRAVITY, name="gravity line")
    pl.add_points(cog[None], color="black", point_size=18, render_points_as_spheres=True, name="cog")
    pl.add_points(proj[None], color=GRAVITY, point_size=18, render_points_as_spheres=True,
                  name="cog projection")


def _side_camera(pl, p, up, toward, zoom=1.0):
    """Camera looking at the robot from beside the direction `toward`, raised by 38 deg."""
    S = rd._strut_length(p)
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


def _inset(pl, k, contact: ct.Contact, colour, arrow=None, normal_xy=None):
    """Renderer k: the support triangle seen from above in its support frame (mm), with the
    CoG projection and, optionally, an arrow (2-D unit vector) from the crossed edge."""
    pl.subplot(0, k)
    tri = contact.triangle * 1e3
    q = contact.local * 1e3
    pts = np.vstack([tri, q[None]])
    box, nx, ny = rd._nice_box(pts.min(axis=0) - 25, pts.max(axis=0) + 25)
    rd._triangle_2d(pl, np.column_stack([tri, np.zeros(3)]), box, 3, "inset triangle",
                    fill="#eef7ee" if colour == STANDS else "#fbe9e9", edge=colour)
    rd._corner_labels(pl, np.column_stack([tri, np.zeros(3)]), contact.nodes, 5.0, 18,
                      "inset corner labels")
    pl.add_mesh(rd._disc(q, 6.0, 2.0), color=GRAVITY, name="inset projection")
    if normal_xy is not None:
        pl.add_mesh(rd._disc(np.asarray(normal_xy) * 1e3, 5.0, 1.5), color="#8c8c8c",
                    name="inset normal projection")
    if arrow is not None:
        a = np.asarray(arrow, float)
        pl.add_mesh(pv.Arrow(start=(q[0], q[1], 3.0), direction=(a[0], a[1], 0.0), scale=60.0,
                             tip_length=0.3, tip_radius=0.12, shaft_radius=0.04),
                    color=ROLLS, name="inset arrow")
    rd._camera_2d(pl, k, box, margins=(0.06, 0.06, 0.06, 0.1))
    pl.add_text(f"seen from above, support frame: corners are nodes\nCoG projection (blue) "
                f"margin {contact.margin * 1e3:+.1f} mm", position="upper_left", font_size=10,
                color="black", name=f"inset {k} text")
    pl.subplot(0, 0)


# --- Fig. 8, 9 and 10 ------------------------------------------------------------------------

def fig_state(nodes, terrain: Terrain, face, path, title: str, arrow=None) -> dict:
    """A robot (nodes (12, 3) m) on `terrain` judged on `face`: the CoG, its projection along
    gravity onto the plane of the face's nodes, the support triangle green if the projection is
    inside (Fig. 8: stable) or red with an arrow over the crossed edge if not (Fig. 9: rolling);
    an inset shows the triangle and the projection in the support frame (mm). `arrow`: a world
    direction to draw from the CoG (e.g. the target). Returns {"path", "title", "actors",
    "face", "margin" m, "stands", "edge", "next_face"}."""
    p = rd._check_nodes(nodes)
    f = topo.face_number(face)
    c = ct.judge(p, f)
    S = rd._strut_length(p)
    colour = STANDS if c.stands else ROLLS
    pl = rd._plotter(title, panels=3)
    _add_terrain(pl, terrain, p.mean(axis=0)[:2], 0.7 * S * 1.6, coloured=False)
    _robot(pl, p)
    _support(pl, p, f, colour)
    _gravity_line(pl, c.cog, c.projection, S)
    rd._node_labels(pl, p, topo.FACES[f - 1], font_size=22, name="corner labels")
    arrow2 = None
    out_world = ct.edge_outward(p[topo.FACES[f - 1]])
    if c.edge is not None:
        k = [topo.edge_nodes(f, j) for j in range(3)].index(c.edge)
        mid = p[[n - 1 for n in c.edge]].mean(axis=0) + 0.06 * S * c.normal
        pl.add_mesh(pv.Arrow(start=mid, direction=out_world[k], scale=0.45 * S, tip_length=0.25,
                             tip_radius=0.08, shaft_radius=0.03), color=ROLLS, name="rolling arrow")
        origin, rot = frames.face_frame(p, f)
        arrow2 = (rot @ out_world[k])[:2]
    if arrow is not None:  # the target direction, from the middle of the best-matching edge
        a = np.asarray(arrow, float)
        a = a / np.linalg.norm(a)
        k = int(np.argmax(out_world @ a))
        mid = p[topo.FACES[f - 1]][[k, (k + 1) % 3]].mean(axis=0) + 0.06 * S * c.normal
        pl.add_mesh(pv.Arrow(start=mid, direction=a, scale=0.45 * S, tip_length=0.25,
                             tip_radius=0.08, shaft_radius=0.03), color="#ff7f0e",
                    name="target arrow")
    up = c.normal if terrain.kind == "none" else terrain.normal_at(*c.cog[:2])
    toward = out_world[int(np.argmin(frames.edge_distances(c.local, c.triangle)))]
    _side_camera(pl, p, up, toward)
    _inset(pl, 1, c, colour, arrow2)
    pl.subplot(0, 2)
    legend = ("black: CoG   blue: its projection along gravity\n"
              + ("orange arrow: the target direction\n" if arrow is not None else "")
              + f"{'green' if c.stands else 'red'} triangle: contact face {topo.face_label(f)}\n"
              + ("the projection is inside: the robot stands" if c.stands else
                 f"outside, over edge {c.edge[0]}-{c.edge[1]}: it rolls onto "
                 f"{topo.face_label(c.next_face)}"))
    pl.add_text(legend, position="upper_left", font_size=11, color="black", name="legend")
    pl.subplot(0, 0)
    return rd._finish(pl, path, title, face=f, margin=c.margin, stands=c.stands, edge=c.edge,
                      next_face=c.next_face)


def fig_slope(nodes, terrain: Terrain, face, path, title: str) -> dict:
    """Fig. 10: a robot standing on a slope; the CoG projected along gravity (blue, the
    paper's construction) and along the face normal (grey), which differ by h tan(angle)
    downhill. Returns {"path", "title", "actors", "face", "margin" m, "shift" m, "angle" deg}."""
    p = rd._check_nodes(nodes)
    f = topo.face_number(face)
    c = ct.judge(p, f)
    S = rd._strut_length(p)
    tri = p[topo.FACES[f - 1]]
    h = float(np.dot(c.cog - tri.mean(axis=0), c.normal))
    normal_foot = c.cog - h * c.normal
    shift = float(np.linalg.norm(c.projection - normal_foot))
    angle = math.degrees(math.acos(min(1.0, abs(float(c.normal[2])))))
    pl = rd._plotter(title, panels=3)
    _add_terrain(pl, terrain, p.mean(axis=0)[:2], 1.4 * S, coloured=False)
    _robot(pl, p, opacity=0.35)
    _support(pl, p, f, STANDS if c.stands else ROLLS)
    _gravity_line(pl, c.cog, c.projection, S)
    pl.add_mesh(rd._tube(c.cog, normal_foot, 0.003 * S), color="#8c8c8c", name="normal line")
    pl.add_points(normal_foot[None], color="#8c8c8c", point_size=14,
                  render_points_as_spheres=True, name="normal projection")
    downhill = np.array([-terrain.normal[0], -terrain.normal[1], 0.0])
    downhill = downhill / np.linalg.norm(downhill) if np.linalg.norm(downhill) > 1e-9 else np.array([1.0, 0, 0])
    view = np.cross([0, 0, 1.0], downhill)  # horizontal, across the slope: downhill runs sideways
    centre = c.cog - 0.3 * h * np.array([0, 0, 1.0])
    pl.camera.focal_point = centre
    pl.camera.position = centre + 3.6 * S * (math.cos(math.radians(8)) * view
                                             + math.sin(math.radians(8)) * np.array([0, 0, 1.0]))
    pl.camera.up = (0, 0, 1)
    pl.camera.view_angle = 30.0
    pl.renderer.ResetCameraClippingRange()
    origin, rot = frames.face_frame(p, f)
    _inset(pl, 1, c, STANDS if c.stands else ROLLS, normal_xy=frames.to_frame(c.cog, origin, rot)[:2])
    pl.subplot(0, 2)
    pl.add_text(f"slope {angle:.1f} deg, seen across it (downhill to the side)\n"
                f"blue: projection along gravity (paper Fig. 10)\n"
                f"grey: along the face normal\nthey differ by h tan(angle) = {shift * 1e3:.1f} mm "
                f"downhill\n(h = {h * 1e3:.0f} mm: CoG height above the face)",
                position="upper_left", font_size=11, color="black", name="legend")
    pl.subplot(0, 0)
    return rd._finish(pl, path, title, face=f, margin=c.margin, shift=shift, angle=angle)


# --- paths and animation ---------------------------------------------------------------------

def _run_arrays(ds):
    """Nodes (T, 12, 3) m, CoG (T, 3) m and the sample index at the end of each step."""
    t = ds["time"].values
    idx = np.clip(np.searchsorted(t, ds["t_end"].values), 0, len(t) - 1)
    return ds["nodes"].values, ds["cog"].values, idx


def _oblique_camera(pl: pv.Plotter, centre, cog: np.ndarray, distance: float) -> None:
    """Look at the run from the -x, -y side, 40 deg up, from `distance` m (3D path, animation)."""
    c = np.array([centre[0], centre[1], float(np.nanmean(cog[:, 2]))])
    d = np.array([-0.55, -0.75, 0.62])
    pl.camera.focal_point = c
    pl.camera.position = c + distance * d / np.linalg.norm(d)
    pl.camera.up = (0, 0, 1)
    pl.camera.view_angle = 30.0


def fig_path(ds, path, view: str = "top", title: str | None = None) -> dict:
    """The path of a run (a results/locomotion dataset) over its terrain, `view` "top" (from
    above, parallel projection) or "3d": the CoG track, the contact triangles the robot settled
    on after each roll, the start, the goal with the arrival circle, and the robot at the end.
    Returns {"path", "title", "actors", "rolls", "outcome", "view"}."""
    if view not in ("top", "3d"):
        raise ValueError(f"unknown view {view!r}: use 'top' or '3d'")
    from ..locomotion.demos import terrain_from_dataset
    terrain = terrain_from_dataset(ds)
    nodes, cog, idx = _run_arrays(ds)
    goal = ds["goal"].values
    faces = ds["next_face"].values
    pts = cog[:, :2]
    if np.all(np.isfinite(goal)):
        pts = np.vstack([pts, goal[None, :2]])
    centre = 0.5 * (pts.min(axis=0) + pts.max(axis=0))
    extent = 0.5 * float(np.max(pts.max(axis=0) - pts.min(axis=0))) + 0.6
    run = ds.attrs.get("run", "")
    if title is None:
        title = (f"Rolling run '{run}' on {terrain.kind} ground: {ds.attrs['outcome']}, "
                 f"{int(ds.attrs['rolls'])} rolls ({'from above' if view == 'top' else '3D'})")
    pl = rd._plotter(title)
    _add_terrain(pl, terrain, centre, 1.45 * extent, coloured=True)
    lift = 0.02
    track = cog + [0, 0, lift] if view == "3d" else np.column_stack([cog[:, :2], np.full(len(cog), 1.0)])
    pl.add_mesh(pv.lines_from_points(track).tube(radius=0.007), color=PATH, name="cog track")
    for k, (i, f) in enumerate(zip(idx, faces)):
        if f <= 0:
            continue
        tri = nodes[i][topo.FACES[f - 1]]
        if view == "top":
            tri = np.column_stack([tri[:, :2], np.full(3, 0.9)])
        pl.add_mesh(pv.PolyData(tri, faces=[3, 0, 1, 2]).extract_all_edges().tube(radius=0.006),
                    color="#ff7f0e", name=f"contact {k + 1}")
    start = cog[0] if view == "3d" else np.array([*cog[0, :2], 1.1])
    pl.add_mesh(pv.Sphere(radius=0.05, center=start), color="#2ca02c", name="start")
    if np.all(np.isfinite(goal)):
        gz = goal[2] + lift if view == "3d" else 1.1
        pl.add_mesh(pv.Sphere(radius=0.05, center=(goal[0], goal[1], gz)), color=GOAL, name="goal")
        up = terrain.normal_at(goal[0], goal[1]) if view == "3d" else np.array([0, 0, 1.0])
        ring = pv.Disc(center=(goal[0], goal[1], gz), inner=0.29, outer=0.31, normal=up, c_res=64)
        pl.add_mesh(ring, color=GOAL, name="arrival circle")
    _robot(pl, nodes[-1], name="robot at the end")
    if view == "3d":
        _robot(pl, nodes[0], opacity=0.35, name="robot at the start")
        _oblique_camera(pl, centre, cog, 2.6 * extent)
    else:
        pl.enable_parallel_projection()
        pl.camera.focal_point = (centre[0], centre[1], 0.0)
        pl.camera.position = (centre[0], centre[1], 10.0)
        pl.camera.up = (0, 1, 0)
        pl.camera.parallel_scale = 1.05 * extent
        # a 0.5 m scale bar and the world axes in the lower right corner
        aspect = rd.WINDOW[0] / rd.WINDOW[1]
        x0 = centre[0] + 0.95 * extent * aspect - 0.75
        y0 = centre[1] - 0.85 * extent
        pl.add_mesh(pv.Line((x0, y0, 1.2), (x0 + 0.5, y0, 1.2)).tube(radius=0.01), color="black",
                    name="scale bar")
        pl.add_point_labels(np.array([[x0 + 0.25, y0 + 0.06, 1.2]]), ["0.5 m"], font_size=16,
                            name="scale label", **{**rd._LABEL, "shape_opacity": 0.0})
        for k, (axis, label) in enumerate((((1, 0, 0), "x"), ((0, 1, 0), "y"))):
            pl.add_mesh(pv.Arrow(start=(x0 - 0.3, y0, 1.2), direction=axis, scale=0.22,
                                 tip_length=0.3, tip_radius=0.1, shaft_radius=0.035),
                        color="black", name=f"axis {label}")
            pl.add_point_labels(np.array([[x0 - 0.3 + 0.27 * axis[0], y0 + 0.27 * axis[1], 1.2]]),
                                [label], font_size=16, name=f"axis {label} label",
                                **{**rd._LABEL, "shape_opacity": 0.0})
    pl.renderer.ResetCameraClippingRange()
    pl.add_text("black: CoG track   orange: contact faces after each roll\n"
                "green: start   red: goal and arrival circle", position="lower_left",
                font_size=11, color="black", name="legend")
    return rd._finish(pl, path, title, rolls=int(ds.attrs["rolls"]), outcome=ds.attrs["outcome"],
                      view=view)


def animate(ds, path, fps: int = 10, speed: float = 8.0, size=(640, 480)) -> dict:
    """An animation (GIF) of a run: the robot rolling over its terrain toward the goal, the
    CoG track so far, the time and pressures in the title. speed: playback speed relative to
    simulated time. The meshes are built once and moved in place, so a frame costs one render.
    Returns {"path", "frames", "fps"}."""
    import imageio.v2 as imageio
    from ..locomotion.demos import terrain_from_dataset
    if not (fps >= 1 and speed > 0):
        raise ValueError(f"fps must be >= 1 and speed > 0, got {fps!r}, {speed!r}")
    terrain = terrain_from_dataset(ds)
    nodes, cog = ds["nodes"].values, ds["cog"].values
    t, pres = ds["time"].values, ds["pressure"].values
    goal = ds["goal"].values
    frames = np.unique(np.clip(np.searchsorted(t, np.arange(t[0], t[-1] + 1e-9, speed / fps)),
                               0, len(t) - 1))
    pts = cog[:, :2]
    if np.all(np.isfinite(goal)):
        pts = np.vstack([pts, goal[None, :2]])
    centre = 0.5 * (pts.min(axis=0) + pts.max(axis=0))
    extent = 0.5 * float(np.max(pts.max(axis=0) - pts.min(axis=0))) + 0.6
    pl = pv.Plotter(off_screen=True, window_size=size)
    pl.set_background("white")
    ground = _terrain_mesh(terrain, centre, extent)
    pl.add_mesh(ground, color="#cfc8b4", name="terrain")  # one colour: a small GIF
    if terrain.kind == "heightfield":
        pl.add_mesh(ground.extract_all_edges(), color="#8a8270", name="terrain grid")
    if np.all(np.isfinite(goal)):
        pl.add_mesh(pv.Sphere(radius=0.05, center=goal + [0, 0, 0.02]), color=GOAL, name="goal")
    def lines(seg):
        return pv.PolyData(nodes[frames[0]].copy(), lines=np.hstack(
            [np.full((len(seg), 1), 2), seg]).ravel())

    struts, cables = lines(topo.STRUTS), lines(topo.CABLES)
    struts.cell_data["strut"] = np.arange(6)
    track = pv.lines_from_points(np.repeat(cog[frames[0]][None] + [0, 0, 0.02], len(frames), axis=0))
    pl.add_mesh(struts, scalars="strut", cmap=rd.STRUT_COLOURS, show_scalar_bar=False,
                render_lines_as_tubes=True, line_width=9, name="struts")
    pl.add_mesh(cables, color=rd.CABLE_COLOUR, render_lines_as_tubes=True, line_width=2,
                name="cables")
    pl.add_mesh(track, color=PATH, line_width=3, name="track")
    _oblique_camera(pl, centre, cog, 2.4 * extent)
    pl.renderer.ResetCameraClippingRange()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    run = ds.attrs.get("run", "")
    trail = np.repeat(cog[frames[0]][None] + [0, 0, 0.02], len(frames), axis=0)
    with imageio.get_writer(path, mode="I", duration=1000.0 / fps, loop=0) as writer:
        for n, i in enumerate(frames):
            struts.points = nodes[i]
            cables.points = nodes[i]
            trail[n:] = cog[i] + [0, 0, 0.02]
            track.points = trail
            on = np.flatnonzero(pres[i] > 0)
            act = ", ".join(f"#{k + 1} {pres[i, k]:.1f} MPa" for k in on) or "released"
            pl.add_text(f"run '{run}'  t = {t[i]:5.1f} s ({speed:g}x)  {act}", position="upper_edge",
                        font_size=10, color="black", name="title")
            writer.append_data(pl.screenshot(return_img=True))
    pl.close()
    return {"path": str(path), "frames": len(frames), "fps": fps}


# --- stages (the workflow's scripts call these) -----------------------------------------------

def _sample(ds, step: int, which: str) -> tuple[int, np.ndarray]:
    """Index and nodes of a sample of step `step` (1-based): 'stable' (the pressure at half
    the tipping pressure, the robot still on its face) or 'rolling' (pivoting on an edge of
    its face, the first sample with the CoG projection 25 mm outside, else the furthest)."""
    from ..locomotion.demos import terrain_from_dataset
    terrain = terrain_from_dataset(ds)
    best = None
    t = ds["time"].values
    k0 = int(np.searchsorted(t, ds["t_start"].values[step - 1]))
    k1 = int(np.searchsorted(t, ds["t_end"].values[step - 1]))
    face = int(ds["face"].values[step - 1])
    nodes = ds["nodes"].values
    pres = ds["pressure"].values.max(axis=1)
    tip = float(ds["tip_pressure"].values[step - 1])
    for k in range(k0, k1):
        if which == "stable" and np.isfinite(tip) and pres[k] >= 0.5 * tip:
            return k, nodes[k]
        if which == "rolling":
            touching = ct.clearance(nodes[k], terrain, 0.01)[topo.FACES[face - 1]] < 0.002
            m = ct.judge(nodes[k], face).margin
            if touching.sum() == 2 and m < 0:
                if m < -0.025:
                    return k, nodes[k]
                if best is None or m < best[0]:
                    best = (m, k)
    if which == "stable":
        return k0, nodes[k0]
    if best is not None:
        return best[1], nodes[best[1]]
    raise ValueError(f"step {step} of run {ds.attrs.get('run')!r} never leaves its face")


def render_states(paper_path, slope_path, fig8, fig9, fig10) -> list[dict]:
    """Fig. 8 and 9 from the paper run (its first roll: #10 on (9,10,12)) and Fig. 10 from a
    slope run (the robot at rest on the slope before its first roll)."""
    from ..io.datasets import read
    from ..locomotion.demos import terrain_from_dataset
    ds = read(paper_path)
    terrain = terrain_from_dataset(ds)
    face = int(ds["face"].values[0])
    pair = int(ds["step_pair"].values[0, 0])
    tip = float(ds["tip_pressure"].values[0])
    k, p = _sample(ds, 1, "stable")
    out = [fig_state(p, terrain, face, fig8,
                     f"Fig. 8  Stable: #{pair} at {ds['pressure'].values[k].max():.1f} MPa, the CoG "
                     f"projection stays inside {topo.face_label(face)}",
                     arrow=ct.edge_outward(p[topo.FACES[face - 1]])[
                         [topo.edge_nodes(face, j) for j in range(3)].index(tuple(ds["edge"].values[0]))])]
    k, p = _sample(ds, 1, "rolling")
    out.append(fig_state(p, terrain, face, fig9,
                         f"Fig. 9  Rolling: #{pair} tipped the robot at {tip:.2f} MPa; the CoG "
                         f"projection has left {topo.face_label(face)}"))
    sl = read(slope_path)
    k0 = int(np.searchsorted(sl["time"].values, sl["t_start"].values[0]))
    out.append(fig_slope(sl["nodes"].values[k0], terrain_from_dataset(sl), int(sl["face"].values[0]),
                         fig10, f"Fig. 10  Slope: the CoG projects along gravity onto the contact "
                                f"plane ('{sl.attrs['run']}' run)"))
    return out


def render_paths(run_path, top, three_d) -> list[dict]:
    """The path of one run from above and in 3D."""
    from ..io.datasets import read
    ds = read(run_path)
    return [fig_path(ds, top, "top"), fig_path(ds, three_d, "3d")]


def render_animation(run_path, gif, fps: int = 10, speed: float = 8.0) -> dict:
    from ..io.datasets import read
    return animate(read(run_path), gif, fps, speed)
