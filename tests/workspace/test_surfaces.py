"""The two-pair surfaces of results/curves/two_pair.json (issue 34): each keeps every swept point
within MAX_RESIDUAL and states its largest residual; the spline form evaluates, numpy only, to
scipy's own interpolant and converges to a smooth workspace as a cubic does."""

import json

import numpy as np
import pytest
from scipy.interpolate import RectBivariateSpline

from tensegrity.io.formats import two_pair as tpf
from tensegrity.workspace import surfaces


def saturating(pa, pb):
    """A CoG-like surface in m: saturating in each pressure, a few mm of curvature a cubic misses."""
    return 0.02 * np.tanh(1.5 * (pa - 2.5)) * (1 + 0.2 * np.cos(pb)) + 1e-3 * pa * pb


def grid(n):
    lv = np.linspace(0.8, 4.8, n)
    return np.meshgrid(lv, lv, indexing="ij")


def test_a_polynomial_that_misses_a_point_gives_way_to_the_interpolating_spline():
    pa, pb = grid(6)
    v = saturating(pa, pb)
    poly = surfaces.fit_polynomial(pa, pb, v, max_degree=3, folds=5)
    assert poly["max_residual"] > surfaces.MAX_RESIDUAL  # the old surface missed its data
    surf = surfaces.fit_surface(pa, pb, v, max_degree=3, folds=5)
    assert surf["kind"] == "spline" and surf["degree"] == [3, 3]
    assert surf["max_residual"] < 1e-15 and np.abs(surfaces.evaluate(surf, pa, pb) - v).max() < 1e-15
    # through JSON, numpy only, the same function as scipy's interpolant between the points
    doc = tpf.surfaces_document({"isosceles": ([10, 11, 12], [[10, 11]], [[surf, surf, surf]])})
    back = json.loads(json.dumps(doc, allow_nan=False))["contacts"]["isosceles"]["combos"]["10,11"]["z"]
    q = np.linspace(0.8, 4.8, 37)
    qa, qb = np.meshgrid(q, q, indexing="ij")
    ref = RectBivariateSpline(pa[:, 0], pb[0], v, kx=3, ky=3, s=0)(q, q)
    np.testing.assert_allclose(tpf.evaluate_surface(back, qa, qb), ref, rtol=0, atol=1e-15)


def test_the_spline_converges_as_a_cubic_between_the_points():
    # interpolation error O(h^4): doubling the levels (h / 2.2) cuts it by ~2.2^4 = 23
    q = np.linspace(0.8, 4.8, 81)
    qa, qb = np.meshgrid(q, q, indexing="ij")
    err = [
        np.abs(
            surfaces.evaluate(surfaces.fit_spline(*grid(n), saturating(*grid(n))), qa, qb) - saturating(qa, qb)
        ).max()
        for n in (6, 12)
    ]
    assert err[1] < err[0] / 10, err


@pytest.mark.parametrize("n, degree", [(2, 1), (3, 2)])
def test_coarse_grids_interpolate_with_the_degree_they_allow(n, degree):
    pa, pb = grid(n)
    surf = surfaces.fit_spline(pa, pb, saturating(pa, pb))
    assert surf["degree"] == [degree, degree] and surf["max_residual"] < 1e-15
    if n == 2:  # bilinear: the centre is the mean of the corners
        assert surfaces.evaluate(surf, 2.8, 2.8) == pytest.approx(saturating(pa, pb).mean(), abs=1e-15)


def test_a_polynomial_that_fits_stays_with_its_residual_stated():
    pa, pb = grid(4)
    v = 0.01 + 0.003 * pa - 0.002 * pb + 0.0007 * pa * pb
    surf = surfaces.fit_surface(pa, pb, v, max_degree=3, folds=4)
    assert surf["kind"] == "polynomial" and surf["max_residual"] < 1e-15


def test_a_spline_needs_a_full_grid():
    pa, pb = grid(4)
    with pytest.raises(ValueError, match="full grid"):
        surfaces.fit_spline(pa.ravel()[:-1], pb.ravel()[:-1], pa.ravel()[:-1])
