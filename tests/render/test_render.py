"""The paper's figures (render.paper, docs/design.md §7): the scene's contents and that each PNG
is a real, non-blank picture of the expected size. Synthetic inputs keep the file fast (a few s)."""

import numpy as np
import pytest
import pyvista as pv
from matplotlib.colors import rgb_to_hsv

from tensegrity.physics import frames
from tensegrity.physics import topology as topo
from tensegrity.render import cog_cloud, face_workspace, plot2d
from tensegrity.render import paper as render
from tensegrity.render.scene import AXIS_COLOURS, PAIR_COLOURS, STRUT_COLOURS, WINDOW


def _pixels(path) -> np.ndarray:
    """(rows, columns, 3) uint8 pixels of a PNG, read with VTK's PNG reader."""
    img = pv.read(str(path))
    w, h, _ = img.dimensions
    return np.asarray(img.point_data.active_scalars)[:, :3].reshape(h, w, 3)


def _check_png(path, min_colours: int = 30) -> np.ndarray:
    px = _pixels(path)
    assert px.shape == (WINDOW[1], WINDOW[0], 3)
    assert px.std() > 15  # far from blank
    assert (px.min(axis=2) < 200).mean() > 0.01  # >1 % of the picture is drawn, not white
    assert (px == 255).all(axis=2).mean() > 0.3  # the background is white
    assert len(np.unique(px.reshape(-1, 3), axis=0)) >= min_colours
    return px


def _has_colour(px, hex_colour: str, count: int = 50, tol: float = 0.025) -> bool:
    """At least `count` saturated pixels of the colour's hue (shading changes brightness and
    saturation, not hue)."""
    rgb = np.array([int(hex_colour[i : i + 2], 16) for i in (1, 3, 5)]) / 255
    hsv = rgb_to_hsv(px.reshape(-1, 3) / 255)
    dh = np.abs(hsv[:, 0] - rgb_to_hsv(rgb)[0])
    dh = np.minimum(dh, 1 - dh)
    return int(((dh < tol) & (hsv[:, 1] > 0.35) & (hsv[:, 2] > 0.2)).sum()) >= count


@pytest.fixture(scope="module")
def nodes():
    """The reference robot turned and moved, so no figure relies on the reference pose."""
    rot = np.array([[0.0, -1.0, 0.0], [0.6, 0.0, -0.8], [0.8, 0.0, 0.6]])
    return topo.reference_nodes(0.5) @ rot.T + [1.0, -2.0, 0.3]


def test_fig1_robot_has_six_struts_24_cables_and_12_numbered_nodes(tmp_path, nodes):
    out = render.fig_robot(nodes, tmp_path / "fig1.png")
    assert out["path"] == str(tmp_path / "fig1.png")
    assert out["size"] == WINDOW and out["title"].startswith("Fig. 1")
    assert out["struts"] == 6 and out["cables"] == 24
    assert out["node_labels"] == [str(n) for n in range(1, 13)]
    assert out["highlighted"] == {} and out["pair_labels"] == [] and out["shifted"] == []
    struts = [a for a in out["actors"] if a.startswith("strut ")]
    assert sorted(struts) == sorted(f"strut {a + 1}-{b + 1}" for a, b in topo.STRUTS)
    assert {"cables", "nodes", "node labels"} <= set(out["actors"])
    px = _check_png(out["path"])
    assert all(_has_colour(px, c) for c in STRUT_COLOURS)  # one colour per strut


def test_fig1_is_deterministic(tmp_path, nodes):
    a = render.fig_robot(nodes, tmp_path / "a.png")["path"]
    b = render.fig_robot(nodes, tmp_path / "b.png")["path"]
    np.testing.assert_array_equal(_pixels(a), _pixels(b))


def test_fig4_highlights_the_pairs_cables_and_labels_them(tmp_path, nodes):
    pairs = [9, 10, 12]
    out = render.fig_robot(nodes, tmp_path / "fig4.png", highlight_pairs=pairs)
    assert out["title"].startswith("Fig. 4")
    assert out["struts"] == 6 and out["cables"] == 24
    assert out["highlighted"] == {v: topo.PAIR_CABLES[v - 1].tolist() for v in pairs}
    assert out["pair_labels"] == ["#9", "#10", "#12"]
    assert {f"pair #{v}" for v in pairs} <= set(out["actors"])
    # each pair's cables are the two cables at node v
    for v in pairs:
        assert all(v - 1 in topo.CABLES[c] for c in out["highlighted"][v])
    # 9-10 (#10) and 10-12 (#12) leave node 10 almost together on screen: drawn side by side
    assert [tuple(topo.CABLES[c] + 1) for c in out["shifted"]] == [(9, 10), (10, 12)]
    # each "#v" sits on one of its own pair's cables, 25-55 % of the way from node v
    for v in pairs:
        q = out["pair_label_positions"][v]
        dist = []
        for a, b in topo.CABLES[out["highlighted"][v]]:
            e = nodes[b] - nodes[a]
            t = np.clip(np.dot(q - nodes[a], e) / np.dot(e, e), 0, 1)
            dist.append(np.linalg.norm(nodes[a] + t * e - q))
        assert min(dist) < 1e-9
        assert 0.2 * 0.5 < np.linalg.norm(q - nodes[v - 1]) < 0.6 * 0.5 * 1.1
    px = _check_png(out["path"])
    for v in pairs:
        assert _has_colour(px, PAIR_COLOURS[v - 1]), f"pair #{v} colour not drawn"


def test_fig_robot_rejects_bad_input(tmp_path, nodes):
    with pytest.raises(ValueError, match="pair"):
        render.fig_robot(nodes, tmp_path / "x.png", highlight_pairs=[13])
    with pytest.raises(ValueError, match="12, 3"):
        render.fig_robot(nodes[:11], tmp_path / "x.png")
    assert not (tmp_path / "x.png").exists()


def test_fig5_support_frame(tmp_path, nodes):
    out = render.fig_support_frame(nodes, (9, 10, 12), tmp_path / "fig5.png")
    assert out["face"] == topo.face_number((9, 10, 12))
    assert sorted(out["corners"]) == [9, 10, 12]
    R, o = out["axes"], out["origin"]
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-12)
    assert np.dot(R[2], nodes.mean(axis=0) - o) > 0  # z points into the robot
    ref = nodes[topo.FACES[out["face"] - 1][topo.FACE_REFERENCE[out["face"] - 1]]]
    assert np.dot(R[1], ref - o) > 0  # y toward the reference vertex
    assert {"axis x", "axis y", "axis z", "axis labels", "support triangle", "corner labels", "cog"} <= set(
        out["actors"]
    )
    assert len([a for a in out["actors"] if a.startswith("strut ")]) == 6
    px = _check_png(out["path"])
    for c in AXIS_COLOURS.values():
        assert _has_colour(px, c, count=20)


def _staircase_cloud(levels, per_level=200):
    """A CoG path stepping toward an edge with a decaying wobble at each level, m."""
    n = len(levels)
    nominal = np.column_stack([0.01 * np.arange(1, n + 1), -0.015 * np.arange(1, n + 1), np.full(n, 0.2)])
    t = np.linspace(0, 1, per_level)
    wobble = 0.003 * np.exp(-5 * t)[:, None] * np.column_stack([np.cos(40 * t), np.sin(40 * t)])
    samples = np.concatenate([np.column_stack([m[:2] + wobble, np.full(per_level, m[2])]) for m in nominal])
    pressure = np.repeat(levels, per_level)
    return samples, nominal, pressure


def _triangle(side=0.306):
    r = side / np.sqrt(3)
    ang = np.radians([90, 210, 330])
    return np.column_stack([r * np.cos(ang), r * np.sin(ang), np.zeros(3)])


def test_fig6_cog_cloud(tmp_path):
    levels = np.round(0.4 * np.arange(1, 7), 2)
    samples, nominal, pressure = _staircase_cloud(levels)
    out = cog_cloud.fig_cog_cloud(
        samples,
        nominal,
        levels,
        _triangle(),
        tmp_path / "fig6.png",
        pair=10,
        face_label="(9,10,12)",
        sample_pressure=pressure,
        corner_labels=[9, 12, 10],
    )
    assert out["title"].startswith("Fig. 6") and "#10" in out["title"]
    assert out["samples"] == len(samples) and out["nominal"] == 6
    assert out["labels"] == ["0.4 MPa", "0.8 MPa", "1.2 MPa", "1.6 MPa", "2 MPa", "2.4 MPa"]
    # the labels written beside the markers: the first and the last, none left overlapping
    assert out["labelled"][0] == "0.4 MPa" and out["labelled"][-1] == "2.4 MPa"
    assert set(out["labelled"]) <= set(out["labels"])
    assert out["support_edges"] >= 1  # the edge the CoG heads for is in view
    x0, x1, y0, y1 = out["view_mm"]  # the whole cloud is in the main view
    assert x0 <= 1e3 * samples[:, 0].min() and 1e3 * samples[:, 0].max() <= x1
    assert y0 <= 1e3 * samples[:, 1].min() and 1e3 * samples[:, 1].max() <= y1
    assert x1 - x0 < 200  # zoomed on the cloud, not the ~300 mm triangle
    assert {"cog samples", "nominal labels", "legend", "context triangle fill"} <= set(out["actors"])
    assert len([a for a in out["actors"] if a.startswith("nominal ring")]) == 6
    px = _check_png(out["path"])
    for c in cog_cloud.level_colours(6)[[0, -1]]:
        assert _has_colour(px, "#" + "".join(f"{int(round(255 * v)):02x}" for v in c))


def test_fig6_rejects_mismatched_pressures(tmp_path):
    levels = np.array([0.4, 0.8])
    samples, nominal, pressure = _staircase_cloud(levels, per_level=10)
    with pytest.raises(ValueError, match="sample_pressure"):
        cog_cloud.fig_cog_cloud(
            samples, nominal, levels, _triangle(), tmp_path / "x.png", 10, "(9,10,12)", sample_pressure=pressure[:-1]
        )
    with pytest.raises(ValueError, match="nominal"):
        cog_cloud.fig_cog_cloud(samples, nominal[:1], levels, _triangle(), tmp_path / "x.png", 10, "(9,10,12)")


def test_fig7_workspace(tmp_path):
    tri = _triangle()
    curves, tips = {}, {}
    for v in range(1, 13):
        reach = 0.1 if v in (9, 10, 12) else 0.05 if v in (4, 6, 7) else 0.01
        ang = np.radians(30 * v)
        s = np.linspace(0, 1, 13)[:, None]
        curves[v] = np.column_stack([reach * s * np.cos(ang), reach * s * np.sin(ang), 0.2 - 0.01 * s])
        tips[v] = curves[v][8] if v in (9, 10, 12) else None
    # the deformed support each ring is judged against: shrunk so that the ring is on it
    deformed = {}
    for v in (9, 10, 12):
        q = tips[v][:2]
        shrink = 1.0 - (
            frames.edge_distances(q, tri[:, :2]).min() / frames.edge_distances(np.zeros(2), tri[:, :2]).min()
        )
        deformed[v] = tri * shrink
    out = face_workspace.fig_workspace(
        curves,
        tri,
        tmp_path / "fig7.png",
        "Fig. 7 test",
        tip_points=tips,
        corner_labels=[9, 12, 10],
        tip_supports=deformed,
    )
    for v in (9, 10, 12):
        np.testing.assert_allclose(out["tip_points"][v], 1e3 * tips[v][:2])
        np.testing.assert_allclose(out["tip_supports"][v], 1e3 * deformed[v][:, :2])
        assert abs(frames.margin_2d(out["tip_points"][v], out["tip_supports"][v])) < 1e-6
        assert frames.margin_2d(out["tip_points"][v], 1e3 * tri[:, :2]) > 1.0  # inside the filled one
        assert f"tip support #{v}" in out["actors"]
    assert out["legend"][-2:] == ["CoG leaves dashed triangle", "- - deformed, at tipping"]
    assert out["title"] == "Fig. 7 test"
    assert out["cog_paths"] == {v: 13 for v in range(1, 13)}
    assert out["tips"] == [9, 10, 12]
    assert set(out["labels"]) == {f"#{v}" for v in (4, 6, 7, 9, 10, 12)}
    assert set(out["zoom_labels"]) == {f"#{v}" for v in range(1, 13)}
    assert 10 < out["zoom_mm"] < 50
    assert {f"curve #{v}" for v in range(1, 13)} <= set(out["actors"])
    assert {"legend", "corner labels", "tip #9", "zoom box"} <= set(out["actors"])
    x0, x1, y0, y1 = out["view_mm"]  # the whole triangle is in view
    assert x0 <= 1e3 * tri[:, 0].min() and 1e3 * tri[:, 0].max() <= x1
    assert y0 <= 1e3 * tri[:, 1].min() and 1e3 * tri[:, 1].max() <= y1
    px = _check_png(out["path"])
    for v in (9, 10, 12):
        assert _has_colour(px, PAIR_COLOURS[v - 1])


def test_fig7_rejects_unknown_pair(tmp_path):
    with pytest.raises(ValueError, match="pair"):
        face_workspace.fig_workspace({13: np.zeros((3, 3))}, _triangle(), tmp_path / "x.png", "t")
    with pytest.raises(ValueError, match="empty"):
        face_workspace.fig_workspace({}, _triangle(), tmp_path / "x.png", "t")


def test_fig7_curves_drop_sub_pixel_segments():
    """Wide VTK lines of segments shorter than a pixel drew stripes at the curves' ends."""
    c = np.column_stack([np.r_[np.linspace(0, 10, 11), 10 + np.geomspace(1e-3, 0.5, 30)], np.zeros(41), np.zeros(41)])
    thin = plot2d.drop_close_points(c, 1.0)
    steps = np.linalg.norm(np.diff(thin[:, :2], axis=0), axis=1)
    assert np.all(steps >= 0.5 - 1e-12) and np.array_equal(thin[-1], c[-1])
    assert np.array_equal(thin[0], c[0]) and len(thin) < 15


def test_values_at_a_pressure_skip_nan_levels():
    levels = np.array([1.0, 2.0, 3.0])
    values = np.array([[0.0, 0.0], [1.0, 2.0], [np.nan, np.nan]])
    np.testing.assert_allclose(face_workspace.at_pressure(levels, values, 1.5), [0.5, 1.0])
    np.testing.assert_allclose(face_workspace.at_pressure(levels, values, 2.5), [1.0, 2.0])  # held
    assert np.isnan(face_workspace.at_pressure(levels, np.full((3, 2), np.nan), 1.0)).all()
