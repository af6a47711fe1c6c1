"""The figure stages (tensegrity.stages.render.cog_cloud, workspace_figure, stages.locomotion._path_figure) on small
synthetic datasets: what each figure is judged against is drawn, and a grounded robot that
rolled off its face (NaN from that level on) is drawn up to the roll."""

import numpy as np
import pytest
import xarray as xr

from tensegrity.io import datasets, formats
from tensegrity.io.config import defaults
from tensegrity.io.formats import run as run_formats
from tensegrity.physics import frames
from tensegrity.physics import topology as topo
from tensegrity.physics.terrain import Terrain
from tensegrity.stages import fit as fit_stage
from tensegrity.stages import locomotion as loco_stage
from tensegrity.stages import render as render_stage
from tensegrity.workspace import fit

FACE = 8  # (9,10,12), equilateral
LEVELS = np.round(0.4 * np.arange(1, 13), 2)  # 0.4 .. 4.8 MPa
S = defaults()["params"]["strut_length"]


def _nominal(roll_at: int | None = None) -> xr.Dataset:
    """Pairs #9, #10: the CoG moves linearly from the rest CoG toward edge 10-12 (#10) or
    away from it (#9) while the support shrinks linearly toward its centroid; #10 leaves the
    deformed support between two levels. roll_at: the level index from which the grounded
    robot rolled off (NaN, `rolled` 1)."""
    rest_cog, rest_support = frames.rest_frame(FACE, S)
    P = len(LEVELS)
    cog, sup, margin = np.zeros((2, P, 3)), np.zeros((2, P, 3, 3)), np.zeros((2, P))
    inward = -rest_support[[1, 2]].mean(axis=0)[:2]  # from the edge 10-12 ... to the centroid
    inward /= np.linalg.norm(inward)
    for i, sign in enumerate((-1.0, 1.0)):  # #9 away from the edge, #10 toward it
        for k, p in enumerate(LEVELS):
            cog[i, k] = rest_cog + [*(-sign * 0.02 * p * inward), -0.001 * p]
            sup[i, k] = rest_support * (1 - 0.02 * p)
            margin[i, k] = frames.margin_2d(cog[i, k, :2], sup[i, k, :, :2])
    tip = np.array([frames.first_crossing(LEVELS, m)[0] for m in margin])
    rolled = np.zeros((2, P), np.int8)
    std = np.full((2, P, 3), 1e-4)
    if roll_at is not None:
        rolled[:, roll_at:] = 1
        for a in (cog, std, sup, margin):
            a[:, roll_at:] = np.nan
        tip = np.array([t if t <= LEVELS[roll_at] else LEVELS[roll_at] for t in tip])
    return formats.nominal_dataset(
        [9, 10],
        LEVELS,
        cog,
        std,
        sup,
        margin,
        tip,
        rolled,
        np.where(np.isnan(margin), np.nan, 1e-5),
        {
            "contact": "equilateral",
            "face": FACE,
            "face_nodes": topo.FACES[FACE - 1] + 1,
            "mode": "free" if roll_at is None else "grounded",
        },
        S,
    )


def _write(ds, tmp_path, name):
    return datasets.write(ds, tmp_path / name, defaults(), "test", stage="nominal", allow_nan=formats.NOMINAL_ALLOW_NAN)


def _curves(tmp_path, nominal_path):
    return fit_stage.curves(defaults(), nominal_path, tmp_path / "curves.nc")


def test_fig7_rings_lie_on_the_dashed_deformed_triangle_at_the_tipping_pressure(tmp_path):
    nm = _nominal()
    tp = float(nm["tip_pressure"].sel(pair=10))
    assert np.isfinite(tp) and np.isnan(float(nm["tip_pressure"].sel(pair=9)))
    npath = _write(nm, tmp_path, "nominal.nc")
    out = render_stage.workspace_figure({}, _curves(tmp_path, npath), npath, tmp_path / "fig7.png")
    assert out["tips"] == [10] and list(out["tip_supports"]) == [10]
    assert "tip support #10" in out["actors"] and "tip #10" in out["actors"]
    assert any("dashed" in e for e in out["legend"])  # the legend says what a ring is judged on
    cv = datasets.read(tmp_path / "curves.nc")
    curve = fit.arrays_to_curves({k: cv[k].values for k in fit.ARRAY_DIMS})[list(cv["pair"].values).index(10)]
    at_tp = 1e3 * np.array([float(fit.evaluate(curve[a], tp)) for a in range(2)])
    np.testing.assert_allclose(out["tip_points"][10], at_tp, atol=1e-9)  # the curve at tp
    deformed = out["tip_supports"][10]
    support = nm["support"].sel(pair=10).values
    np.testing.assert_allclose(
        deformed, 1e3 * np.array([[np.interp(tp, LEVELS, support[:, j, a]) for a in range(2)] for j in range(3)])
    )
    # on the deformed triangle's boundary, well inside the unactuated one
    assert abs(frames.margin_2d(out["tip_points"][10], deformed)) < 0.05  # mm
    rest = 1e3 * frames.rest_frame(FACE, S)[1][:, :2]
    assert frames.margin_2d(out["tip_points"][10], rest) > 1.0


def test_fig7_nominal_render_draws_rings_and_a_legend_that_fits(tmp_path, monkeypatch):
    """`tensegrity render nominal.nc` (and workspace.nc): rings and dashed triangles too."""
    from tensegrity.render import face_workspace as paper

    npath = _write(_nominal(), tmp_path, "nominal.nc")
    real, seen = paper.fig_workspace, {}
    monkeypatch.setattr(paper, "fig_workspace", lambda *a, **kw: seen.update(real(*a, **kw)) or seen)
    render_stage.render_dataset(npath, tmp_path / "n.png")
    assert seen["tips"] == [10]
    assert abs(frames.margin_2d(seen["tip_points"][10], seen["tip_supports"][10])) < 0.05
    assert len(seen["legend"]) == 4  # two pairs, the ring, the dashed triangle


def test_grounded_roll_fig6_and_fig7_draw_the_levels_before_it(tmp_path, monkeypatch):
    roll_at = 5  # rolled off at 2.4 MPa
    nm = _nominal(roll_at)
    npath = _write(nm, tmp_path, "nominal.nc")
    per = 20
    cog = np.repeat(nm["cog"].sel(pair=10).values, per, axis=0)
    cog[roll_at * per :] = cog[roll_at * per - 1] + [0.05, -0.3, -0.2]  # rolling away
    sweep = xr.Dataset(
        {
            "cog": (("time", "axis"), cog),
            "level": (("time",), np.repeat(np.arange(len(LEVELS)), per)),
            "pressure_cmd": (("time",), np.repeat(LEVELS, per)),
        },
        attrs={"pair": 10, "face": FACE},
    )
    real_read = datasets.read
    monkeypatch.setattr(render_stage.datasets, "read", lambda p: sweep if str(p).endswith("sweep.nc") else real_read(p))
    out = render_stage.cog_cloud({}, tmp_path / "sweep.nc", npath, tmp_path / "fig6.png", max_pressure=4.8)
    assert out["labels"] == [f"{p:g} MPa" for p in LEVELS[:roll_at]]
    assert out["samples"] == roll_at * per
    assert "rolled off at 2.4 MPa" in out["title"]
    out = render_stage.cog_cloud({}, tmp_path / "sweep.nc", npath, tmp_path / "fig6b.png", max_pressure=1.2)
    assert out["nominal"] == 3 and "rolled" not in out["title"]  # the roll is not in view
    monkeypatch.setattr(render_stage.datasets, "read", real_read)
    out = render_stage.workspace_figure({}, _curves(tmp_path, npath), npath, tmp_path / "fig7.png")
    assert out["tips"] == []  # the robot rolled off before its CoG left the triangle
    assert "#9, #10 rolled off at 2.4 MPa" in out["title"]
    assert (tmp_path / "fig7.png").exists()


@pytest.mark.parametrize(
    "terrain, words",
    [
        (Terrain.flat(), "on flat ground"),
        (
            Terrain(kind="plane", normal=np.array([np.sin(np.radians(10)), 0, np.cos(np.radians(10))])),
            "on a 10 deg slope",
        ),
    ],
)
def test_path_titles_name_the_ground(tmp_path, monkeypatch, terrain, words):
    ds = xr.Dataset(attrs={"run": "r", "outcome": "arrived", "rolls": 1})
    seen = {}
    from tensegrity.render import runs

    monkeypatch.setattr(run_formats, "terrain_from_dataset", lambda ds: terrain)
    monkeypatch.setattr(runs, "fig_path", lambda *a, **kw: seen.update(title=a[3]) or seen)
    ds = ds.assign(
        time=("time", [0.0, 1.0]),
        t_end=("step", [1.0]),
        next_face=("step", [8]),
        goal=("axis", [1.0, 0.0, 0.0]),
        nodes=(("time", "node", "axis"), np.zeros((2, 12, 3))),
    )
    out = loco_stage._path_figure(ds, tmp_path / "p.png", "top")
    assert words in out["title"]
