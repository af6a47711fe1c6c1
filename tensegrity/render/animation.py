"""An animation (GIF) of a rolling run over its terrain, drawn off-screen with PyVista
(docs/design.md §7): the robot rolling toward the goal, the CoG track so far, the time and
the pressures applied in each frame's title, and a legend of the colours.

Drawing only, from arrays, as render.runs (whose checks, ground and camera it shares); nothing
here reads a file (tensegrity.stages.locomotion_animation reads the run). It writes one file and
returns a dict saying what was drawn.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pyvista as pv
from numpy.typing import ArrayLike

from ..physics import topology as topo
from ..physics.terrain import Terrain
from .files import atomic
from .runs import GOAL, PATH, area_shown, check_run, goal_or_none, oblique_camera
from .scene import CABLE_COLOUR, STRUT_COLOURS, plotter
from .terrain import terrain_mesh

__all__ = ["animate"]


def _title(pl: pv.Plotter, longest: str, width: int) -> pv.Text:
    """A text actor centred at the top of the picture (`width` px wide), in the largest font
    (at most 24) in which the text `longest` fits 96 % of the width. Unlike a corner annotation
    (`add_text` at a named position), which finds its font size again whenever its text
    changes (20 ms of a 35 ms frame), it keeps one size: the title of a frame does not jump."""
    title = pl.add_text(longest, position=(0.5, 0.99), viewport=True, font_size=12, color="black", name="title")
    title.prop.justification_horizontal, title.prop.justification_vertical = "center", "top"
    box = np.zeros(4)
    for size in range(24, 7, -1):
        title.prop.font_size = size
        title.GetBoundingBox(pl.renderer, box)
        if box[1] - box[0] <= 0.96 * width:
            break
    return title


LEGEND = "black: CoG track so far   red ball: goal   struts coloured as in Fig. 1, cables brown"


def _legend(pl: pv.Plotter, size: tuple[int, int]) -> tuple[float, float, float, float]:
    """LEGEND in a white strip of its own under the scene (a second renderer; the scene's is
    raised above it, so the legend hides nothing), in the largest font (at most 1/34 of the
    height) in which it fits 96 % of the width. Returns its box (xmin, xmax, ymin, ymax) px
    from the lower left."""
    from vtkmodules.vtkRenderingCore import vtkRenderer

    strip = vtkRenderer()
    strip.SetBackground(1.0, 1.0, 1.0)
    pl.ren_win.AddRenderer(strip)
    legend = pv.Text(LEGEND)
    legend.prop.color, legend.prop.justification_vertical = "black", "bottom"
    strip.AddActor(legend)
    box = np.zeros(4)
    for font in range(max(6, size[1] // 34), 4, -1):
        legend.prop.font_size = font
        legend.GetBoundingBox(strip, box)
        if box[1] - box[0] <= 0.96 * size[0]:
            break
    height = (box[3] - box[2] + 6) / size[1]  # of the picture
    strip.SetViewport(0.0, 0.0, 1.0, height)
    pl.renderer.SetViewport(0.0, height, 1.0, 1.0)
    legend.SetPosition(0.01 * size[0], 3.0)
    legend.GetBoundingBox(strip, box)
    return (box[0] + 0.01 * size[0], box[1] + 0.01 * size[0], box[2] + 3.0, box[3] + 3.0)


def animate(
    nodes: np.ndarray,
    time: np.ndarray,
    pressure: np.ndarray,
    terrain: Terrain,
    path: str | Path,
    *,
    goal: ArrayLike | None = None,
    label: str = "",
    fps: int = 10,
    speed: float = 8.0,
    size: tuple[int, int] = (640, 480),
    unit: str = "MPa",
) -> dict:
    """An animation (GIF) of a run: the robot rolling over its terrain toward the goal, the
    CoG track so far, and in each frame's title `label`, the time and the pressures applied.
    The meshes and the title are built once and changed in place, so a frame costs one
    render; every frame is mapped to one palette (made from the first frame and the scene's
    colours) instead of being quantized on its own, and the GIF is written to a temporary file
    in the same folder and renamed, so a run killed midway leaves no file at `path`.

    nodes: (T, 12, 3) world, m; time: (T,) s, increasing; pressure: (T, 12) MPa per pair (V
    with unit "V": the twisted strings' motor voltages);
    goal: (3,) world, m (None or NaN: none); label: e.g. "run 'paper'"; fps: frames per
    second; speed: playback speed relative to simulated time; size: (width, height) px.
    A legend in a strip under the scene names the track, the goal and the robot's colours.
    Returns {"path", "frames", "fps", "legend" (its text), "legend_box" (xmin, xmax, ymin,
    ymax) px from the lower left}.
    """
    from PIL import Image

    if not (fps >= 1 and speed > 0):
        raise ValueError(f"fps must be >= 1 and speed > 0, got {fps!r}, {speed!r}")
    nodes, cog = check_run(nodes)
    t, pres = np.asarray(time, float), np.asarray(pressure, float)
    if t.shape != (len(nodes),) or pres.shape != (len(nodes), topo.N_PAIRS):
        raise ValueError(
            f"time {t.shape} and pressure {pres.shape} must be ({len(nodes)},) "
            f"and ({len(nodes)}, 12) for {len(nodes)} samples"
        )
    goal = goal_or_none(goal)
    frames = np.unique(np.clip(np.searchsorted(t, np.arange(t[0], t[-1] + 1e-9, speed / fps)), 0, len(t) - 1))
    centre, extent = area_shown(cog, goal)
    pl = plotter(None, size=size)
    for r in pl.renderers:  # smoothing costs time in software and shows little in a GIF
        r.UseFXAAOff()
    ground = terrain_mesh(terrain, centre, extent)
    pl.add_mesh(ground, color="#cfc8b4", name="terrain")  # one colour: a small GIF
    if terrain.kind == "heightfield":
        pl.add_mesh(ground.extract_all_edges(), color="#8a8270", name="terrain grid")
    if goal is not None:
        pl.add_mesh(pv.Sphere(radius=0.05, center=goal + [0, 0, 0.02]), color=GOAL, name="goal")

    def segments(seg: np.ndarray) -> pv.PolyData:  # lines only: one cell per segment
        return pv.PolyData(nodes[frames[0]].copy(), lines=np.hstack([np.full((len(seg), 1), 2), seg]).ravel())

    robot_struts, cables = segments(topo.STRUTS), segments(topo.CABLES)
    robot_struts.cell_data["strut"] = np.arange(topo.N_STRUTS)
    trail = np.repeat(cog[frames[0]][None] + [0, 0, 0.02], len(frames), axis=0)
    track = pv.lines_from_points(trail.copy())
    pl.add_mesh(
        robot_struts,
        scalars="strut",
        cmap=STRUT_COLOURS,
        show_scalar_bar=False,
        render_lines_as_tubes=True,
        line_width=9,
        name="struts",
    )
    pl.add_mesh(cables, color=CABLE_COLOUR, render_lines_as_tubes=True, line_width=2, name="cables")
    pl.add_mesh(track, color=PATH, line_width=3, name="track")
    oblique_camera(pl, centre, cog, 2.4 * extent)
    pl.renderer.ResetCameraClippingRange()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    head = f"{label}  " if label else ""
    titles = []
    for i in frames:
        act = ", ".join(f"#{k + 1} {pres[i, k]:.1f} {unit}" for k in np.flatnonzero(pres[i] > 0)) or "released"
        titles.append(f"{head}t = {t[i]:5.1f} s ({speed:g}x)  {act}")
    title = _title(pl, max(titles, key=len), size[0])
    legend_box = _legend(pl, size)
    # The palette: the robot's, track's and goal's colours in four shades (the tubes are lit),
    # then the rest of the first frame's colours (mostly the terrain), 256 in all.
    key = np.array([[int(c[k : k + 2], 16) for k in (1, 3, 5)] for c in [*STRUT_COLOURS, CABLE_COLOUR, GOAL]], float)
    shades = np.vstack(
        [key * f for f in (0.45, 0.7, 1.0)] + [key + 0.35 * (255 - key)] + [[[0, 0, 0], [255, 255, 255]]]
    )
    shades = np.clip(np.rint(shades), 0, 255).astype(np.uint8)
    palette, images = None, []
    for n, i in enumerate(frames):
        robot_struts.points = nodes[i]
        cables.points = nodes[i]
        trail[n:] = cog[i] + [0, 0, 0.02]
        track.points = trail
        title.input = titles[n]
        pl.render()
        rgb = np.ascontiguousarray(pl.screenshot(return_img=True)[..., :3])
        if palette is None:
            rest = Image.fromarray(rgb).quantize(256 - len(shades), method=Image.Quantize.MEDIANCUT)
            colours = np.vstack([shades, np.reshape(rest.getpalette()[: 3 * (256 - len(shades))], (-1, 3))]).astype(
                np.uint8
            )
            palette = Image.new("P", (1, 1))
            palette.putpalette(colours.ravel().tolist())
        images.append(Image.fromarray(rgb).quantize(palette=palette, dither=Image.Dither.NONE))
    pl.close()
    with atomic(path) as tmp:
        images[0].save(tmp, format="GIF", save_all=True, append_images=images[1:], duration=1000.0 / fps, loop=0)
    return {"path": str(path), "frames": len(frames), "fps": fps, "legend": LEGEND, "legend_box": legend_box}
