"""Fast tests of tensegrity.workspace.fit: exported curves against scikit-learn's pipelines of
the same models (an independent least-squares fit; scikit-learn is a test-only dependency), model
choice, serialisation round trips and input checks."""

import json

import numpy as np
import pytest

from tensegrity.workspace import fit as F


def sklearn_model(model: str):
    """scikit-learn's pipeline (unfitted) of the candidate `model` ("polyD" or "spline k=K"):
    the same least-squares model, computed independently."""
    from sklearn.linear_model import LinearRegression
    from sklearn.pipeline import make_pipeline
    from sklearn.preprocessing import PolynomialFeatures, SplineTransformer

    if model.startswith("poly"):
        features = PolynomialFeatures(int(model[4:]), include_bias=False)
    else:
        features = SplineTransformer(
            n_knots=int(model.split("=")[1]), degree=3, knots="uniform", extrapolation="continue"
        )
    return make_pipeline(features, LinearRegression())


P = np.linspace(0.4, 4.8, 12)  # the default sweep levels, MPa
Q = np.linspace(P[0], P[-1], 200)  # evaluation pressures across the range
QUAD = 0.05 + 0.02 * P - 0.004 * P**2  # exact quadratic CoG, m (order 0.1)
SAT = 0.12 * (1 - np.exp(-P / 0.8))  # saturating CoG, m: no low-degree polynomial fits
TOL = 1e-9  # m; float64 roundoff on 0.1 m values is ~1e-16


@pytest.mark.parametrize("values, kind", [(QUAD, "polynomial"), (SAT, "spline"), (0.1 * np.minimum(P, 2.6), "spline")])
def test_export_matches_estimator(values, kind):
    curve = F.fit_curve(P, values)
    est = sklearn_model(curve.model).fit(P[:, None], values)
    assert curve.kind == kind
    np.testing.assert_allclose(F.evaluate(curve, Q), est.predict(Q[:, None]), rtol=0, atol=TOL)
    # the end pieces continue outside [pmin, pmax] exactly as the estimator does
    out = np.r_[0.0, 0.1, 5.0, 6.0]
    np.testing.assert_allclose(curve(out), est.predict(out[:, None]), rtol=0, atol=TOL)
    assert (curve.pmin, curve.pmax) == (P[0], P[-1])
    assert curve.breaks[0] == P[0] and curve.breaks[-1] == P[-1]


@pytest.mark.parametrize(
    "opts, model",
    [
        ({"max_degree": 3, "spline_knots": ()}, "poly3"),
        ({"max_degree": 0, "spline_knots": (3,)}, "spline k=3"),
        ({"max_degree": 0, "spline_knots": (4,)}, "spline k=4"),
    ],
)
def test_export_restricted_candidates(opts, model):
    v = 0.1 * np.sin(P)  # smooth, not representable by any candidate
    curve = F.fit_curve(P, v, **opts)
    est = sklearn_model(model).fit(P[:, None], v)
    assert curve.model == model
    assert curve.coefs.shape == (int(model[-1]) - 1 if "spline" in model else 1, 4)
    np.testing.assert_allclose(F.evaluate(curve, Q), est.predict(Q[:, None]), rtol=0, atol=TOL)


@pytest.mark.parametrize(
    "values, model", [(QUAD + 2e-3 * np.sin(7 * P), "poly2"), (SAT + 1e-4 * np.cos(5 * P), "spline k=4")]
)
def test_cv_rmse_is_sklearns_cross_validation(values, model):
    # the winner's score: held-out predictions of folds rank mod 5, as scikit-learn makes them
    from sklearn.model_selection import PredefinedSplit, cross_val_predict

    curve = F.fit_curve(P, values)
    assert curve.model == model
    pred = cross_val_predict(sklearn_model(model), P[:, None], values, cv=PredefinedSplit(np.arange(P.size) % 5))
    assert curve.cv_rmse == pytest.approx(np.sqrt(np.mean((pred - values) ** 2)), rel=1e-9)


def test_spline_with_undetermined_coefficients():
    # levels crowded at one end leave B-splines of 5 knots without points: the fit is still the
    # least-squares one (unique at the points, as scikit-learn's), its CV score finite
    p = np.r_[np.linspace(0.4, 1.0, 10), 4.8]
    v = np.sin(p)
    curve = F.fit_curve(p, v, max_degree=0, spline_knots=(5,))
    assert curve.model == "spline k=5" and np.isfinite(curve.cv_rmse)
    est = sklearn_model("spline k=5").fit(p[:, None], v)
    np.testing.assert_allclose(curve(p), est.predict(p[:, None]), rtol=0, atol=TOL)


def test_cv_prefers_true_degree_on_ties():
    # poly3 and the splines reproduce a quadratic exactly too: only the tie rule picks poly2
    tied = F.fit_curve(P, QUAD, max_degree=3, spline_knots=(3, 4))
    assert tied.model == "poly2" and tied.coefs.shape == (1, 3)
    assert F.fit_curve(P, QUAD, max_degree=0, spline_knots=(3,)).cv_rmse < 1e-12
    assert F.fit_curve(P, QUAD, max_degree=1, spline_knots=()).cv_rmse > 1e-4
    # the coefficients are those of the quadratic in u = p - pmin, highest power first
    u = P - P[0]
    np.testing.assert_allclose(np.polyval(tied.coefs[0], u), QUAD, rtol=0, atol=1e-14)


def test_cv_prefers_true_degree_for_many_quadratics():
    # roundoff decides a plain argmin among the exact fits (poly2/3, splines) for some of these
    rng = np.random.default_rng(1)
    for a, b, c in rng.uniform(-0.1, 0.1, (20, 3)):
        assert F.fit_curve(P, a + b * P / 5 + c * (P / 5) ** 2).model == "poly2"


def test_tie_tolerance_is_relative():
    # noisy quadratic (2 mm noise) where poly3 beats poly2 in CV by ~3 %, less than TIE_RTOL
    v = QUAD + 2e-3 * np.random.default_rng(3).standard_normal(P.size)
    s2 = F.fit_curve(P, v, max_degree=2, spline_knots=()).cv_rmse
    s3 = F.fit_curve(P, v, max_degree=3, spline_knots=(), tie_rtol=0.0)
    assert s3.model == "poly3" and 0.95 * s2 < s3.cv_rmse < s2
    assert F.fit_curve(P, v, max_degree=3, spline_knots=()).model == "poly2"
    assert F.fit_curve(P, v).model == "poly2"  # the splines do worse here


def test_fit_is_deterministic_and_order_free():
    rng = np.random.default_rng(0)
    v = SAT + 1e-3 * rng.standard_normal(P.size)
    a = F.fit_curve(P, v)
    perm = rng.permutation(P.size)
    b = F.fit_curve(P[perm], v[perm])
    assert a.model == b.model and a.cv_rmse == b.cv_rmse
    np.testing.assert_array_equal(a.coefs, b.coefs)


def test_dict_json_round_trip():
    for values in (QUAD, SAT):
        curve = F.fit_curve(P, values)
        d = json.loads(json.dumps(F.to_dict(curve), allow_nan=False))
        back = F.from_dict(d)
        assert (back.kind, back.model, back.pmin, back.pmax, back.cv_rmse, back.max_residual) == (
            curve.kind,
            curve.model,
            curve.pmin,
            curve.pmax,
            curve.cv_rmse,
            curve.max_residual,
        )
        np.testing.assert_array_equal(F.evaluate(back, Q), F.evaluate(curve, Q))
        np.testing.assert_array_equal(F.evaluate(d, Q), F.evaluate(curve, Q))  # plain dict
    two = F.fit_curve([1.0, 2.0], [0.1, 0.2])  # too few points to validate: NaN -> null
    assert np.isnan(F.from_dict(json.loads(json.dumps(F.to_dict(two)))).cv_rmse)


def test_arrays_round_trip():
    cog = np.stack(
        [np.c_[QUAD, SAT, 0.1 * np.minimum(P, 2.6)], np.c_[0.01 * P, QUAD[::-1], 0.1 * np.tanh(P - 2.5)]]
    )  # (2, 12, 3)
    curves = F.fit_pairs(P, cog)
    arr = F.curves_to_arrays(curves)
    assert arr["coefs"].shape[:2] == (2, 3) and arr["pmin"].shape == (2, 3)
    assert set(arr) == set(F.ARRAY_DIMS)
    assert all(arr[k].ndim == len(F.ARRAY_DIMS[k]) for k in arr)
    assert np.isnan(arr["breaks"]).any()  # pieces padded with NaN
    back = F.arrays_to_curves(arr)
    for row, row_back in zip(curves, back):
        for c, b in zip(row, row_back):
            assert (b.kind, b.model, b.cv_rmse, b.max_residual) == (c.kind, c.model, c.cv_rmse, c.max_residual)
            np.testing.assert_array_equal(b.breaks, c.breaks)
            np.testing.assert_array_equal(b.coefs, c.coefs)
            np.testing.assert_array_equal(F.evaluate(b, Q), F.evaluate(c, Q))


def test_max_residual_is_the_fits_own_error_at_its_data():
    # exact data: the chosen model reproduces it, to roundoff
    assert F.fit_curve(P, QUAD).max_residual < 1e-12
    # a line through a line with a spike d at point i misses it by d (1 - h_ii), h_ii the
    # point's leverage 1/n + (p_i - mean)^2 / sum (p - mean)^2 (least-squares hat matrix)
    d, i = 1e-3, 3
    v = 0.02 + 0.01 * P
    v[i] += d
    curve = F.fit_curve(P, v, max_degree=1, spline_knots=())
    h = 1 / P.size + (P[i] - P.mean()) ** 2 / np.sum((P - P.mean()) ** 2)
    assert curve.max_residual == pytest.approx(d * (1 - h), rel=1e-9)
    assert np.isnan(F.from_dict({k: v for k, v in F.to_dict(curve).items() if k != "max_residual"}).max_residual)


@pytest.mark.parametrize(
    "pressure, values, match",
    [
        (P, np.r_[QUAD[:-1], np.nan], "values contain NaN"),
        (np.r_[P[:-1], np.nan], QUAD, "pressure contain NaN"),
        (P, QUAD[:-1], "different lengths"),
        ([1.0], [0.1], "at least 2 points"),
        ([1.0, 1.0, 1.0], [0.1, 0.2, 0.3], "2 distinct"),
    ],
)
def test_bad_input_raises(pressure, values, match):
    with pytest.raises(ValueError, match=match):
        F.fit_curve(pressure, values)


def test_fit_pairs_names_pair_and_axis():
    cog = np.zeros((3, P.size, 3))
    cog[1, 4, 2] = np.nan
    with pytest.raises(ValueError, match="pair 2 axis z: values contain NaN"):
        F.fit_pairs(P, cog)
    with pytest.raises(ValueError, match="shape"):
        F.fit_pairs(P, cog[..., :2])
