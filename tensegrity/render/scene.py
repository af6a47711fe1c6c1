"""Figures of the paper, drawn off-screen with PyVista (design.md section 7).

Pure drawing functions on numpy arrays: each writes one PNG (white background, a title, a
fixed camera, WINDOW pixels) and returns a small dict saying what was drawn, so that tests
can check the scene. Node, pair and face numbers are 1-based as in the paper; lengths are
taken in m and shown in mm in the support-frame figures.

Off-screen rendering needs no X display: without DISPLAY the VTK wheel is told to use its
EGL window (Mesa's llvmpipe software renderer through libEGL; Debian packages libegl1,
libegl-mesa0 and libgl1-mesa-dri). Callers set nothing.
"""
from __future__ import annotations

import os

if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
    # Without this VTK first tries X, warns "bad X server connection", then falls back to EGL.
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")

from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
import pyvista as pv  # noqa: E402
from matplotlib import colormaps  # noqa: E402  (a PyVista dependency)
from scipy.spatial.transform import Rotation  # noqa: E402

from ..physics import frames, topology as topo

pv.OFF_SCREEN = True

WINDOW = (1200, 900)  # px
STRUT_COLOURS = ["#1f77b4", "#2ca02c", "#d62728", "#9467bd", "#ff7f0e", "#17becf"]
CABLE_COLOUR = "#8b4513"  # brown, as in the paper's Fig. 1
# One colour per pair #1..#12; the strongest contrasts go to the pairs that move the CoG most
# (#9, #10, #12, then #4, #6, #7 on the equilateral face; #5, #11 on the isosceles one).
PAIR_COLOURS = ["#42d4f4", "#9a6324", "#808000", "#f58231", "#000075", "#911eb4",
                "#f032e6", "#469990", "#e6194b", "#4363d8", "#d4a000", "#3cb44b"]
AXIS_COLOURS = {"x": "#d62728", "y": "#2ca02c", "z": "#1f4fd6"}
# Canonical view of the robot in its reference pose (direction from the centre to the camera,
# and the up vector): the direction that keeps the 12 projected nodes furthest apart.
_ROBOT_VIEW = (np.array([-0.441, -0.148, 0.885]), np.array([0.0, 1.0, 0.0]))
_LABEL = dict(bold=True, text_color="black", shape_color="white", shape_opacity=0.75,
              show_points=False, always_visible=True, margin=2)


# --- plumbing --------------------------------------------------------------------------------

def _plotter(title: str, panels: int = 1) -> pv.Plotter:
    """A white off-screen plotter. panels = 3 gives a main view on the left (renderer 0), two
    side panels on the right (1: top, with a border; 2: bottom) and a title strip (3)."""
    pl = pv.Plotter(off_screen=True, window_size=WINDOW, shape=(1, 4 if panels == 3 else 1),
                    border=False)
    pl.set_background("white")
    if panels == 3:
        ports = [(0.0, 0.0, 0.7, 0.93), (0.7, 0.45, 1.0, 0.93), (0.7, 0.0, 1.0, 0.45),
                 (0.0, 0.93, 1.0, 1.0)]
        for r, port in zip(pl.renderers, ports):
            r.SetViewport(*port)
            r.set_background("white")
        pl.renderers[1].add_border(color="black", width=2)
        pl.subplot(0, 3)
        pl.add_text(title, position="upper_edge", font_size=13, color="black", name="title")
    else:
        pl.add_title(title, font_size=13, color="black")
    pl.subplot(0, 0)
    return pl


def _aspect(pl: pv.Plotter, k: int) -> float:
    x0, y0, x1, y1 = pl.renderers[k].GetViewport()
    return (x1 - x0) * WINDOW[0] / ((y1 - y0) * WINDOW[1])


def _view_2d(pl: pv.Plotter, k: int, box, margins=(0.04, 0.04, 0.04, 0.04)):
    """The region (xmin, xmax, ymin, ymax) that renderer k shows when box fills it less
    margins (left, right, bottom, top, fractions of the viewport), equal scales on x and y."""
    x0, x1, y0, y1 = box
    ml, mr, mb, mt = margins
    aspect = _aspect(pl, k)
    height = max((y1 - y0) / (1 - mb - mt), (x1 - x0) / (1 - ml - mr) / aspect)
    width = height * aspect
    cx = (x0 + x1) / 2 + width * (mr - ml) / 2
    cy = (y0 + y1) / 2 + height * (mt - mb) / 2
    return cx - width / 2, cx + width / 2, cy - height / 2, cy + height / 2


def _camera_2d(pl: pv.Plotter, k: int, box, margins=(0.04, 0.04, 0.04, 0.04)) -> None:
    """Look down -z with a parallel projection at _view_2d(pl, k, box, margins)."""
    v = _view_2d(pl, k, box, margins)
    cx, cy = (v[0] + v[1]) / 2, (v[2] + v[3]) / 2
    cam = pl.renderers[k].camera
    cam.parallel_projection = True
    cam.focal_point = (cx, cy, 0.0)
    cam.position = (cx, cy, 1e4)
    cam.up = (0.0, 1.0, 0.0)
    cam.parallel_scale = (v[3] - v[2]) / 2
    pl.renderers[k].ResetCameraClippingRange()


def _nice_box(lo, hi, n: int = 5):
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


def _finish(pl: pv.Plotter, path, title: str, **what) -> dict:
    """Write the PNG, close the plotter and return what was drawn (actor names included)."""
    # PyVista names a point-label actor "<name>-labels"; report the name we gave it
    names = sorted(name.removesuffix("-labels") for r in pl.renderers for name in r.actors)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    pl.screenshot(str(path))
    pl.close()
    return {"path": str(path), "size": WINDOW, "title": title, "actors": names, **what}


def _tube(a, b, radius: float) -> pv.PolyData:
    return pv.Line(a, b).tube(radius=radius, n_sides=24, capping=True)


def _lines(points: np.ndarray, segments: np.ndarray) -> pv.PolyData:
    """One PolyData of straight segments (k, 2) between rows of points."""
    mesh = pv.PolyData(np.asarray(points, float))
    mesh.lines = np.hstack([np.full((len(segments), 1), 2), segments]).ravel()
    return mesh


def _strut_length(nodes: np.ndarray) -> float:
    return float(np.mean(np.linalg.norm(nodes[topo.STRUTS[:, 0]] - nodes[topo.STRUTS[:, 1]], axis=1)))


def _check_nodes(nodes) -> np.ndarray:
    p = np.asarray(nodes, float)
    if p.shape != (topo.N_NODES, 3) or not np.all(np.isfinite(p)):
        raise ValueError(f"nodes must be a finite (12, 3) array in m, got shape {p.shape}")
    return p


def _robot_camera(pl: pv.Plotter, nodes: np.ndarray, zoom: float = 1.0) -> None:
    """The canonical view (_ROBOT_VIEW) carried along with the robot's pose, so that Fig. 1
    looks the same whatever the robot's position and orientation."""
    c = nodes.mean(axis=0)
    ref = topo.reference_nodes(_strut_length(nodes))
    rot, _ = Rotation.align_vectors(nodes - c, ref)
    d, up = rot.apply(_ROBOT_VIEW[0]), rot.apply(_ROBOT_VIEW[1])
    S = _strut_length(nodes)
    cam = pl.camera
    c = c + 0.05 * S * up  # leave room for the title
    cam.focal_point = c
    cam.position = c + 3.2 * S / zoom * d
    cam.up = up
    cam.view_angle = 30.0
    pl.renderer.ResetCameraClippingRange()


def _node_labels(pl: pv.Plotter, nodes: np.ndarray, idx, font_size: int = 22,
                 offset: float = 0.06, **kw) -> list[str]:
    """Number the nodes idx (0-based) 1-based, just outside the structure as seen by the
    camera (the offset from the centre is taken in the image plane)."""
    c = nodes.mean(axis=0)
    S = _strut_length(nodes)
    d = np.asarray(pl.camera.position) - np.asarray(pl.camera.focal_point)
    d /= np.linalg.norm(d)
    out = nodes[idx] - c
    out -= (out @ d)[:, None] * d
    norm = np.maximum(np.linalg.norm(out, axis=1, keepdims=True), 1e-9 * S)
    pos = nodes[idx] + offset * S * out / norm
    labels = [str(i + 1) for i in idx]
    pl.add_point_labels(pos, labels, font_size=font_size, name=kw.pop("name", "node labels"),
                        **{**_LABEL, **kw})
    return labels


def _struts(pl: pv.Plotter, nodes: np.ndarray, colours, opacity: float = 1.0) -> int:
    S = _strut_length(nodes)
    for k, (a, b) in enumerate(topo.STRUTS):
        pl.add_mesh(_tube(nodes[a], nodes[b], 0.02 * S), color=colours[k], opacity=opacity,
                    smooth_shading=True, name=f"strut {a + 1}-{b + 1}")
    return len(topo.STRUTS)


# --- Fig. 1 and 4 ----------------------------------------------------------------------------

def fig_robot(nodes: np.ndarray, path, highlight_pairs=None, title: str | None = None) -> dict:
    """Fig. 1 (or Fig. 4 with highlight_pairs): the robot, struts as thick tubes, one colour
    each, the 24 cables as thin brown tubes and the 12 nodes numbered.

    nodes: (12, 3) node positions, m (any pose). highlight_pairs: 1-based pair numbers; their
    two cables are drawn thick, one colour per pair, labelled "#v" near node v, the other
    cables thin grey and the struts grey (paper Fig. 4).
    Returns {"path", "size", "title", "actors", "struts", "cables", "node_labels",
    "highlighted": {pair: [cable index (0-based), ...]}, "pair_labels"}.
    """
    p = _check_nodes(nodes)
    pairs = [] if highlight_pairs is None else [topo.check_pair(v) for v in highlight_pairs]
    if len(set(pairs)) != len(pairs):
        raise ValueError(f"highlight_pairs has repeated pairs: {pairs}")
    if title is None:
        title = ("Fig. 4  Actuator pairs " + ", ".join(f"#{v}" for v in pairs)) if pairs else \
            "Fig. 1  Six-strut tensegrity robot: struts (thick), cables (brown), nodes 1-12"
    S = _strut_length(p)
    pl = _plotter(title)
    _robot_camera(pl, p)
    n_struts = _struts(pl, p, ["#9a9a9a"] * 6 if pairs else STRUT_COLOURS)
    hot = {v: topo.PAIR_CABLES[v - 1].tolist() for v in pairs}
    cold = np.setdiff1d(np.arange(topo.N_CABLES), [c for cs in hot.values() for c in cs])
    n_cables = 0
    if len(cold):
        mesh = _lines(p, topo.CABLES[cold]).tube(radius=(0.003 if pairs else 0.0045) * S, n_sides=12)
        pl.add_mesh(mesh, color="#b4b4b4" if pairs else CABLE_COLOUR, name="cables")
        n_cables += len(cold)
    pair_labels, label_pos, label_col = [], [], []
    for v, cs in hot.items():
        colour = PAIR_COLOURS[v - 1]
        mesh = _lines(p, topo.CABLES[cs]).tube(radius=0.011 * S, n_sides=20)
        pl.add_mesh(mesh, color=colour, smooth_shading=True, name=f"pair #{v}")
        n_cables += len(cs)
        # "#v" between the pair's two cables, a third of the way from node v
        far = [c[1] if c[0] == v - 1 else c[0] for c in topo.CABLES[cs]]
        label_pos.append(p[v - 1] + 0.34 * (p[far].mean(axis=0) - p[v - 1]))
        pair_labels.append(f"#{v}")
        label_col.append(colour)
    node_labels = _node_labels(pl, p, np.arange(topo.N_NODES), font_size=22 if pairs else 24)
    pl.add_points(p, color="black", point_size=11, render_points_as_spheres=True, name="nodes")
    for k, (pos, text, colour) in enumerate(zip(label_pos, pair_labels, label_col)):
        pl.add_point_labels(pos[None], [text], font_size=26, name=f"pair label {k}",
                            **{**_LABEL, "text_color": colour, "shape_opacity": 0.85})
    _robot_camera(pl, p)  # adding meshes may have reset it
    return _finish(pl, path, title, struts=n_struts, cables=n_cables, node_labels=node_labels,
                    highlighted=hot, pair_labels=pair_labels)


# --- Fig. 5 ----------------------------------------------------------------------------------

def _frame_camera(pl: pv.Plotter, nodes: np.ndarray, origin: np.ndarray, rot: np.ndarray) -> None:
    """Camera fixed in the support frame: 45 deg above the support plane on the side away from
    the reference vertex, so y points into the picture, x to the right and z (into the robot)
    up."""
    S = _strut_length(nodes)
    h = 0.5 * rot[0] - rot[1]
    h /= np.linalg.norm(h)
    d = np.cos(np.radians(45)) * h + np.sin(np.radians(45)) * rot[2]
    centre = origin + 0.95 * (nodes.mean(axis=0) - origin)
    pl.camera.focal_point = centre
    pl.camera.position = centre + 3.15 * S * d
    pl.camera.up = rot[2]
    pl.camera.view_angle = 30.0
    pl.renderer.ResetCameraClippingRange()


def fig_support_frame(nodes: np.ndarray, face, path, title: str | None = None) -> dict:
    """Fig. 5: the supporting-triangle frame of `face` (1..20 or three node numbers): the robot
    faint, the triangle filled, the x, y, z axes as arrows at its centroid (z into the robot,
    toward the CoG = mean of the nodes, y toward the reference vertex), corners numbered.

    nodes: (12, 3) m. Returns {"path", "size", "title", "actors", "face", "corners" (1-based
    node numbers), "axes" (3, 3) rows x, y, z in world components, "origin" (3,) m}.
    """
    p = _check_nodes(nodes)
    f = topo.face_number(face)
    corners = topo.FACES[f - 1]
    tri, cog = p[corners], p.mean(axis=0)
    origin, rot = frames.face_frame(p, f)
    if title is None:
        title = (f"Fig. 5  Supporting-triangle frame of face {f} {topo.face_label(f)} "
                 f"({topo.FACE_TYPES[f - 1]})")
    S = _strut_length(p)
    pl = _plotter(title)
    _frame_camera(pl, p, origin, rot)
    _struts(pl, p, STRUT_COLOURS, opacity=0.15)
    pl.add_mesh(_lines(p, topo.CABLES).tube(radius=0.004 * S, n_sides=10), color=CABLE_COLOUR,
                opacity=0.18, name="cables")
    pl.add_mesh(pv.PolyData(tri, faces=[3, 0, 1, 2]), color="#ffd54a", opacity=0.85,
                lighting=False, name="support triangle")
    pl.add_mesh(_lines(tri, np.array([[0, 1], [1, 2], [2, 0]])).tube(radius=0.005 * S),
                color="#b8860b", name="support triangle edges")
    length = 0.62 * float(np.min(np.linalg.norm(tri - origin, axis=1)))
    tips = []
    for k, name in enumerate("xyz"):
        arrow = pv.Arrow(start=origin, direction=rot[k], scale=length, tip_length=0.22,
                         tip_radius=0.07, shaft_radius=0.028)
        pl.add_mesh(arrow, color=AXIS_COLOURS[name], name=f"axis {name}")
        tips.append(origin + 1.12 * length * rot[k] + 0.16 * length * rot[(k + 2) % 3])
    pl.add_point_labels(np.array(tips), list("xyz"), font_size=34, name="axis labels",
                        **{**_LABEL, "shape_opacity": 0.0})
    pl.add_point_labels(origin[None] - 0.12 * length * (rot[0] + rot[1]), ["O"], font_size=24,
                        name="origin label", **{**_LABEL, "shape_opacity": 0.0})
    pl.add_points(cog[None], color="black", point_size=16, render_points_as_spheres=True,
                  name="cog")
    pl.add_point_labels(cog[None] + 0.05 * S * rot[0], ["CoG"], font_size=22, name="cog label",
                        **_LABEL)
    _node_labels(pl, p, corners, font_size=28, name="corner labels", offset=0.09)
    pl.add_points(tri, color="black", point_size=12, render_points_as_spheres=True,
                  name="corners")
    _frame_camera(pl, p, origin, rot)
    return _finish(pl, path, title, face=f, corners=(corners + 1).tolist(), axes=rot,
                    origin=origin)


# --- Fig. 6 and 7: support-frame plots (mm, viewed along -z) ---------------------------------

def _level_colours(n: int) -> np.ndarray:
    return colormaps["viridis"](np.linspace(0.0, 0.85, n))[:, :3]


def _clip_polygon(poly: np.ndarray, box) -> np.ndarray:
    """Convex polygon (k, 2) clipped to box (xmin, xmax, ymin, ymax) (Sutherland-Hodgman)."""
    out = np.asarray(poly, float)
    for axis, bound, keep_below in ((0, box[0], False), (0, box[1], True), (1, box[2], False),
                                    (1, box[3], True)):
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


def _clip_segment(a, b, box):
    """Segment a-b (2,) clipped to box, or None if it misses it (Liang-Barsky)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    d = b - a
    t0, t1 = 0.0, 1.0
    for p, q in ((-d[0], a[0] - box[0]), (d[0], box[1] - a[0]), (-d[1], a[1] - box[2]),
                 (d[1], box[3] - a[1])):
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


def _triangle_2d(pl, tri_mm, box, width, name, fill="#fff6d5", edge="#b8860b",
                 corner_labels=None):
    """The support triangle (3, 2+) mm, filled and outlined, clipped to box; with corner
    labels, each visible edge is named ("edge 10-12") at the middle of its visible part."""
    poly = _clip_polygon(tri_mm[:, :2], box)
    if len(poly) >= 3:
        faces = np.hstack([[len(poly)], np.arange(len(poly))])
        pl.add_mesh(pv.PolyData(np.column_stack([poly, np.full(len(poly), -3.0)]), faces=faces),
                    color=fill, lighting=False, name=name + " fill")
    n = 0
    for k in range(3):
        seg = _clip_segment(tri_mm[k, :2], tri_mm[(k + 1) % 3, :2], box)
        if seg is not None:
            pl.add_lines(np.array([[*seg[0], -2.0], [*seg[1], -2.0]]), color=edge, width=width,
                         name=f"{name} edge {k + 1}")
            n += 1
            if corner_labels is not None:
                a, b = sorted((int(corner_labels[k]), int(corner_labels[(k + 1) % 3])))
                mid = 0.5 * (seg[0] + seg[1])
                pl.add_point_labels(np.array([[*mid, 5.0]]), [f"edge {a}-{b}"], font_size=16,
                                    name=f"{name} edge label {k + 1}",
                                    **{**_LABEL, "text_color": edge})
    return n


def _disc(centre_xy, radius, z, inner=0.0):
    return pv.Disc(center=(centre_xy[0], centre_xy[1], z), inner=inner, outer=radius,
                   normal=(0, 0, 1), c_res=48)


def _axes_2d(pl, box, nx: int, ny: int):
    pl.show_bounds(bounds=(box[0], box[1], box[2], box[3], 0, 0), xtitle="x (mm)",
                   ytitle="y (mm)", show_zaxis=False, show_zlabels=False, color="black",
                   font_size=16, location="front", use_2d=True, n_xlabels=nx, n_ylabels=ny,
                   fmt="%.0f", bold=False)


def _corner_labels(pl, tri_mm, labels, z, font_size, name):
    c = tri_mm[:, :2].mean(axis=0)
    out = tri_mm[:, :2] - c
    pos = tri_mm[:, :2] + 0.07 * np.linalg.norm(out, axis=1).max() * out / np.linalg.norm(
        out, axis=1, keepdims=True)
    pl.add_point_labels(np.column_stack([pos, np.full(3, z)]), [str(s) for s in labels],
                        font_size=font_size, name=name, **_LABEL)


def _sample_levels(n_samples: int, levels: np.ndarray, sample_pressure) -> np.ndarray:
    if sample_pressure is None:  # the paper's staircase: equal holds, in order
        return np.minimum(np.arange(n_samples) * len(levels) // n_samples, len(levels) - 1)
    sp = np.asarray(sample_pressure, float).reshape(-1)
    if sp.size != n_samples:
        raise ValueError(f"sample_pressure has {sp.size} values for {n_samples} samples")
    return np.argmin(np.abs(sp[:, None] - levels[None, :]), axis=1)


def _check_points(a, name: str, n: int | None = None) -> np.ndarray:
    a = np.asarray(a, float)
    if a.ndim != 2 or a.shape[1] != 3 or (n is not None and len(a) != n) or \
            not np.all(np.isfinite(a)):
        want = f"({n}, 3)" if n is not None else "(n, 3)"
        raise ValueError(f"{name} must be a finite {want} array in m, got shape {a.shape}")
    return a


def fig_cog_cloud(samples: np.ndarray, nominal: np.ndarray, levels, tri: np.ndarray, path,
                  pair: int, face_label: str, sample_pressure=None, corner_labels=None,
                  title: str | None = None) -> dict:
    """Fig. 6: the CoG during a pressure sweep, projected on the support plane (mm): samples
    as a point cloud coloured by pressure level, nominal CoGs (level averages, paper III.A)
    as circles labelled with their pressure; the main view is zoomed on the cloud with the
    nearest triangle edge, a side panel shows the whole support triangle.

    samples: (T, 3) CoG in the support frame, m; nominal: (n, 3) m; levels: (n,) MPa;
    tri: (3, 3) support triangle in the support frame, m (corners in face order);
    sample_pressure: (T,) MPa of each sample (default: n equal consecutive blocks);
    corner_labels: three node numbers for tri's corners.
    Returns {"path", "size", "title", "actors", "samples", "nominal", "labels",
    "triangle_edges" (edges in the main view), "view_mm" (xmin, xmax, ymin, ymax)}.
    """
    pair = topo.check_pair(pair)
    s = _check_points(samples, "samples") * 1e3
    levels = np.asarray(levels, float).reshape(-1)
    nom = _check_points(nominal, "nominal", len(levels)) * 1e3
    t = _check_points(tri, "tri", 3) * 1e3
    lvl = _sample_levels(len(s), levels, sample_pressure)
    cols = _level_colours(len(levels))
    if title is None:
        title = (f"Fig. 6  CoG path when #{pair} works, face {face_label}, "
                 f"{levels.min():g}-{levels.max():g} MPa (support frame, top view)")
    pl = _plotter(title, panels=3)

    # Main view: the cloud, the nominal CoGs, the frame origin and the nearest edge's stretch.
    pts = np.vstack([s[:, :2], nom[:, :2], [[0.0, 0.0]]])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    span = max(hi - lo)
    edges = [(t[k, :2], t[(k + 1) % 3, :2]) for k in range(3)]
    some = pts[::max(1, len(pts) // 400)]
    dist = [min(_seg_distance(q, a, b) for q in some) for a, b in edges]
    k_near = int(np.argmin(dist))
    if dist[k_near] < 1.5 * span:  # show the edge the CoG is heading for
        a, b = edges[k_near]
        foot = [_closest_on_segment(q, a, b) for q in (nom[-1, :2], lo, hi)]
        lo = np.minimum(lo, np.min(foot, axis=0))
        hi = np.maximum(hi, np.max(foot, axis=0))
    size = hi - lo
    box, nx, ny = _nice_box(lo - 0.06 * size.max(), hi + 0.06 * size.max(), n=8)
    r = 0.016 * max(box[1] - box[0], box[3] - box[2])

    n_edges = _triangle_2d(pl, t, box, 5, "triangle", corner_labels=corner_labels)
    cloud = pv.PolyData(np.column_stack([s[:, :2], np.zeros(len(s))]))
    cloud["rgb"] = (cols[lvl] * 255).astype(np.uint8)
    pl.add_mesh(cloud, scalars="rgb", rgb=True, point_size=4, render_points_as_spheres=True,
                name="cog samples")
    for k in range(len(levels)):
        pl.add_mesh(_disc(nom[k], r, 2.0), color=cols[k], name=f"nominal {k}", lighting=False)
        pl.add_mesh(_disc(nom[k], r, 2.5, inner=0.72 * r), color="black",
                    name=f"nominal ring {k}", lighting=False)
    labels = [f"{p:g} MPa" for p in levels]
    direction = nom[-1, :2] - nom[0, :2]
    side = np.array([-direction[1], direction[0]]) / max(np.linalg.norm(direction), 1e-12)
    pl.add_point_labels(np.column_stack([nom[:, :2] + 3.2 * r * side, np.full(len(nom), 4.0)]),
                        labels, font_size=18, name="nominal labels", **_LABEL)
    pl.add_points(np.array([[0.0, 0.0, 1.0]]), color="black", point_size=10,
                  render_points_as_spheres=True, name="origin")
    pl.add_point_labels(np.array([[0.0, 0.0, 4.0]]) + [r, -r, 0], ["centroid"], font_size=16,
                        name="origin label", **{**_LABEL, "shape_opacity": 0.0})
    if corner_labels is not None:
        _corner_labels(pl, t, corner_labels, 4.0, 18, "corner labels")
    _axes_2d(pl, box, nx, ny)
    _camera_2d(pl, 0, box, margins=(0.13, 0.04, 0.1, 0.03))

    # Context panel: the whole triangle, the cloud and a box around the main view.
    pl.subplot(0, 1)
    tb = (t[:, 0].min(), t[:, 0].max(), t[:, 1].min(), t[:, 1].max())
    _triangle_2d(pl, t, tb, 3, "context triangle")
    pl.add_mesh(cloud.copy(), scalars="rgb", rgb=True, point_size=2, name="context samples")
    frame = np.array([[box[0], box[2], 1], [box[1], box[2], 1], [box[1], box[3], 1],
                      [box[0], box[3], 1], [box[0], box[2], 1]])
    pl.add_lines(frame, color="black", width=2, connected=True, name="context view box")
    if corner_labels is not None:
        _corner_labels(pl, t, corner_labels, 4.0, 14, "context corner labels")
    pl.add_text("whole support triangle", position="upper_edge", font_size=10, color="black",
                name="context caption")
    _camera_2d(pl, 1, tb, margins=(0.12, 0.12, 0.1, 0.15))

    # Legend panel: the pressure levels.
    pl.subplot(0, 2)
    pl.add_legend([[lab, tuple(c), "circle"] for lab, c in zip(labels, cols)], bcolor=None,
                  size=(0.5, 0.6), loc="center", name="legend")
    return _finish(pl, path, title, samples=len(s), nominal=len(nom), labels=labels,
                   triangle_edges=n_edges, view_mm=tuple(float(v) for v in box))


def _closest_on_segment(q, a, b):
    e = b - a
    tt = np.clip(np.dot(q - a, e) / np.dot(e, e), 0.0, 1.0)
    return a + tt * e


def _seg_distance(q, a, b) -> float:
    return float(np.linalg.norm(q - _closest_on_segment(q, a, b)))


def fig_workspace(curves_xy: dict, tri: np.ndarray, path, title: str,
                  tip_points: dict | None = None, corner_labels=None,
                  zoom_mm: float | None = None) -> dict:
    """Fig. 7: the kinematic workspace of one contact face, viewed from above (support-frame z
    toward the camera, CoG projected on the support plane, mm): each pair's CoG curve as a
    coloured line labelled "#v" at its far end, the support triangle with its corners' node
    numbers (corner_labels), and where a curve leaves the triangle (tip_points) as a red ring.
    A side panel zooms on the curves' common start, where the short curves are; a legend
    names every pair with its reach.

    curves_xy: {pair: (m, 3) CoG points along the curve, support frame, m, from low to high
    pressure}; tri: (3, 3) support triangle in the support frame, m; tip_points:
    {pair: (3,) m or None}; corner_labels: three node numbers for tri's corners; zoom_mm:
    half-width of the zoom panel, mm (default: from the short curves).
    Returns {"path", "size", "title", "actors", "curves" {pair: number of points}, "labels"
    (main view), "zoom_labels", "tips" [pairs], "zoom_mm", "view_mm"}.
    """
    curves = {topo.check_pair(v): _check_points(c, f"curve of pair {v}") * 1e3
              for v, c in sorted(curves_xy.items())}
    if not curves:
        raise ValueError("curves_xy is empty: give at least one pair's curve")
    t = _check_points(tri, "tri", 3) * 1e3
    tips = {topo.check_pair(v): _check_points(np.reshape(q, (1, 3)), f"tip of pair {v}")[0] * 1e3
            for v, q in (tip_points or {}).items() if q is not None}
    pl = _plotter(title, panels=3)
    circum = float(np.max(np.linalg.norm(t[:, :2] - t[:, :2].mean(axis=0), axis=1)))
    start = np.mean([c[0, :2] for c in curves.values()], axis=0)
    reach = {v: float(np.max(np.linalg.norm(c[:, :2] - start, axis=1))) for v, c in curves.items()}
    short = [v for v in curves if reach[v] < 0.15 * circum]
    if zoom_mm is None:
        zoom_mm = float(1.4 * max([reach[v] for v in short] or [0.05 * circum]))
    centroid = t[:, :2].mean(axis=0)
    pts = np.vstack([centroid + 1.12 * (t[:, :2] - centroid)] + [c[:, :2] for c in curves.values()])
    box, nx, ny = _nice_box(pts.min(axis=0) - 0.05 * circum, pts.max(axis=0) + 0.05 * circum,
                            n=7)
    zb = (start[0] - zoom_mm, start[0] + zoom_mm, start[1] - zoom_mm, start[1] + zoom_mm)

    def draw(pre: str, view, width: float, label_pairs, font: int, off: float, ring: float):
        _triangle_2d(pl, t, view, 4 if not pre else 3, pre + "triangle")
        for v, c in curves.items():
            xy = np.column_stack([c[:, :2], np.full(len(c), 0.01 * v)])
            pl.add_lines(xy if len(xy) > 1 else np.vstack([xy, xy]), color=PAIR_COLOURS[v - 1],
                         width=width, connected=True, name=f"{pre}curve #{v}")
        texts = []
        for v in label_pairs:
            c = curves[v][:, :2]
            d = c[-1] - start
            d = d / max(np.linalg.norm(d), 1e-12)
            texts.append(f"#{v}")
            pl.add_point_labels(np.array([[*(c[-1] + off * d), 5.0]]), [texts[-1]],
                                font_size=font, name=f"{pre}label #{v}",
                                **{**_LABEL, "text_color": PAIR_COLOURS[v - 1],
                                   "shape_opacity": 0.6})
        for v, q in tips.items():
            pl.add_mesh(_disc(q[:2], ring, 4.0, inner=0.6 * ring), color="red",
                        name=f"{pre}tip #{v}", lighting=False)
        pl.add_points(np.array([[*start, 3.0]]), color="black", point_size=10 if not pre else 12,
                      render_points_as_spheres=True, name=pre + "start")
        return texts

    labels = draw("", box, 6, [v for v in curves if v not in short], 22, 0.08 * circum,
                  0.022 * circum)
    pl.add_lines(np.array([[zb[0], zb[2], 2], [zb[1], zb[2], 2], [zb[1], zb[3], 2],
                           [zb[0], zb[3], 2], [zb[0], zb[2], 2]]), color="#555555", width=2,
                 connected=True, name="zoom box")
    if corner_labels is not None:
        _corner_labels(pl, t, corner_labels, 5.0, 24, "corner labels")
    _axes_2d(pl, box, nx, ny)
    _camera_2d(pl, 0, box, margins=(0.12, 0.03, 0.1, 0.02))

    pl.subplot(0, 1)
    zoom_margins = (0.02, 0.02, 0.02, 0.1)
    zoom_labels = draw("zoom ", _view_2d(pl, 1, zb, zoom_margins), 4, list(curves), 16,
                       0.12 * zoom_mm, 0.05 * zoom_mm)
    pl.add_point_labels(np.array([[*(start + [0.0, -0.12 * zoom_mm]), 5.0]]), ["0 MPa"],
                        font_size=13, name="zoom start label", **{**_LABEL, "shape_opacity": 0.0})
    pl.add_text(f"zoom: start +-{zoom_mm:.0f} mm", position="upper_edge", font_size=10,
                color="black", name="zoom caption")
    _camera_2d(pl, 1, zb, zoom_margins)

    pl.subplot(0, 2)
    entries = [[f"#{v}  {reach[v]:.0f} mm", PAIR_COLOURS[v - 1], "-"] for v in curves]
    if tips:
        entries.append(["leaves triangle", "red", "circle"])
    pl.add_legend(entries, bcolor=None, size=(0.62, 0.95), loc="center", name="legend")
    return _finish(pl, path, title, curves={v: len(c) for v, c in curves.items()},
                   labels=labels, zoom_labels=zoom_labels, tips=sorted(tips), zoom_mm=zoom_mm,
                   view_mm=tuple(float(v) for v in box))
