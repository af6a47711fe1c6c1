"""render.scene, render.plot2d and render.terrain: the shared plumbing (off-screen set-up, the
PNG writer), the 2-D helpers of the support-frame plots and the terrain mesh."""

import os
import subprocess
import sys

import numpy as np
import pytest

from tensegrity.physics import topology as topo
from tensegrity.render import plot2d, scene


def test_importing_the_figures_changes_no_process_setting_until_a_plotter_is_made():
    code = (
        "import os\n"
        "from tensegrity.render import animation, cog_cloud, face_workspace, locomotion, paper, runs, scene\n"
        "before = os.environ.get('VTK_DEFAULT_OPENGL_WINDOW')\n"
        "scene.plotter('t').close()\n"
        "print(before, os.environ.get('VTK_DEFAULT_OPENGL_WINDOW'))\n"
    )
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY", "VTK_DEFAULT_OPENGL_WINDOW")}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["None", "vtkEGLRenderWindow"]
    assert "bad X server" not in out.stderr


def test_finish_writes_the_png_and_reports_the_named_actors(tmp_path):
    nodes = topo.reference_nodes(0.5)
    pl = scene.plotter("a robot")
    scene.robot(pl, nodes, name="r")
    out = scene.finish(pl, tmp_path / "sub" / "r.png", "a robot", extra=1)
    assert (tmp_path / "sub" / "r.png").stat().st_size > 1000
    assert out["size"] == scene.WINDOW and out["title"] == "a robot" and out["extra"] == 1
    assert {f"r strut {a + 1}-{b + 1}" for a, b in topo.STRUTS} | {"r cables"} <= set(out["actors"])
    assert scene.strut_length(nodes) == pytest.approx(0.5)


def test_clipping_to_a_box():
    box = (0.0, 1.0, 0.0, 1.0)
    tri = np.array([[-1.0, 0.5], [2.0, 0.5], [0.5, 2.0]])
    poly = plot2d.clip_polygon(tri, box)
    assert np.all(poly >= -1e-12) and np.all(poly <= 1 + 1e-12) and len(poly) >= 4
    assert len(plot2d.clip_polygon(tri + 10, box)) == 0
    a, b = plot2d.clip_segment([-1.0, 0.5], [2.0, 0.5], box)
    np.testing.assert_allclose([a, b], [[0.0, 0.5], [1.0, 0.5]])
    assert plot2d.clip_segment([-1.0, 2.0], [2.0, 2.0], box) is None
    assert plot2d.segment_distance(np.array([0.5, 1.0]), np.zeros(2), np.array([1.0, 0.0])) == 1.0


def test_nice_box_has_round_ticks_around_the_data():
    box, nx, ny = plot2d.nice_box([-13.0, 2.0], [71.0, 48.0], n=5)
    assert box[0] <= -13 and box[1] >= 71 and box[2] <= 2 and box[3] >= 48
    step = (box[1] - box[0]) / (nx - 1)
    assert step in (10.0, 20.0, 50.0) and (box[3] - box[2]) / (ny - 1) == step


def test_terrain_mesh_of_a_height_field_is_cut_to_the_area_shown():
    from tensegrity.physics.terrain import Terrain
    from tensegrity.render import terrain

    t = Terrain(kind="heightfield", origin=np.array([-4.0, -4.0]), spacing=0.25, heights=np.zeros((33, 33)))
    mesh = terrain.terrain_mesh(t, (0.5, 0.3), 1.0)
    b = mesh.bounds
    assert b[0] >= -0.5 - 1e-9 and b[1] <= 1.5 + 1e-9 and b[2] >= -0.7 - 1e-9 and b[3] <= 1.3 + 1e-9
    assert "height (m)" in mesh.point_data and mesh.n_cells > 0
