"""The interactive 3D page of the workspace and of the runs: one self-contained HTML file (plotly,
its JavaScript embedded, so the page opens offline in any browser; docs/design.md §7).

Left, the workspace of a contact case (a menu picks the case) in its support frame, mm: the
unactuated robot standing on the face, the support triangle, and for every pair its CoG samples
(paper Fig. 6), nominal CoGs and fitted curve (Fig. 7); the legend switches pairs on and off.
Right, a run (a menu picks it) in the world frame, m: the terrain, the CoG track, the contact
faces after each roll, the start, the goal with its arrival circle, and the robot at the start
(faint) and at the end. Drag to turn, scroll to zoom.

Drawing only, from arrays (`Workspace`, `Run`); tensegrity.stages.page reads the files.
What the page leaves out: of a pair's CoG samples it draws CLOUD_POINTS evenly spaced in time
and those that keep every sample within CLOUD_TOLERANCE (0.5 mm) of the line through the drawn
ones in time order (Ramer-Douglas-Peucker: the fast moves after a pressure step are kept; 417-651
points of 12000 in a default sweep); the CoG track through the samples within TRACK_TOLERANCE
(1 mm) of it (render.runs); coordinates are rounded to 0.1 um at most.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import plotly.io

from ..atomic import write_text
from ..physics import topology as topo
from ..physics.terrain import Terrain
from . import page_traces as tr
from .runs import GOAL, PATH, TRACK_TOLERANCE, area_shown, check_run, goal_or_none, rdp_indices

__all__ = ["Workspace", "Run", "CLOUD_POINTS", "figure", "write_page"]

CLOUD_POINTS = 400  # CoG samples drawn per pair and contact case, evenly spaced in time, and
CLOUD_TOLERANCE = 5e-4  # m: those that keep every sample within this of the line through them
MM = 1e3  # the workspace is drawn in mm, as the paper's figures
SUPPORT, CONTACT, TIP = "#5a5a5a", "#ff7f0e", "#ff0000"  # grey: no strut or pair has it
DIV_ID = "tensegrity-page"  # a fixed id (plotly draws a random one): the same bytes every run
SIZE = (1400, 800)  # px, the figure's size when it is not stretched to the window


@dataclass(frozen=True)
class Workspace:
    """One contact case in the support frame of its face, m: `nodes` (12, 3) the unactuated
    robot, `support` (3, 3) its support triangle (corners in the order of topology.FACES);
    per pair number: `clouds` (n, 3) CoG samples, `curves` (k, 3) the fitted curve from the
    unactuated CoG, `nominal` (m, 3) nominal CoGs, `tips` (3,) the curve at the tipping pressure,
    where the CoG projection leaves the deformed triangle (pairs that tip only); `unit` of the
    levels, MPa or V (the twisted strings)."""

    contact: str
    face: int
    nodes: np.ndarray
    support: np.ndarray
    clouds: dict[int, np.ndarray] = field(default_factory=dict)
    curves: dict[int, np.ndarray] = field(default_factory=dict)
    nominal: dict[int, np.ndarray] = field(default_factory=dict)
    tips: dict[int, np.ndarray] = field(default_factory=dict)
    unit: str = "MPa"


@dataclass(frozen=True)
class Run:
    """A run in the world frame, m: `nodes` (T, 12, 3) its samples, `faces` (n,) the face it
    rested on after each step (0: none), `step_end` (n,) each step's last sample, `goal` (3,)
    (None or NaN: none), the `terrain`, and a `label` for the menu."""

    name: str
    label: str
    nodes: np.ndarray
    faces: np.ndarray
    step_end: np.ndarray
    goal: np.ndarray | None
    terrain: Terrain


def thin(points: np.ndarray, n: int = CLOUD_POINTS, tol: float = CLOUD_TOLERANCE) -> np.ndarray:
    """The rows of points (m, 3) m, in time order, that are drawn: those that keep every row
    within `tol` m of the line through the drawn ones (render.runs.rdp_indices), and n evenly
    spaced (the look of the cloud where the CoG oscillates)."""
    points = np.asarray(points, float)
    if len(points) <= n:
        return points
    even = np.linspace(0, len(points) - 1, n).round().astype(int)
    return points[np.union1d(even, rdp_indices(points, tol))]


def _workspace_traces(ws: Workspace) -> list:
    kw = dict(scene="scene", legend="legend")
    f = topo.FACES[ws.face - 1]
    out = tr.robot(ws.nodes * MM, name=f"robot (0 {ws.unit})", **kw)
    out += tr.triangle(ws.support * MM, name="support triangle", colour=SUPPORT, labels=f + 1, **kw)
    out += tr.marker(ws.nodes.mean(axis=0) * MM, name=f"CoG (0 {ws.unit})", colour="black", size=5, **kw)
    for p in sorted(ws.curves):
        cloud = thin(ws.clouds.get(p, np.empty((0, 3))))
        out += tr.pair(p, cloud * MM, ws.curves[p] * MM, ws.nominal.get(p, np.empty((0, 3))) * MM, **kw)
    if ws.tips:  # Fig. 7's red rings
        tips = np.array([ws.tips[p] for p in sorted(ws.tips)]) * MM
        out += tr.marker(tips, name="tipping points", colour=TIP, size=9, symbol="circle-open", **kw)
    return out


def _run_traces(run: Run) -> list:
    kw = dict(scene="scene2", legend="legend2")
    nodes, cog = check_run(run.nodes)
    goal = goal_or_none(run.goal)
    centre, extent = area_shown(cog, goal)
    extent -= 0.25  # m: the ground shown reaches 0.35 m past the track and the goal
    verts, tris = run.terrain.triangles(extent=extent, centre=centre)
    near = (np.abs(verts[:, :2] - centre) <= extent + 1e-9).all(axis=1)[tris].all(axis=1)
    if near.any():  # a height field: only the cells near the run, and only their vertices
        used, tris = np.unique(tris[near], return_inverse=True)
        verts, tris = verts[used], tris.reshape(-1, 3)
    out = tr.terrain(verts, tris, relief=run.terrain.kind == "heightfield", **kw)
    lift = np.array([0.0, 0.0, 0.02])  # the track drawn just above the ground it rolls on
    out += tr.track(cog[rdp_indices(cog, TRACK_TOLERANCE)] + lift, name="CoG track", colour=PATH, **kw)
    faces, ends = np.asarray(run.faces, int).reshape(-1), np.asarray(run.step_end, int).reshape(-1)
    tris_ = [nodes[i][topo.FACES[f - 1]] for i, f in zip(ends, faces) if f > 0]
    if tris_:
        loops = np.concatenate([np.vstack([t, t[:1], np.full((1, 3), np.nan)]) for t in tris_])
        out += tr.track(loops, name="contact faces", colour=CONTACT, width=4, **kw)
    out += tr.marker(cog[0], name="start", colour="#2ca02c", **kw)
    if goal is not None:
        out += tr.marker(goal + lift, name="goal", colour=GOAL, **kw)
        up = run.terrain.normal_at(goal[0], goal[1]).reshape(3)
        out += tr.circle(goal + lift, 0.3, name="arrival circle", colour=GOAL, normal=up, **kw)
    out += tr.robot(nodes[0], name="robot at the start", opacity=0.35, **kw)
    out += tr.robot(nodes[-1], name="robot at the end", **kw)
    return out


def _menu(labels: list[str], groups: list[range], x: float) -> dict:
    """A drop-down menu at x (paper coordinates) showing one group of traces at a time."""
    every = [i for g in groups for i in g]
    buttons = [
        dict(
            label=label,
            method="restyle",
            args=[{"visible": [i in g for i in every]}, every],
        )
        for label, g in zip(labels, groups)
    ]
    return dict(buttons=buttons, x=x, y=1.0, xanchor="left", yanchor="top", direction="down", showactive=True)


def figure(workspaces: list[Workspace], runs: list[Run], title: str) -> tuple[dict, dict]:
    """The page's figure (a plotly figure as a dict), and what it holds: {"workspace": [trace
    indices per contact case], "runs": [... per run], "robot": the trace indices of the robot
    shown first (the workspace's, else the first run's)}."""
    if not workspaces and not runs:
        raise ValueError("the page needs at least one contact case or one run")
    traces, groups = [], {"workspace": [], "runs": []}
    for key, items, build in (("workspace", workspaces, _workspace_traces), ("runs", runs, _run_traces)):
        for k, item in enumerate(items):
            new = build(item)
            for t in new:
                t["visible"] = k == 0
            groups[key].append(range(len(traces), len(traces) + len(new)))
            traces += new
    # the workspace on the left, the runs on the right; either alone takes the whole width
    split = 0.5 if workspaces and runs else (1.0 if workspaces else 0.0)
    layout = dict(
        title=dict(text=title, x=0.5, xanchor="center"),
        width=None,
        height=SIZE[1],
        margin=dict(l=0, r=0, t=70, b=0),
        paper_bgcolor="white",
        updatemenus=[],
    )
    if workspaces:
        labels = [f"{w.contact} face {topo.face_label(w.face)}" for w in workspaces]
        layout["updatemenus"].append(_menu(labels, groups["workspace"], 0.0))
        layout["scene"] = dict(
            domain=dict(x=[0.1, split], y=[0.0, 0.92]),
            aspectmode="data",
            camera=dict(eye=dict(x=1.5, y=-1.5, z=0.95)),
            **{f"{a}axis": {"title": f"{a} (mm)"} for a in "xyz"},
        )
        layout["legend"] = dict(x=0.0, y=0.9, xanchor="left", yanchor="top", title="workspace (support frame)")
    if runs:
        layout["updatemenus"].append(_menu([r.label for r in runs], groups["runs"], split))
        layout["scene2"] = dict(
            domain=dict(x=[split + 0.12, 1.0], y=[0.0, 0.92]),
            aspectmode="data",
            camera=dict(eye=dict(x=-1.7, y=-2.4, z=1.9)),
            **{f"{a}axis": {"title": f"{a} (m)"} for a in "xyz"},
        )
        layout["legend2"] = dict(x=split, y=0.9, xanchor="left", yanchor="top", title="run (world frame)")
    robot = [i for i in (groups["workspace"] or groups["runs"])[0] if "robot" in traces[i].get("name", "")]
    return {"data": traces, "layout": layout}, {**{k: [list(g) for g in v] for k, v in groups.items()}, "robot": robot}


def write_page(workspaces: list[Workspace], runs: list[Run], path: str | os.PathLike, title: str) -> dict:
    """Write the page (render.page's docstring) to the HTML file `path`, atomically and
    byte-identically for the same arrays. Returns {"path", "traces" (their names),
    "workspace", "runs", "robot" (trace indices, `figure`)}."""
    fig, groups = figure(workspaces, runs, title)
    html = plotly.io.to_html(
        fig,
        validate=False,
        include_plotlyjs=True,
        full_html=True,
        div_id=DIV_ID,
        default_width="100%",
        default_height=f"{SIZE[1]}px",
        config={"displaylogo": False, "responsive": True},
    )
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    write_text(path, html)
    return {"path": str(path), "traces": [t.get("name", "") for t in fig["data"]], **groups}
