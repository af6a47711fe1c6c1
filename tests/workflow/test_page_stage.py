"""Stage `page` (tensegrity.stages.page) on the tiny run's files: the page the rule wrote is the
one the function makes from the same files outside Snakemake, byte for byte, and files that do
not fit together are refused, naming them, before anything is written."""

import pytest

from tensegrity.io import datasets
from tensegrity.physics import frames
from tensegrity.render.face_workspace import at_pressure
from tensegrity.stages import page


def _inputs(res):
    return dict(
        sweeps=sorted(str(p) for p in (res / "sweeps").glob("*/pair*.nc")),
        nominal=[str(res / "nominal" / f"{c}.nc") for c in ("equilateral", "isosceles")],
        curves=[str(res / "curves" / f"{c}.nc") for c in ("equilateral", "isosceles")],
        runs=[str(res / "locomotion" / f"{r}.nc") for r in ("paper", "slope_down")],
    )


def test_the_stage_outside_snakemake_writes_the_rules_page(tiny, tmp_path):
    res = tiny / "results"
    out = page.page({}, out=tmp_path / "p.html", **_inputs(res))
    assert (tmp_path / "p.html").read_bytes() == (res / "figures" / "workspace_3d.html").read_bytes()
    assert len(out["workspace"]) == 2 and len(out["runs"]) == 2
    for p in (4, 9, 10, 11, 12):  # every swept pair of the tiny configuration, its curve and samples
        assert {f"#{p}", f"#{p} CoG samples", f"#{p} nominal CoG"} <= set(out["traces"])


def test_the_tipping_points_lie_on_the_edge_of_the_deformed_triangle(tiny):
    """Fig. 7's rings: #9, #10, #12 on (9,10,12) tip within the tiny levels (paper: 4.2 MPa);
    each ring's projection is on the edge of the support triangle deformed at that pressure, to
    2 mm (the tipping pressure is interpolated linearly between levels 1.2 MPa apart, the ring
    is on the fitted curve: 1.0 mm apart here)."""
    res = tiny / "results"
    nm = datasets.read(res / "nominal" / "equilateral.nc")
    ws = page._workspace("equilateral", nm, datasets.read(res / "curves" / "equilateral.nc"), [], 60)
    assert sorted(ws.tips) == [9, 10, 12]
    for p, tip in ws.tips.items():
        tp = float(nm["tip_pressure"].sel(pair=p))
        support = at_pressure(nm["pressure"].values, nm["support"].sel(pair=p).values, tp)
        assert abs(frames.margin_2d(tip[:2], support[:, :2])) < 2e-3, p


def test_files_that_do_not_fit_together_are_refused_before_writing(tiny, tmp_path):
    args = _inputs(tiny / "results")
    with pytest.raises(
        ValueError, match=r"nominal files of \['equilateral', 'isosceles'\] but curves files of \['equilateral'\]"
    ):
        page.page({}, **{**args, "curves": args["curves"][:1]}, out=tmp_path / "p.html")
    with pytest.raises(ValueError, match="isosceles.*has no nominal and curves file"):
        page.page({}, **{**args, "nominal": args["nominal"][:1], "curves": args["curves"][:1]}, out=tmp_path / "p.html")
    with pytest.raises(ValueError, match="curves: two files of the equilateral case"):
        page.page({}, **{**args, "curves": args["curves"][:1] * 2}, out=tmp_path / "p.html")
    assert not list(tmp_path.iterdir())
