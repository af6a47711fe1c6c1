"""render.locomotion (Figs. 8-10), render.runs (path) and render.animation (GIF), drawn from
arrays: the robot is the reference robot set down on a face, moved along x for a synthetic run."""

import imageio.v2 as imageio
import numpy as np
import pytest

from tensegrity.physics import frames
from tensegrity.physics import topology as topo
from tensegrity.physics.terrain import Terrain
from tensegrity.render import animation, locomotion, runs

EQUI = topo.face_number(topo.CONTACT_FACES["equilateral"])
ISO = topo.face_number(topo.CONTACT_FACES["isosceles"])


def _png_ok(path, spread: float = 20.0):
    img = imageio.imread(path)
    assert img.shape[:2] == (900, 1200) and img[..., :3].std() > spread  # not blank


@pytest.fixture(scope="module")
def standing():
    """The reference robot (S = 0.5 m) resting on face (9,10,12) of flat ground, (12, 3) m."""
    ref = topo.reference_nodes(0.5)
    return frames.to_frame(ref, *frames.face_frame(ref, EQUI))


def test_stable_and_rolling_states(tmp_path, standing):
    out = locomotion.fig_state(standing, Terrain.flat(), EQUI, tmp_path / "fig8.png", "stable", arrow=[1.0, 0.0, 0.0])
    assert out["stands"] and out["edge"] is None and out["margin"] == pytest.approx(0.0884, abs=1e-4)
    assert {"cog", "cog projection", "gravity line", "support triangle", "target arrow", "inset projection"} <= set(
        out["actors"]
    )
    _png_ok(out["path"])
    tipped = standing.copy()  # the upper nodes shifted over edge 10-12
    up = np.setdiff1d(np.arange(12), topo.FACES[EQUI - 1])
    tipped[up, :2] += 1.3 * (standing[[9, 11]].mean(0) - standing.mean(0))[:2] * 12 / 9
    out = locomotion.fig_state(tipped, Terrain.flat(), EQUI, tmp_path / "fig9.png", "rolling")
    assert not out["stands"] and out["edge"] == (10, 12) and out["next_face"] == ISO
    assert out["margin"] == pytest.approx(-0.3 * 0.0884, abs=1e-3)
    assert {"rolling arrow", "inset arrow"} <= set(out["actors"])
    _png_ok(out["path"])


def test_slope_state(tmp_path, standing):
    angle = np.radians(10.0)
    rot = np.array([[np.cos(angle), 0, -np.sin(angle)], [0, 1, 0], [np.sin(angle), 0, np.cos(angle)]])
    terrain = Terrain.slope(10.0)
    nodes = standing @ rot.T
    assert np.allclose(terrain.normal, rot[:, 2]), "the slope rises toward +x"
    out = locomotion.fig_slope(nodes, terrain, EQUI, tmp_path / "fig10.png", "slope")
    assert out["angle"] == pytest.approx(10.0, abs=1e-6) and out["margin"] > 0
    h = float(standing.mean(0)[2])
    assert out["shift"] == pytest.approx(h * np.tan(angle), rel=1e-6)
    assert {"normal line", "normal projection", "inset normal projection"} <= set(out["actors"])
    _png_ok(out["path"])


def test_state_figures_reject_bad_nodes(tmp_path, standing):
    with pytest.raises(ValueError, match="12, 3"):
        locomotion.fig_state(standing[:11], Terrain.flat(), EQUI, tmp_path / "x.png", "t")
    assert not (tmp_path / "x.png").exists()


@pytest.fixture(scope="module")
def run(standing):
    """A synthetic run: the robot slides 0.6 m along x in 40 samples of 0.1 s, pair #10 at
    1 MPa; two steps ending at samples 19 and 39, settled on (9,10,12) then none."""
    x = np.linspace(0.0, 0.6, 40)
    nodes = standing[None] + x[:, None, None] * np.array([1.0, 0.0, 0.0])
    pressure = np.zeros((40, 12))
    pressure[:, 9] = 1.0
    return {
        "nodes": nodes,
        "time": 0.1 * np.arange(1, 41),
        "pressure": pressure,
        "faces": np.array([EQUI, 0]),
        "step_end": np.array([19, 39]),
        "goal": np.array([1.0, 0.2, 0.0]),
    }


@pytest.mark.parametrize("view", ["top", "3d"])
def test_path_of_a_run(tmp_path, run, view):
    out = runs.fig_path(
        run["nodes"],
        Terrain.flat(),
        tmp_path / "p.png",
        "a run",
        faces=run["faces"],
        step_end=run["step_end"],
        goal=run["goal"],
        view=view,
    )
    assert out["contacts"] == 1 and out["view"] == view and out["title"] == "a run"
    assert {"cog track", "contact 1", "start", "goal", "arrival circle", "robot at the end strut 1-3"} <= set(
        out["actors"]
    )
    assert "contact 2" not in out["actors"]
    assert ("scale bar" in out["actors"]) == (view == "top")
    assert ("robot at the start cables" in out["actors"]) == (view == "3d")
    _png_ok(out["path"], spread=10.0)  # mostly ground


def test_3d_path_shows_all_of_its_ground(tmp_path, run):
    """The 3D view was clipped at the top: the ground drawn now fits below the title."""
    out = runs.fig_path(
        run["nodes"],
        Terrain.slope(10.0),
        tmp_path / "p.png",
        " ",
        faces=run["faces"],
        step_end=run["step_end"],
        goal=run["goal"],
        view="3d",
    )
    img = imageio.imread(out["path"])[..., :3].astype(int)
    white = (img >= 250).all(axis=2)
    assert white[:60].all()  # the title strip (a blank title here) holds no ground
    assert white[:, 0].mean() > 0.5 and white[:, -1].mean() > 0.5  # nor reaches past the sides


def test_path_without_a_goal_and_bad_input(tmp_path, run):
    out = runs.fig_path(run["nodes"], Terrain.flat(), tmp_path / "p.png", "t", goal=np.full(3, np.nan))
    assert out["contacts"] == 0 and "goal" not in out["actors"]
    with pytest.raises(ValueError, match="view"):
        runs.fig_path(run["nodes"], Terrain.flat(), tmp_path / "x.png", "t", view="side")
    with pytest.raises(ValueError, match="differ in length"):
        runs.fig_path(run["nodes"], Terrain.flat(), tmp_path / "x.png", "t", faces=[8], step_end=[])
    with pytest.raises(ValueError, match=r"\(T, 12, 3\)"):
        runs.fig_path(run["nodes"][0], Terrain.flat(), tmp_path / "x.png", "t")


def test_animation_of_a_run(tmp_path, run):
    out = animation.animate(
        run["nodes"],
        run["time"],
        run["pressure"],
        Terrain.flat(),
        tmp_path / "run.gif",
        goal=run["goal"],
        label="run 'test'",
        fps=5,
        speed=2.0,
        size=(320, 240),
    )
    frames_ = imageio.mimread(out["path"])
    assert out["frames"] == len(frames_) == 10 and out["fps"] == 5
    assert frames_[0].shape[:2] == (240, 320)
    assert not np.array_equal(frames_[0], frames_[-1])  # the robot moved
    with pytest.raises(ValueError, match="pressure"):
        animation.animate(run["nodes"], run["time"], run["pressure"][:5], Terrain.flat(), tmp_path / "x.gif")
    with pytest.raises(ValueError, match="fps"):
        animation.animate(run["nodes"], run["time"], run["pressure"], Terrain.flat(), tmp_path / "x.gif", fps=0)


def test_track_thinned_within_tolerance():
    """The drawn CoG track keeps its ends and passes within the tolerance of every sample."""
    rng = np.random.default_rng(0)
    s = np.linspace(0.0, 2.0, 3000)
    track = np.column_stack([s, 0.1 * np.sin(5 * s), 0.02 * np.cos(40 * s)])
    track += 1e-4 * rng.normal(size=track.shape)
    keep = runs.rdp_indices(track, 1e-3)
    assert keep[0] == 0 and keep[-1] == len(track) - 1 and len(keep) < len(track) / 5
    a, b = track[keep[:-1]], track[keep[1:]]  # distance of every sample to the drawn polyline
    t = np.clip(np.einsum("nkj,kj->nk", track[:, None] - a, b - a) / np.sum((b - a) ** 2, 1), 0, 1)
    gap = np.linalg.norm(track[:, None] - (a + t[..., None] * (b - a)), axis=-1).min(axis=1)
    assert gap.max() <= 1e-3
    track[5] = np.nan  # a failed run: drawn as it is
    assert len(runs.rdp_indices(track, 1e-3)) == len(track)
