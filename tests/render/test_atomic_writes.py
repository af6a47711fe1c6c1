"""Figures and the animation are written atomically: to a temporary file in the same folder,
then renamed. A render that fails or is killed while writing leaves no file at the final
path (nor a partial one over an earlier good file), and no temporary file after a failure."""

import os
import signal
import subprocess
import sys
import textwrap

import numpy as np
import pytest
from PIL import Image

from tensegrity.physics import topology as topo
from tensegrity.physics.terrain import Terrain
from tensegrity.render import animation, scene


def _run(n: int = 6) -> dict:
    nodes = topo.reference_nodes(0.5)[None] + np.linspace(0, 0.3, n)[:, None, None] * [1.0, 0, 0]
    return {"nodes": nodes, "time": 0.1 * np.arange(1, n + 1), "pressure": np.zeros((n, 12))}


def _png(path) -> dict:
    pl = scene.plotter("atomic")
    scene.robot(pl, topo.reference_nodes(0.5))
    return scene.finish(pl, path, "atomic")


def test_png_and_gif_leave_no_temporary_file(tmp_path):
    _png(tmp_path / "a.png")
    r = _run()
    animation.animate(
        r["nodes"], r["time"], r["pressure"], Terrain.flat(), tmp_path / "a.gif", fps=10, speed=1.0, size=(160, 120)
    )
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.gif", "a.png"]
    assert Image.open(tmp_path / "a.gif").n_frames == 6


def test_a_failed_png_write_leaves_nothing(tmp_path, monkeypatch):
    def broken(self, filename=None, *a, **k):  # half a file, then the disk is full
        with open(filename, "wb") as f:
            f.write(b"\x89PNG\r\n")
        raise OSError("no space left on device")

    monkeypatch.setattr(scene.pv.Plotter, "screenshot", broken)
    with pytest.raises(OSError, match="no space"):
        _png(tmp_path / "a.png")
    assert list(tmp_path.iterdir()) == []


def test_a_failed_gif_write_keeps_the_earlier_file(tmp_path, monkeypatch):
    r = _run()
    gif = tmp_path / "a.gif"
    gif.write_bytes(b"the earlier, complete animation")

    def broken(self, fp, *a, **k):
        with open(fp, "wb") as f:
            f.write(b"GIF89a")
        raise OSError("no space left on device")

    monkeypatch.setattr(Image.Image, "save", broken)
    with pytest.raises(OSError, match="no space"):
        animation.animate(r["nodes"], r["time"], r["pressure"], Terrain.flat(), gif, fps=10, speed=1.0, size=(160, 120))
    assert [p.name for p in tmp_path.iterdir()] == ["a.gif"]
    assert gif.read_bytes() == b"the earlier, complete animation"


@pytest.mark.parametrize("kind", ["png", "gif"])
def test_a_render_killed_while_writing_leaves_no_file_at_the_final_path(tmp_path, kind):
    """SIGKILL at the moment the file is complete but not yet renamed: the worst case."""
    out = tmp_path / f"fig.{kind}"
    code = textwrap.dedent(f"""
        import os, signal
        os.replace = lambda *a: os.kill(os.getpid(), signal.SIGKILL)
        import numpy as np
        from tensegrity.physics import topology as topo
        from tensegrity.physics.terrain import Terrain
        from tensegrity.render import animation, scene
        nodes = topo.reference_nodes(0.5)
        if {kind!r} == "png":
            pl = scene.plotter("killed")
            scene.robot(pl, nodes)
            scene.finish(pl, {str(out)!r}, "killed")
        else:
            animation.animate(np.stack([nodes] * 3), np.arange(1.0, 4.0), np.zeros((3, 12)),
                         Terrain.flat(), {str(out)!r}, fps=1, speed=1.0, size=(160, 120))
    """)
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert r.returncode == -signal.SIGKILL, r.stderr[-2000:]
    assert not out.exists()
    left = [p.name for p in tmp_path.iterdir()]  # only the hidden temporary file, complete
    assert len(left) == 1 and left[0].startswith(".fig.") and left[0].endswith(f".tmp.{kind}")
    assert os.path.getsize(tmp_path / left[0]) > 0
