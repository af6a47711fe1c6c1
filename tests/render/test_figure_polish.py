"""Figure polish (issue 35, item 5): each test guards one defect seen in the default run's
figures, measured on the drawn figure (text boxes in pixels, marker extents, pixel colours)."""

import imageio.v2 as imageio
import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg

from tensegrity.physics import frames
from tensegrity.physics import topology as topo
from tensegrity.physics.terrain import Terrain
from tensegrity.render import animation, face_workspace, gravity, locomotion
from tensegrity.render.scene import WINDOW


def test_slope_limit_markers_at_0_deg_lie_inside_the_axes():
    """The gravity-aware grid says 0 deg where the robot cannot stand: those markers sat on
    the lower spine, cut in half."""
    headings = np.arange(0.0, 360.0, 45.0)
    simulated = np.full((3, 2, 8), 12.0)
    grid = np.tile(np.array([0.0, 10.0, 0.0, 20.0, 0.0, 15.0, 0.0, 38.0]), (3, 2, 1))
    fig = gravity.slope_limit_axes(
        ["stand", "uphill", "downhill"], ["equilateral", "isosceles"], headings, simulated, simulated, grid, 38.7, 5.0
    )
    FigureCanvasAgg(fig).draw()
    checked = 0
    for ax in fig.axes:
        box = ax.bbox
        for line in ax.get_lines():
            if line.get_marker() in ("None", "", None):
                continue
            r = (line.get_markersize() + line.get_markeredgewidth()) / 2 * fig.dpi / 72  # px
            xy = ax.transData.transform(np.column_stack(line.get_data()))
            assert (xy[:, 0] - r >= box.x0).all() and (xy[:, 0] + r <= box.x1).all()
            assert (xy[:, 1] - r >= box.y0).all(), f"a marker of {line.get_label()!r} is cut by the lower spine"
            assert (xy[:, 1] + r <= box.y1).all()
            checked += int((line.get_ydata() == 0).sum())
    assert checked == 2 * 3 * 4  # every 0 deg marker of both panels was measured


def test_slope_limit_draws_the_multi_actuator_limits_and_their_legend_clears_the_axes():
    """The limits with optimised actions of any set of pairs and with the 24 cables (issue 30)
    are drawn where they are computed (the cables on one panel only: named in the legend all
    the same); all-NaN ones (volts) are not; the four-row legend overlaps no axes' text."""
    headings = np.arange(0.0, 360.0, 45.0)
    lim = np.full((3, 2, 8), 12.0)
    multi = lim + 3.0
    cables = np.full((2, 8), np.nan)
    cables[1] = 25.0
    kinds, contacts = ["stand", "uphill", "downhill"], ["equilateral", "isosceles"]
    draw = lambda m, c: gravity.slope_limit_axes(kinds, contacts, headings, lim, lim, lim, 38.7, 5.0, multi=m, cables=c)  # noqa: E731
    fig = draw(multi, cables)
    FigureCanvasAgg(fig).draw()
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    assert "uphill: 24 cables one by one" in labels and "uphill: any set of pairs" in labels
    assert "stand: any set of pairs" not in labels  # the stand limit is the single pairs' own
    drawn = [line.get_label() for line in fig.axes[0].get_lines()]
    assert "uphill: 24 cables one by one" not in drawn  # all NaN on the equilateral panel
    legend = fig.legends[0].get_window_extent()
    for ax in fig.axes:
        for text in [ax.xaxis.label, *ax.get_xticklabels()]:
            assert not legend.overlaps(text.get_window_extent()), f"the legend covers {text.get_text()!r}"
    bare = draw(np.full_like(lim, np.nan), np.full((2, 8), np.nan))
    assert len(bare.legends[0].get_texts()) == 9  # volts: the nine lines of before


def _triangle(side=0.306):
    """An equilateral support triangle (3, 3) m around the origin."""
    ang = np.radians([90, 210, 330])
    return side / np.sqrt(3) * np.column_stack([np.cos(ang), np.sin(ang), np.zeros(3)])


def _overlaps(boxes: dict) -> list[tuple[str, str]]:
    """Pairs of names whose boxes (xmin, xmax, ymin, ymax) px share more than a pixel."""
    items = sorted(boxes.items())
    return [
        (a, b)
        for i, (a, p) in enumerate(items)
        for b, q in items[i + 1 :]
        if min(p[1], q[1]) - max(p[0], q[0]) > 1 and min(p[3], q[3]) - max(p[2], q[2]) > 1
    ]


@pytest.fixture(scope="module")
def fig7(tmp_path_factory):
    """Fig. 7 of twelve straight CoG curves: the reach of the paper's pairs."""
    curves = {}
    for v in range(1, 13):
        reach = 0.09 if v in (9, 10, 12) else 0.045 if v in (4, 6, 7) else 0.01
        s = np.linspace(0, 1, 9)[:, None]
        ang = np.radians(30 * v)
        curves[v] = np.column_stack([reach * s * np.cos(ang), reach * s * np.sin(ang), 0.2 - 0.01 * s])
    path = tmp_path_factory.mktemp("fig7") / "fig7.png"
    return face_workspace.fig_workspace(curves, _triangle(), path, "Fig. 7 test", corner_labels=[9, 12, 10])


def test_tick_labels_do_not_collide_at_the_corner(fig7):
    """The first x and y labels (-200 and -150 in the default run) were drawn over each other."""
    ticks = {n: b for n, b in fig7["text_boxes"].items() if n.startswith("tick label")}
    x0, x1, y0, y1 = fig7["view_mm"]
    assert {f"tick label x {x0:+.6g}", f"tick label y {y0:+.6g}", f"tick label x {x1:+.6g}"} <= set(ticks)
    assert len(ticks) >= 8
    assert _overlaps(ticks) == []
    assert _overlaps({**ticks, **{n: fig7["text_boxes"][n] for n in ("axis title x", "axis title y")}}) == []
    for b in fig7["text_boxes"].values():  # and nothing is cut by the picture's edges
        assert 0 <= b[0] and b[1] <= WINDOW[0] and 0 <= b[2] and b[3] <= WINDOW[1]


def _bar_px(png, label_box) -> int:
    """The longest run of dark pixels right of a scale bar's label (box in px from the lower
    left), on the rows of the label's middle: the bar as drawn, in px."""
    img = imageio.imread(png)[..., :3].astype(int)
    dark = (img < 70).all(axis=2)
    mid = img.shape[0] - int(round((label_box[2] + label_box[3]) / 2))
    best = 0
    for row in dark[mid - 3 : mid + 4, int(label_box[1]) :]:
        edges = np.flatnonzero(np.diff(np.r_[0, row.astype(int), 0]))
        best = max([best, *(edges[1::2] - edges[::2])])
    return best


def _check_scale_bar(out, name, panel):
    """The scale bar `name` is a round length, drawn as long as it says at the panel's scale,
    its label whole inside the panel (x0, x1, y0, y1 px from the lower left)."""
    bar = out["scale_bars"][name]
    mantissa = bar["length"] / 10 ** np.floor(np.log10(bar["length"]))
    assert np.isclose(mantissa, [1, 2, 5]).any()
    assert np.linalg.norm(bar["end"] - bar["start"]) == pytest.approx(bar["length"])
    box = out["text_boxes"][name + " label"]
    assert panel[0] <= box[0] and box[1] <= panel[1] and panel[2] <= box[2] and box[3] <= panel[3]
    assert abs(_bar_px(out["path"], box) - bar["length"] / bar["mm_per_px"]) <= 4  # end ticks: 3 px wide


EQUI = topo.face_number(topo.CONTACT_FACES["equilateral"])
INSET = (0.7 * WINDOW[0], WINDOW[0], 0.45 * WINDOW[1], 0.93 * WINDOW[1])  # the upper side panel, px


def test_zoom_inset_has_a_scale_bar(fig7):
    _check_scale_bar(fig7, "zoom scale bar", INSET)


@pytest.fixture(scope="module")
def rolling(tmp_path_factory):
    """Fig. 9 of the reference robot (S = 0.5 m) on face (9,10,12) of flat ground, its upper
    nodes shifted out over edge 10-12: it rolls."""
    ref = topo.reference_nodes(0.5)
    nodes = frames.to_frame(ref, *frames.face_frame(ref, EQUI))
    up = np.setdiff1d(np.arange(12), topo.FACES[EQUI - 1])
    nodes[up, :2] += 1.3 * (nodes[[9, 11]].mean(0) - nodes.mean(0))[:2] * 12 / 9
    path = tmp_path_factory.mktemp("fig9") / "fig9.png"
    return locomotion.fig_state(nodes, Terrain.flat(), EQUI, path, "rolling", arrow=[1.0, 0.0, 0.0])


def test_rolling_figure_explains_its_arrows(rolling):
    """Fig. 9's red arrow (3D and inset) was drawn with no word about it."""
    assert not rolling["stands"] and {"rolling arrow", "inset arrow", "target arrow"} <= set(rolling["actors"])
    assert "red arrows (both views): the way\nit rolls, out across edge 10-12" in rolling["legend"]
    assert "orange arrow: target direction" in rolling["legend"]


def test_state_figure_inset_has_a_scale_bar(rolling):
    _check_scale_bar(rolling, "inset scale bar", INSET)


def _ground_inside(png):
    """Every pixel along the main view's left, right and lower edges is background, and the
    ground is drawn (its sand colour covers a good part of the view)."""
    img = imageio.imread(png)[..., :3].astype(int)
    right, top = int(0.7 * WINDOW[0]), int(round(0.07 * WINDOW[1]))  # the main view: columns < right, rows > top
    main = img[top:, :right]
    frame = np.concatenate([main[:, :3].reshape(-1, 3), main[:, -3:].reshape(-1, 3), main[-3:].reshape(-1, 3)])
    assert (frame >= 250).all(), "the ground (or robot) reaches the main view's edge"
    sand = (np.abs(main - [200, 195, 180]) < 50).all(axis=2) & (main.max(axis=2) < 245)
    assert sand.mean() > 0.1


def test_ground_ends_inside_the_main_view(rolling, tmp_path):
    """The ground plane of Figs. 8-10 ran to the main view's edge, cut by the side panels."""
    _ground_inside(rolling["path"])
    angle = np.radians(10.0)  # Fig. 10: seen across a 10 deg slope, nearly level
    rot = np.array([[np.cos(angle), 0, -np.sin(angle)], [0, 1, 0], [np.sin(angle), 0, np.cos(angle)]])
    ref = topo.reference_nodes(0.5)
    nodes = frames.to_frame(ref, *frames.face_frame(ref, EQUI)) @ rot.T
    out = locomotion.fig_slope(nodes, Terrain.slope(10.0), EQUI, tmp_path / "fig10.png", "slope")
    _ground_inside(out["path"])


def test_animation_frames_carry_a_legend(tmp_path):
    """The GIF of a run named none of its colours: every frame now holds a legend in a white
    strip under the scene, wholly inside the frame."""
    ref = topo.reference_nodes(0.5)
    standing = frames.to_frame(ref, *frames.face_frame(ref, EQUI))
    x = np.linspace(0.0, 0.6, 12)
    nodes = standing[None] + x[:, None, None] * np.array([1.0, 0.0, 0.0])
    pressure = np.zeros((12, 12))
    pressure[:, 9] = 1.0
    out = animation.animate(
        nodes, 0.1 * np.arange(1, 13), pressure, Terrain.flat(), tmp_path / "run.gif",
        goal=[1.0, 0.2, 0.0], fps=5, speed=2.0, size=(320, 240),
    )  # fmt: skip
    assert "CoG track" in out["legend"] and "goal" in out["legend"]
    x0, x1, y0, y1 = out["legend_box"]
    assert 0 <= x0 and x1 <= 320 and 0 <= y0 and y1 <= 240 and x1 - x0 > 100
    shots = imageio.mimread(out["path"])
    assert len(shots) == out["frames"] > 1
    for img in shots:
        plate = np.asarray(img)[240 - int(y1) + 1 : 240 - int(y0) - 1, int(x0) + 1 : int(x1) - 1, :3].astype(int)
        light, dark = (plate >= 225).all(axis=2).mean(), (plate <= 160).all(axis=2).mean()
        assert light > 0.5 and dark > 0.03, (light, dark)  # white with black writing
