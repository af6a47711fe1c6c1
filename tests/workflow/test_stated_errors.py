"""Every approximation of the tiny run states its error in the file that holds it (issue 34): the
curves' and surfaces' largest residuals, recomputed here from the data files they were fitted to;
the nominal files' averaging errors, judged by check 7; the slope limits' bisection brackets, whose
ends a direct simulation puts on either side of the standing limit."""

import json

import numpy as np

from tensegrity.io import datasets, settings
from tensegrity.io.formats import two_pair as tpf
from tensegrity.physics import topology as topo
from tensegrity.workspace import fit
from tensegrity.workspace import slope_limit as sl
from tensegrity.workspace.gravity import GravitySetup

AXES = "xyz"


def test_curves_state_their_largest_residual_against_the_nominal_cog(tiny):
    doc = json.loads((tiny / "results" / "curves" / "curves.json").read_text())
    assert "max_residual" in doc
    for contact, case in doc["contacts"].items():
        nom = datasets.read(tiny / "results" / "nominal" / f"{contact}.nc")
        p = nom["pressure"].values
        for pair, per_axis in case["pairs"].items():
            cog = nom["cog"].sel(pair=int(pair)).transpose("pressure", "axis").values
            ok = np.isfinite(cog).all(axis=-1)
            for a, ax in enumerate(AXES):
                miss = np.abs(fit.evaluate(per_axis[ax], p[ok]) - cog[ok, a]).max()
                assert abs(per_axis[ax]["max_residual"] - miss) <= 1e-15


def test_two_pair_surfaces_keep_every_swept_point_within_0_1_mm(tiny):
    doc = json.loads((tiny / "results" / "curves" / "two_pair.json").read_text())
    for contact, case in doc["contacts"].items():
        ds = datasets.read(tiny / "results" / "two_pair" / f"{contact}.nc")
        lv = ds["pressure_a"].values
        pa, pb = np.meshgrid(lv, lv, indexing="ij")
        combos = [f"{a},{b}" for a, b in ds["combo_pairs"].values]
        assert case["combos"]
        for key, per_axis in case["combos"].items():
            cog = ds["cog"].isel(combo=combos.index(key)).transpose("level_a", "level_b", "axis").values
            for a, ax in enumerate(AXES):
                miss = np.abs(tpf.evaluate_surface(per_axis[ax], pa, pb) - cog[..., a]).max()
                assert miss <= per_axis[ax]["max_residual"] + 1e-15 and per_axis[ax]["max_residual"] <= 1e-4


def test_nominal_files_hold_the_averaging_error_that_check_7_judges(tiny):
    val = datasets.read(tiny / "results" / "validation" / "validation.nc")
    tol = datasets.provenance_config(tiny / "results" / "validation" / "validation.nc")["validate"][
        "averaging_tolerance"
    ]
    for contact in topo.CONTACTS:
        nom = datasets.read(tiny / "results" / "nominal" / f"{contact}.nc")
        assert nom["averaging_error"].attrs["units"] == "m"
        err = nom["averaging_error"].transpose("pair", "pressure").values
        np.testing.assert_array_equal(val["averaging_error"].sel(contact=contact, pair=nom["pair"].values).values, err)
    st = dict(zip(val["check"].values, val["status"].values))
    above = np.nanmax(val["averaging_error"].values) > tol
    assert st["7"] == ("fail" if above else "pass")


def test_the_standing_limit_lies_in_its_bisection_bracket(tiny):
    """The robot placed on each bracket end with the stage's own settings (its provenance): it
    stands at the low end and not at the high end, unless friction ends the bracket there."""
    path = tiny / "results" / "slope_limit.nc"
    lim = datasets.read(path).sel(kind="stand")
    lo, hi = lim["simulated"].values, lim["simulated_high"].values  # (contact, heading) deg
    assert np.array_equal(np.isnan(lo), np.isnan(hi)) and np.all(lo[np.isfinite(lo)] < hi[np.isfinite(hi)])
    setup = settings.build(GravitySetup, datasets.provenance_config(path))
    params = setup.rolling(settings.params(datasets.provenance_config(path)))
    c, h = np.argwhere(np.isfinite(lo) & (lim["limited_by"].values != "friction"))[0]  # one case: 2 robots
    face = topo.face_number(topo.CONTACT_FACES[str(lim["contact"].values[c])])
    head = float(lim["heading"].values[h])
    ok = sl.stands(params, [face] * 2, [lo[c, h], hi[c, h]], [head] * 2, setup.settle + 0.5, setup.dt)
    assert ok.tolist() == [True, False], (lo[c, h], hi[c, h])
