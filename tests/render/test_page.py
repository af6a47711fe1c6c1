"""render.page: the interactive 3D page. Its contents from arrays (the robot in the support
frame of its face, the pieces of each contact case and run, the menus), its bytes, and the page
itself in a real headless browser: Debian's Chromium driven by Playwright (`.ci/run` installs
Chromium; without it the browser test fails, it does not skip)."""

import shutil

import numpy as np
import pytest

from tensegrity.physics import frames
from tensegrity.physics import topology as topo
from tensegrity.physics.terrain import Terrain
from tensegrity.render import page
from tensegrity.render.scene import STRUT_COLOURS

FACE = 8  # (9,10,12), the equilateral contact case
LENGTH = 0.5  # m


def _workspace(pairs=(9, 10, 12), samples=3000) -> page.Workspace:
    """The unactuated robot on face 8 in its support frame, and for each pair a made-up CoG
    path: a straight curve from the unactuated CoG, samples along it as a sweep makes them (1 kHz,
    three pressure steps, each followed by a decaying 2 mm oscillation), nominal CoGs on it."""
    nodes = topo.reference_nodes(LENGTH)
    nodes = frames.to_frame(nodes, *frames.face_frame(nodes, FACE))
    rest_cog, support = frames.rest_frame(FACE, LENGTH)
    t = np.arange(samples) * 1e-3  # s
    hold = t[-1] / 3 + 1e-9
    level, since = np.floor(t / hold) + 1, t % hold
    s = (level - np.exp(-since / 0.05)) / 3  # fraction of the way along the curve
    wobble = 0.002 * np.exp(-since / 0.3) * np.sin(2 * np.pi * 5 * since)  # m
    curves, clouds, nominal = {}, {}, {}
    for k, p in enumerate(pairs):
        d = np.array([np.cos(2.1 * k), np.sin(2.1 * k), -0.3]) * 0.06
        side = np.cross(d, [0, 0, 1.0]) / np.linalg.norm(np.cross(d, [0, 0, 1.0]))
        curves[p] = rest_cog + np.linspace(0, 1, 20)[:, None] * d
        clouds[p] = rest_cog + s[:, None] * d + wobble[:, None] * side
        nominal[p] = rest_cog + np.array([1, 2, 3])[:, None] / 3 * d
    return page.Workspace("equilateral", FACE, nodes, support, clouds, curves, nominal)


def _run() -> page.Run:
    """A made-up run on flat ground: the reference robot slid 0.4 m along x in 50 samples."""
    nodes = topo.reference_nodes(LENGTH)
    nodes = nodes - [0, 0, nodes[:, 2].min()]
    track = np.linspace(0, 0.4, 50)[:, None, None] * np.array([1.0, 0, 0])
    return page.Run("slide", "run 'slide'", nodes[None] + track, [8], [49], np.array([0.5, 0, 0]), Terrain.flat())


def test_the_robot_stands_on_its_face_in_the_support_frame():
    ws = _workspace()
    fig, groups = page.figure([ws], [], "t")
    struts = [fig["data"][i] for i in groups["robot"] if "strut" in fig["data"][i]["name"] or i == groups["robot"][0]]
    assert len(struts) == topo.N_STRUTS
    drawn = np.array([[t[a] for a in "xyz"] for t in struts], float).transpose(0, 2, 1) / page.MM  # (6, 2, 3) m
    ends = ws.nodes[topo.STRUTS]
    assert np.allclose(drawn, ends, atol=1e-6)
    # the face's three nodes on the ground plane z = 0, the other nine above it
    on = np.isin(np.arange(topo.N_NODES), topo.FACES[FACE - 1])
    assert np.allclose(ws.nodes[on, 2], 0.0, atol=1e-12) and (ws.nodes[~on, 2] > 0.05).all()
    assert np.allclose(np.sort(np.linalg.norm(np.diff(drawn, axis=1)[:, 0], axis=1)), LENGTH)


def test_a_cloud_is_thinned_to_within_its_tolerance_of_every_sample():
    cloud = _workspace(pairs=(10,)).clouds[10]
    drawn = page.thin(cloud)
    assert page.CLOUD_POINTS <= len(drawn) < len(cloud) / 2
    # the drawn rows are samples, in time order; every sample within CLOUD_TOLERANCE of the
    # segment between the drawn samples before and after it
    idx = np.array([np.flatnonzero((cloud == row).all(axis=1))[0] for row in drawn])
    assert (np.diff(idx) > 0).all() and idx[0] == 0 and idx[-1] == len(cloud) - 1
    k = np.searchsorted(idx, np.arange(len(cloud)), side="right") - 1
    a, b = cloud[idx[np.minimum(k, len(idx) - 2)]], cloud[idx[np.minimum(k + 1, len(idx) - 1)]]
    u = np.clip(np.sum((cloud - a) * (b - a), 1) / np.maximum(np.sum((b - a) ** 2, 1), 1e-30), 0, 1)
    assert np.linalg.norm(cloud - a - u[:, None] * (b - a), axis=1).max() <= page.CLOUD_TOLERANCE
    # evenly spaced alone would miss the fast move after each step by more than that
    even = np.linspace(0, len(cloud) - 1, page.CLOUD_POINTS).round().astype(int)
    assert not np.isin(idx, even).all()


def test_the_menus_switch_whole_groups_and_each_scene_gets_its_own():
    ws = _workspace()
    fig, groups = page.figure([ws, _workspace(pairs=(11,))], [_run()], "t")
    data = fig["data"]
    cloud = next(t for t in data if t["name"] == "#10 CoG samples")
    assert np.allclose(np.array([cloud[a] for a in "xyz"], float).T / page.MM, page.thin(ws.clouds[10]), atol=1e-9)
    seen = [(i in groups["workspace"][0] or i in groups["runs"][0]) for i in range(len(data))]
    assert [t["visible"] for t in data] == seen  # the first case and the first run are shown
    for menu, key in zip(fig["layout"]["updatemenus"], ("workspace", "runs")):
        for button, g in zip(menu["buttons"], groups[key]):
            vis, idx = button["args"]
            assert [i for i, v in zip(idx, vis["visible"]) if v] == list(g)
            assert set(idx) == {i for gg in groups[key] for i in gg}
    scenes = {t["scene"] for t in data[slice(groups["runs"][0][0], None)]}
    assert scenes == {"scene2"}
    alone, _ = page.figure([ws], [], "t")  # no runs (locomotion.runs: []): the workspace takes the width
    assert "scene2" not in alone["layout"] and alone["layout"]["scene"]["domain"]["x"] == [0.1, 1.0]
    with pytest.raises(ValueError, match="at least one contact case or one run"):
        page.figure([], [], "t")


def test_a_run_on_a_slope_has_its_arrival_circle_on_the_slope():
    slope = Terrain.slope(10.0)
    run = _run()
    goal = np.array([0.5, 0.0, float(slope.height(0.5, 0.0))])
    fig, _ = page.figure([], [page.Run("up", "up", run.nodes, [], [], goal, slope)], "t")
    ring = next(t for t in fig["data"] if t["name"] == "arrival circle")
    pts = np.array([ring[a] for a in "xyz"], float).T
    centre = pts[:-1].mean(axis=0)
    assert np.allclose(np.linalg.norm(pts - centre, axis=1), 0.3, atol=1e-6)  # m, the arrival radius
    assert np.allclose((pts - centre) @ slope.normal_at(0.5, 0.0).reshape(3), 0.0, atol=1e-6)  # in the slope


def test_a_height_field_is_drawn_only_near_the_run():
    rough = Terrain.random(seed=1)  # 6 m square
    run = _run()
    fig, _ = page.figure([], [page.Run("r", "r", run.nodes, [], [], None, rough)], "t")
    ground = next(t for t in fig["data"] if t["name"] == "terrain")
    xy = np.array([ground["x"], ground["y"]], float).T
    used = np.unique(np.concatenate([ground[k] for k in "ijk"]))
    assert np.array_equal(used, np.arange(len(xy)))  # no vertex without a triangle (they set the view)
    cog = run.nodes.mean(axis=1)
    assert np.abs(xy - cog[:, :2].mean(axis=0)).max() < 1.0  # m: around the 0.4 m run, not the 6 m field
    assert np.allclose(ground["z"], rough.height(xy[:, 0], xy[:, 1]), atol=1e-6)


def test_the_page_is_one_file_with_its_script_and_the_same_bytes_each_time(tmp_path):
    a = page.write_page([_workspace()], [_run()], tmp_path / "a.html", "t")
    page.write_page([_workspace()], [_run()], tmp_path / "b.html", "t")
    html = (tmp_path / "a.html").read_bytes()
    assert html == (tmp_path / "b.html").read_bytes()
    assert len(html) > 3_000_000  # plotly.js is inside
    assert a["traces"][a["robot"][0]] == "robot (0 MPa)"


def _chromium() -> str:
    path = shutil.which("chromium") or shutil.which("chromium-browser")
    if path is None:
        pytest.fail("no Chromium: install Debian's package (apt-get install chromium; .ci/run does)")
    return path


def _strut_pixels(img: np.ndarray, tol: int = 40) -> list[int]:
    """Pixels of img (h, w, 3) within `tol` of each strut colour, per colour."""
    rgb = [np.array([int(c[i : i + 2], 16) for i in (1, 3, 5)]) for c in STRUT_COLOURS]
    return [int((np.abs(img.astype(int) - c).max(axis=-1) <= tol).sum()) for c in rgb]


def test_the_page_draws_the_robot_in_headless_chromium(tmp_path):
    """The page loads offline with no console error, draws its canvases, and the robot: hiding
    its traces changes many pixels of the left scene and takes away the struts' six colours."""
    import io

    from PIL import Image
    from playwright.sync_api import sync_playwright

    # pairs whose colours are far from the struts' (#2, #5, #8)
    out = page.write_page([_workspace(pairs=(2, 5, 8))], [_run()], tmp_path / "p.html", "t")
    size = (1200, 700)
    with sync_playwright() as pw:
        # software WebGL (SwiftShader): no GPU in CI
        browser = pw.chromium.launch(
            executable_path=_chromium(), args=["--use-angle=swiftshader", "--enable-unsafe-swiftshader"]
        )
        try:
            tab = browser.new_page(viewport=dict(zip(("width", "height"), size)))
            problems = []
            tab.on("console", lambda m: problems.append(m.text) if m.type == "error" else None)
            tab.on("pageerror", lambda e: problems.append(str(e)))
            fetched = []  # offline: the page asks for nothing but itself
            tab.route(
                "**/*",
                lambda r: (
                    r.continue_() if r.request.url.startswith("file:") else (fetched.append(r.request.url), r.abort())
                ),
            )
            tab.goto((tmp_path / "p.html").as_uri(), timeout=120_000)
            tab.wait_for_function(f"document.getElementById('{page.DIV_ID}')._fullLayout !== undefined", timeout=60_000)
            assert tab.evaluate("document.querySelectorAll('canvas').length") >= 2
            shots = [np.asarray(Image.open(io.BytesIO(tab.screenshot())).convert("RGB"))]
            tab.evaluate(f"Plotly.restyle('{page.DIV_ID}', {{visible: false}}, {out['robot']})")
            tab.wait_for_timeout(300)
            shots.append(np.asarray(Image.open(io.BytesIO(tab.screenshot())).convert("RGB")))
        finally:
            browser.close()
    for k, shot in enumerate(shots):
        Image.fromarray(shot).save(tmp_path / f"page{k}.png")
    assert not problems and not fetched, (problems, fetched)
    left = slice(int(0.1 * size[0]), int(0.5 * size[0]))  # the workspace scene's columns
    with_robot, without = shots[0][:, left], shots[1][:, left]
    assert with_robot.std() > 10  # not blank
    changed = np.abs(with_robot.astype(int) - without).max(axis=-1) > 30
    assert changed.sum() > 2000, changed.sum()
    gained = np.subtract(_strut_pixels(with_robot), _strut_pixels(without))
    assert (gained > 200).all(), gained  # each of the six struts, in its colour
