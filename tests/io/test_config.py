"""tensegrity.io.config: defaults, validation messages, overrides, Params and JSON provenance."""

import json
import math
from dataclasses import fields
from pathlib import Path

import jsonschema
import pytest
import yaml

from tensegrity.io import config, datasets
from tensegrity.io.config import ConfigError
from tensegrity.physics.params import Params


def file_config():
    with open(config.DEFAULT_PATH) as f:
        return yaml.safe_load(f)


def walk_properties(schema, path=""):
    for name, sub in schema.get("properties", {}).items():
        yield f"{path}{name}", sub
        yield from walk_properties(sub, f"{path}{name}.")


def test_schema_is_valid_and_documented():
    schema = config.schema()
    jsonschema.validators.validator_for(schema).check_schema(schema)
    props = list(walk_properties(schema))
    assert len(props) > 30
    for key, sub in props:
        assert "default" in sub, key
        assert sub.get("description", "").strip(), key
        if sub.get("type") == "object" and key not in ("locomotion", "render"):
            assert sub.get("additionalProperties") is False, key
    assert schema["additionalProperties"] is False


def test_default_config_is_the_file_plus_defaults():
    cfg = config.load()
    assert cfg == {**file_config(), "render": {}}
    # The file and the schema defaults agree: an empty config resolves to the same thing.
    assert config.defaults() == cfg
    assert config.load({}) == cfg
    assert isinstance(cfg["sim"]["record_every"], int)
    assert all(isinstance(p, int) for p in cfg["sweep"]["pairs"])


def test_every_documented_key_is_in_the_readme():
    readme = (config.DEFAULT_PATH.parent / "README.md").read_text()
    for key, _ in walk_properties(config.schema()):
        assert f"`{key.split('.')[-1]}`" in readme, key


def test_partial_config_and_file_fill_defaults(tmp_path):
    p = tmp_path / "c.yaml"
    p.write_text("sweep:\n  levels: [0.5, 1.0]\n  mode: grounded\n")
    cfg = config.load(p)
    assert cfg["sweep"]["levels"] == [0.5, 1.0]
    assert cfg["sweep"]["mode"] == "grounded"
    assert cfg["sweep"]["pairs"] == list(range(1, 13))
    assert cfg["params"] == file_config()["params"]
    nothing = tmp_path / "nothing.yaml"
    nothing.write_text("{}\n")
    assert config.load(nothing) == config.load() == config.defaults()


BAD = [
    ({"foo": 1}, "config key foo: unknown key"),
    ({"sweep": {"level": [1.0, 2.0]}}, "config key sweep.level: unknown key (did you mean 'levels'?)"),
    ({"sweep": {"levels": [0.4, 0.8, -0.4]}}, "config key sweep.levels[2]: -0.4 is less than"),
    ({"sweep": {"levels": [0.4, float("nan")]}}, "config key sweep.levels[1]: nan is not a finite"),
    ({"sweep": {"levels": [0.4, 10.5]}}, "config key sweep.levels[1]: 10.5 is greater than the maximum of 10"),
    ({"sweep": {"levels": [0.4]}}, "config key sweep.levels:"),
    ({"sweep": {"levels": [0.8, 0.4]}}, "config key sweep.levels[1]: 0.4 is not greater than"),
    ({"sweep": {"pairs": [13]}}, "config key sweep.pairs[0]: 13 is greater than the maximum of 12"),
    ({"sweep": {"pairs": [0]}}, "config key sweep.pairs[0]: 0 is less than the minimum of 1"),
    ({"sweep": {"pairs": [1, 1]}}, "config key sweep.pairs: [1, 1] has non-unique elements"),
    ({"sweep": {"pairs": []}}, "config key sweep.pairs:"),
    ({"sweep": {"pairs": [2.5]}}, "config key sweep.pairs[0]: 2.5 is not of type 'integer'"),
    ({"sweep": {"contacts": ["square"]}}, "config key sweep.contacts[0]: 'square' is not one of"),
    ({"sweep": {"mode": "walk"}}, "config key sweep.mode: 'walk' is not one of"),
    ({"sweep": {"hold": 0}}, "config key sweep.hold:"),
    ({"sweep": {"settle": -1}}, "config key sweep.settle:"),
    ({"sweep": {"node_stride": 0}}, "config key sweep.node_stride:"),
    ({"sim": {"dt": "fast"}}, "config key sim.dt: 'fast' is not of type 'number'"),
    ({"sim": {"dt": True}}, "config key sim.dt: True is not of type 'number'"),
    ({"sim": {"dt": 2e-3}}, "config key sim.dt: 0.002 is greater than the maximum of 0.001"),
    ({"sim": {"dt": 0}}, "config key sim.dt:"),
    ({"sim": {"record_every": 2.5}}, "config key sim.record_every: 2.5 is not of type 'integer'"),
    ({"nominal": {"discard": 1.0}}, "config key nominal.discard: 1.0 s is not less than sweep.hold"),
    ({"nominal": {"discard": -0.1}}, "config key nominal.discard:"),
    ({"fit": {"max_degree": 7}}, "config key fit.max_degree:"),
    ({"fit": {"spline_knots": [1]}}, "config key fit.spline_knots[0]:"),
    ({"fit": {"folds": 1}}, "config key fit.folds:"),
    ({"params": {"strut_length": 0}}, "config key params.strut_length:"),
    ({"params": {"strut_lenght": 0.5}}, "config key params.strut_lenght: unknown key"),
    ({"params": {"gravity": -9.81}}, "config key params.gravity:"),
    ({"params": {"friction": float("inf")}}, "config key params.friction: inf is not a finite"),
    ({"params": {"muscle_gain": "lots"}}, "config key params.muscle_gain: 'lots' is not of type"),
    ({"params": {"muscle_min_length": 0.3}}, "config key params.muscle_min_length: 0.3 m is not below"),
    ({"params": {"cable_pretension": 400.0}}, "config key params.cable_pretension:"),
    ({"gravity": {"cable_iterations": -1}}, "config key gravity.cable_iterations: -1 is less than the minimum of 0"),
    ({"gravity": {"cable_iterations": True}}, "config key gravity.cable_iterations: True is not of type 'integer'"),
    ({"params": 5}, "config key params: 5 is not of type 'object'"),
    ({"locomotion": 3}, "config key locomotion: 3 is not of type 'object'"),
]


@pytest.mark.parametrize("override, message", BAD, ids=[m for _, m in BAD])
def test_bad_config_names_the_key(override, message):
    with pytest.raises(ConfigError) as exc:
        config.load(overrides=override)
    assert message in str(exc.value)
    assert isinstance(exc.value, ValueError)


def test_zero_allowed_where_documented():
    zeros = {
        k: 0.0 for k in ("cable_damping", "gravity", "ground_damping", "friction", "friction_damping", "strut_damping")
    }
    cfg = config.load(overrides={"params": zeros, "sweep": {"settle": 0}, "nominal": {"discard": 0}})
    assert cfg["params"]["gravity"] == 0.0


def test_yaml_nan_is_rejected(tmp_path):
    p = tmp_path / "c.yaml"
    p.write_text("sweep:\n  levels: [0.4, .nan, 1.2]\n")
    with pytest.raises(ConfigError, match=r"config key sweep\.levels\[1\]: nan is not a finite"):
        config.load(p)
    p.write_text("params:\n  strut_mass: .inf\n")
    with pytest.raises(ConfigError, match=r"config key params\.strut_mass: inf is not a finite"):
        config.load(p)


def test_all_errors_are_reported():
    with pytest.raises(ConfigError) as exc:
        config.load(overrides={"foo": 1, "sim": {"dt": 1.0}, "sweep": {"pairs": [13]}})
    assert len(exc.value.errors) == 3
    for key in ("config key foo", "config key sim.dt", "config key sweep.pairs[0]"):
        assert key in str(exc.value)


def test_duplicate_yaml_key_is_rejected(tmp_path):
    p = tmp_path / "c.yaml"
    p.write_text("sweep:\n  hold: 1.0\n  hold: 2.0\n")
    with pytest.raises(ConfigError, match="line 3: duplicate key 'hold'"):
        config.load(p)


def test_check_files_names_every_file_with_a_duplicate_key(tmp_path):
    """The Snakefile re-reads the files Snakemake loaded (PyYAML keeps the last of two keys)."""
    good, bad, worse = tmp_path / "good.yaml", tmp_path / "bad.yaml", tmp_path / "worse.yaml"
    good.write_text("sweep:\n  hold: 1.0\n")
    bad.write_text("params:\n  cable_stiffness: 2000.0\n  cable_stiffness: 3000.0\n")
    worse.write_text("sim:\n  dt: 1.0e-4\nsim:\n  record_every: 5\n")
    config.check_files([good, config.DEFAULT_PATH])
    with pytest.raises(ConfigError) as exc:
        config.check_files([good, bad, worse])
    assert exc.value.errors == [
        f"config file {bad} line 3: duplicate key 'cable_stiffness'",
        f"config file {worse} line 3: duplicate key 'sim'",
    ]
    assert config.read_yaml(good) == {"sweep": {"hold": 1.0}}


def test_the_snakefile_rereads_every_config_file_strictly():
    text = (Path(__file__).resolve().parents[2] / "Snakefile").read_text()
    assert text.index("check_config_files(workflow.configfiles)") < text.index("validate_config(config)")


@pytest.mark.parametrize(
    "dt, interval, ok",
    [
        (1e-4, 0.02, True),
        (5e-5, 0.02, True),
        (3e-5, 0.02, False),
        (1e-4, 0.00015, False),
        (1e-4, 0.0001, True),
        (2e-4, 0.0001, False),
    ],
)
def test_locomotion_interval_must_be_whole_time_steps(dt, interval, ok):
    """Caught before any job runs, as locomotion.settings.RollSettings would in the job."""
    from tensegrity.io.settings import build
    from tensegrity.locomotion.settings import RollSettings

    over = {"sim": {"dt": dt}, "locomotion": {"interval": interval}}
    if ok:
        build(RollSettings, config.validate(over))
        return
    with pytest.raises(
        ConfigError,
        match=r"^config key locomotion\.interval: .* is not a whole number of time "
        r"steps sim\.dt",
    ):
        config.validate(over)
    with pytest.raises(ValueError):
        RollSettings(interval=interval, dt=dt)


def test_runs_need_both_contact_cases():
    """The demonstration runs roll onto faces of both kinds: a one-case workspace cannot plan them
    (locomotion_run would fail late with 'the workspace has no curve for face ...')."""
    for contacts, missing in ((["equilateral"], "isosceles"), (["isosceles"], "equilateral")):
        with pytest.raises(ConfigError) as exc:
            config.validate({"sweep": {"contacts": contacts}})
        (msg,) = exc.value.errors
        assert msg.startswith("config key locomotion.runs:") and f"sweep.contacts = [{contacts[0]}]" in msg
        assert f"leaves out {missing}" in msg and "locomotion='{runs: []}'" in msg
        config.validate({"sweep": {"contacts": contacts}, "locomotion": {"runs": []}})
    config.validate({"sweep": {"contacts": ["isosceles", "equilateral"]}})


def test_messages_hold_no_numpy_reprs():
    import numpy as np

    for bad in (
        {"sweep": {"pairs": np.array([10, 13])}},
        {"sweep": {"hold": np.float64(-1.0)}},
        {"sweep": {"pairs": [np.int64(13)]}},
        {"sweep": {"levels": [np.float64(1.0), np.float64(0.5)]}},
        {"sim": {"dt": np.float64(1e-4)}, "locomotion": {"interval": np.float64(1.5e-4)}},
    ):
        with pytest.raises(ConfigError) as exc:
            config.validate(bad)
        assert "np." not in str(exc.value) and "array(" not in str(exc.value), str(exc.value)
    assert config.validate({"sweep": {"pairs": np.array([10, 11])}})["sweep"]["pairs"] == [10, 11]


def test_numbers_as_strings_are_converted():
    """Snakemake's nested --config values and PyYAML's `1e-4` arrive as strings."""
    cfg = config.validate(
        {
            "sweep": {"levels": ["0.5", "1.0"], "pairs": ["10", "11"], "hold": "2"},
            "sim": {"dt": "1e-4", "record_every": "5"},
            "fit": {"max_degree": 2.0},
        }
    )
    assert cfg["sweep"]["levels"] == [0.5, 1.0]
    assert cfg["sweep"]["pairs"] == [10, 11] and all(type(p) is int for p in cfg["sweep"]["pairs"])
    assert cfg["sweep"]["hold"] == 2.0 and type(cfg["sweep"]["hold"]) is float
    assert cfg["sim"] == {"dt": 1e-4, "record_every": 5}
    assert type(cfg["fit"]["max_degree"]) is int
    with pytest.raises(ConfigError, match=r"sweep\.levels\[0\]: nan is not a finite"):
        config.validate({"sweep": {"levels": [".nan", "1.0"]}})


def test_null_as_a_string_is_none_where_the_schema_allows_it():
    """`--config locomotion='{animation_run: null}'` (no GIF) arrives as the string 'null'."""
    for null in ("null", "~", None):
        assert config.validate({"locomotion": {"animation_run": null}})["locomotion"]["animation_run"] is None
    assert config.validate({})["locomotion"]["animation_run"] == "terrain"
    with pytest.raises(ConfigError, match=r"locomotion\.animation_run: 'none' is not one of"):
        config.validate({"locomotion": {"animation_run": "none"}})
    with pytest.raises(ConfigError, match=r"sweep\.hold"):  # not where the schema has no null
        config.validate({"sweep": {"hold": "null"}})


def test_snakemake_command_line_overrides():
    snakemake_cli = pytest.importorskip("snakemake.cli")
    from snakemake.utils import update_config

    cfg = file_config()
    update_config(
        cfg, snakemake_cli.parse_config(["sweep={levels: [0.5, 1.0], pairs: [10], mode: grounded}", "sim={dt: 5e-5}"])
    )
    out = config.validate(cfg)
    assert out["sweep"]["levels"] == [0.5, 1.0]
    assert out["sweep"]["pairs"] == [10]
    assert out["sweep"]["mode"] == "grounded"
    assert out["sweep"]["contacts"] == ["equilateral", "isosceles"]
    assert out["sim"] == {"dt": 5e-5, "record_every": 10}


def test_snakemake_validate_accepts_the_schema():
    from snakemake.utils import validate

    cfg = file_config()
    validate(cfg, str(config.SCHEMA_PATH))
    assert cfg["locomotion"]["max_rolls"] == 200


def test_overrides_merge_and_do_not_mutate():
    base = file_config()
    before = json.dumps(base, sort_keys=True)
    cfg = config.load(base, overrides={"sweep": {"pairs": [10, 11]}})
    assert cfg["sweep"]["pairs"] == [10, 11]
    assert cfg["sweep"]["levels"] == base["sweep"]["levels"]
    assert json.dumps(base, sort_keys=True) == before
    cfg2 = config.load(overrides=["sweep.pairs=[10, 11]", "params.friction=0.5"])
    assert cfg2["sweep"]["pairs"] == [10, 11] and cfg2["params"]["friction"] == 0.5
    with pytest.raises(ConfigError, match="expected key.path=value"):
        config.load(overrides=["sweep.pairs"])
    # validate fills a copy, never its argument (nor the schema's defaults)
    partial = {"sweep": {"pairs": [3]}}
    config.validate(partial)
    assert partial == {"sweep": {"pairs": [3]}}
    config.validate({})["sweep"]["pairs"].append(99)
    assert config.defaults()["sweep"]["pairs"] == list(range(1, 13))


def test_params_from_config():
    cfg = config.load(overrides={"params": {"cable_stiffness": 2000.0}})
    p = config.params_from_config(cfg)
    assert isinstance(p, Params)
    for f in fields(Params):
        if f.name in cfg["params"]:
            assert getattr(p, f.name) == cfg["params"][f.name], f.name
    l0 = 0.5 * math.sqrt(6) / 4
    assert p.cable_rest_length == pytest.approx(l0 - 20.0 / 2000.0, abs=1e-12)
    assert config.params_from_config({"strut_mass": 0.3}).strut_mass == 0.3
    assert config.params_from_config({}) == Params()
    with pytest.raises(ConfigError, match="params.strut_mass"):
        config.params_from_config({"strut_mass": -1})


def test_to_json_is_sorted_and_round_trips():
    cfg = config.load()
    s = datasets.to_json(cfg)
    assert json.loads(s) == cfg
    assert s == datasets.to_json(json.loads(s))
    assert list(json.loads(s)) == sorted(cfg)
    assert s.index('"fit"') < s.index('"params"') < s.index('"sweep"')
    # `hold: 1` and `hold: 1.0` resolve to the same provenance
    assert datasets.to_json(config.load(overrides={"sweep": {"hold": 1}})) == s
    with pytest.raises(ValueError):
        datasets.to_json({"x": float("nan")})
