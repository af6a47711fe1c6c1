"""Study analysis: SALib indices recover known sensitivities; best designs; success rates;
the figures are drawn and not blank."""

import numpy as np
import pytest

from tensegrity.io import study_config
from tensegrity.render import studies as fig
from tensegrity.studies import analysis as an
from tensegrity.studies import spec

BOX = {"a": {"low": 0.0, "high": 1.0, "units": "m"}}


def _study(method, n):
    return study_config.validate(
        {
            "parameters": {
                "cable_stiffness": {"low": 500.0, "high": 1500.0, "units": "N/m"},
                "muscle_gain": {"low": 400.0, "high": 800.0, "units": "N/(MPa m)"},
            },
            "design": {"method": method, "n": n, "seed": 2},
        }
    )


@pytest.mark.parametrize("method, n, index", [("saltelli", 256, "S1"), ("morris", 40, "mu_star"), ("lhs", 100, "S1")])
def test_an_output_of_one_parameter_is_attributed_to_it(method, n, index):
    """y = K / 100 + 0 * Kg: the stiffness carries the sensitivity, the gain none (within the
    index's own 95 % interval)."""
    st = _study(method, n)
    X = spec.design_matrix(st)
    r = an.sensitivity(st, X, X[:, 0] / 100.0, resamples=20)  # fewer bootstrap resamples: faster
    conf = r.get(index + "_conf", np.zeros(2))
    assert r[index][0] > 0.8 * (10.0 if index == "mu_star" else 1.0)
    assert abs(r[index][1]) <= max(0.05, 2 * conf[1])


def test_undefined_outputs_need_a_censoring_value():
    st = _study("saltelli", 8)
    X = spec.design_matrix(st)
    y = np.where(X[:, 0] > 1000, np.nan, 1.0)
    with pytest.raises(ValueError, match="undefined"):
        an.sensitivity(st, X, y)
    assert np.isfinite(an.sensitivity(st, X, y, censor=4.8)["S1"]).all()


def test_best_designs_skip_undefined_objectives():
    assert an.best_designs(np.array([3.0, np.nan, 1.0, 2.0, 1.0]), 3).tolist() == [2, 4, 3]


def test_success_rate_interval_brackets_the_rate():
    p, lo, hi = an.success_rate(np.array([1] * 8))
    assert p == 1.0 and 0.6 < lo < 0.7 and hi == 1.0  # Wilson: 67.6-100 % for 8 of 8
    p, lo, hi = an.success_rate(np.array([1, 0] * 50))
    assert lo < p == 0.5 < hi and hi - lo == pytest.approx(0.19, abs=0.01)


def test_the_study_figures_are_drawn(tmp_path):
    import imageio.v3 as iio

    rng = np.random.default_rng(0)
    X = rng.random((20, 2)) * [1000, 400] + [500, 400]
    obj = np.where(X[:, 0] > 600, X[:, 0] / 400, np.nan)
    paths = [
        fig.response_map(
            X[:, 0],
            X[:, 1],
            obj,
            rng.normal(0, 0.01, 20),
            ("cable_stiffness", "N/m"),
            ("muscle_gain", "N/(MPa m)"),
            an.best_designs(obj, 3),
            tmp_path / "r.png",
        ),
        fig.sensitivity_bars(
            ["cable_stiffness", "muscle_gain"],
            ["best_tip_pressure"],
            "saltelli",
            {"S1": np.array([[0.9, 0.05]]), "S1_conf": np.array([[0.1, 0.02]])},
            tmp_path / "s.png",
        ),
        fig.robustness(
            rng.random(20) > 0.2,
            rng.normal([4.2, 2.2], 0.2, (20, 2)),
            X,
            [("cable_stiffness", "N/m"), ("muscle_gain", "N/(MPa m)")],
            (0.8, 0.6, 0.9),
            tmp_path / "b.png",
        ),
    ]
    for p in paths:
        img = iio.imread(p)
        assert img.shape[0] > 300 and img.shape[1] > 400
        assert img[..., :3].std() > 10  # not blank
