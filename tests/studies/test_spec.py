"""Study files: the schema and the checks it cannot express name the bad key; the designs."""

from pathlib import Path

import numpy as np
import pytest

from tensegrity.io import study_config
from tensegrity.io.config import ConfigError
from tensegrity.studies import spec

ROOT = Path(__file__).resolve().parents[2]
BASE = {
    "parameters": {
        "cable_stiffness": {"low": 800.0, "high": 1200.0, "units": "N/m"},
        "cable_pretension": {"low": 15.0, "high": 25.0, "units": "N"},
    },
    "design": {"method": "grid", "levels": 3},
}


def _with(**kw):
    st = {k: dict(v) if isinstance(v, dict) else v for k, v in BASE.items()}
    for k, v in kw.items():
        st[k] = v
    return st


@pytest.mark.parametrize(
    "study, key",
    [
        (
            _with(parameters={"cable_stifness": {"low": 1, "high": 2, "units": "N/m"}}),
            "study key parameters.cable_stifness",
        ),
        (
            _with(parameters={"cable_stiffness": {"low": 900.0, "high": 800.0, "units": "N/m"}}),
            "study key parameters.cable_stiffness.high",
        ),
        (
            _with(parameters={"cable_stiffness": {"low": 0.8, "high": 1.2, "units": "kN/m"}}),
            "study key parameters.cable_stiffness.units",
        ),
        (_with(design={"method": "latin"}), "study key design.method"),
        (_with(chunk_size=0), "study key chunk_size"),
        (_with(workspace={"levels": [1.0, 0.5]}), "study key workspace.levels"),
        (_with(workspace={"reference_pressure": 9.0}), "study key workspace.reference_pressure"),
        (
            _with(roll={"enabled": True}, parameters={"strut_length": {"low": 0.4, "high": 0.6, "units": "m"}}),
            "study key parameters.strut_length",
        ),
        (_with(analysis={"response": ["strut_mass"]}), "study key analysis.response"),
        (_with(colour="red"), "study key colour"),
        (_with(analysis={"outputs": ["roll_success"]}), "study key analysis.outputs"),
    ],
)
def test_a_bad_study_names_its_key(study, key):
    with pytest.raises(ConfigError) as e:
        study_config.validate(study)
    assert key in str(e.value)


def test_a_box_with_an_impossible_corner_is_refused():
    # T0 = 60 N at K = 300 N/m: rest length l0 - T0/K = 0.106 m < Lmin = 0.2 m
    st = _with(
        parameters={
            "cable_stiffness": {"low": 300.0, "high": 1200.0, "units": "N/m"},
            "cable_pretension": {"low": 20.0, "high": 60.0, "units": "N"},
        }
    )
    with pytest.raises(ConfigError, match="study key parameters: the corner .* is not a valid robot"):
        study_config.validate(st)


def test_grid_is_the_full_factorial_and_chunks_cover_it_once():
    st = study_config.validate(_with(chunk_size=4))
    X = spec.design_matrix(st)
    assert X.shape == (9, 2) == (spec.n_designs(st), 2)
    assert sorted(map(tuple, X)) == sorted((k, t) for k in (800, 1000, 1200) for t in (15, 20, 25))
    rows = np.concatenate([spec.chunk_rows(st, c) for c in range(spec.n_chunks(st))])
    assert rows.tolist() == list(range(9))
    assert spec.n_chunks(st, limit=5) == 2 and spec.chunk_rows(st, 1, limit=5).tolist() == [4]


@pytest.mark.parametrize("method, n, size", [("lhs", 10, 10), ("sobol", 8, 8), ("saltelli", 8, 32), ("morris", 5, 15)])
def test_samples_are_seeded_inside_the_box(method, n, size):
    st = study_config.validate(_with(design={"method": method, "n": n, "seed": 4}))
    X = spec.design_matrix(st)
    assert X.shape == (size, 2) == (spec.n_designs(st), 2)
    assert np.all(X >= [800, 15]) and np.all(X <= [1200, 25])
    np.testing.assert_array_equal(X, spec.design_matrix(st))  # same study, same designs
    other = study_config.validate(_with(design={"method": method, "n": n, "seed": 5}))
    assert not np.array_equal(X, spec.design_matrix(other))
    if method == "lhs":  # one sample in each of the n strata of every parameter
        for j, (lo, hi) in enumerate([(800, 1200), (15, 25)]):
            assert sorted(np.floor((X[:, j] - lo) / (hi - lo) * n).astype(int)) == list(range(n))


def test_design_params_set_only_the_varied_parameters():
    from tensegrity.physics.params import Params

    st = study_config.validate(BASE)
    p = spec.design_params(Params(strut_mass=0.3), st, np.array([[900.0, 18.0]]))[0]
    assert (p.cable_stiffness, p.cable_pretension, p.strut_mass) == (900.0, 18.0, 0.3)
    assert p.cable_rest_length == pytest.approx(0.5 * np.sqrt(6) / 4 - 18.0 / 900.0)


@pytest.mark.parametrize("name", ["stiffness_pretension", "robustness"])
def test_the_example_studies_are_valid(name):
    st = study_config.load(name, root=ROOT)
    assert st["name"] == name and spec.n_designs(st) >= 64


def test_an_unknown_study_name_lists_the_known_ones():
    with pytest.raises(ConfigError, match="known studies: .*stiffness_pretension"):
        study_config.load("no_such_study", root=ROOT)
