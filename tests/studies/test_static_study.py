"""A study with `workspace: {method: statics}`: the chunk holds the static equilibria and the
tipping pressures found by root-finding, the paper's statements read those, and a bad choice is
refused by key before any work."""

from pathlib import Path

import numpy as np
import pytest

from tensegrity.io import config, datasets, study_config
from tensegrity.io.config import ConfigError
from tensegrity.physics import statics
from tensegrity.physics.params import Params
from tensegrity.stages import study as stage
from tensegrity.stages.config import stage_config
from tensegrity.studies import spec

STUDY = {
    "parameters": {
        "cable_stiffness": {"low": 800.0, "high": 1300.0, "units": "N/m"},
        "cable_pretension": {"low": 15.0, "high": 30.0, "units": "N"},
    },
    "design": {"method": "lhs", "n": 3, "seed": 2},
    "chunk_size": 3,
    "workspace": {"method": "statics", "pairs": [4, 10, 11], "levels": [1.2, 2.4, 3.6, 4.8]},
}


def test_method_defaults_to_dynamics_and_statics_needs_linear_cables():
    assert study_config.validate({k: v for k, v in STUDY.items() if k != "workspace"})["workspace"]["method"] == (
        "dynamics"
    )
    with pytest.raises(ConfigError, match="study key workspace.method"):
        study_config.validate({**STUDY, "workspace": {"method": "quasi"}})
    with pytest.raises(ConfigError, match="study key workspace.method: statics needs linear cables"):
        study_config.validate(STUDY, base=Params(cable_exponent=1.2))


def test_a_static_chunk_holds_the_equilibria_and_the_roots(tmp_path: Path):
    cfg = stage_config(config.load(), "study_chunk")
    st = {"name": "static", **study_config.validate(STUDY, dt=cfg["sim"]["dt"])}
    ds = datasets.read(stage.study_chunk(cfg, st, 0, tmp_path / "chunk.nc"))
    X = spec.design_matrix(st)
    prm = Params().replace(cable_stiffness=float(X[1, 0]), cable_pretension=float(X[1, 1]))
    # design 1, #11 on (10,11,12): the chunk's CoG is the independent static equilibrium
    cog, _ = statics.static_workspace(prm, (10, 11, 12), 11, st["workspace"]["levels"])
    np.testing.assert_allclose(ds["cog"].values[1, 1, 2], cog, rtol=0, atol=1e-9)
    # its tipping pressure is a root of that margin, not an interpolation between levels
    tip = float(ds["tip_pressure"].values[1, 1, 2])
    _, m = statics.static_workspace(prm, (10, 11, 12), 11, [tip - 1e-5, tip + 1e-5])
    assert m[0] > 0 > m[1]
    assert ds["tip_edge"].values[1, 1, 2].tolist() == [10, 11]
    assert float(ds["best_tip_pressure"].values[1]) == pytest.approx(np.nanmin(ds["tip_pressure"].values[1]))
