"""Typed settings from the configuration (`io.settings`): every settings class's defaults are the
schema's (no drift), every field has a key, and a missing key is an error, never a default."""

from dataclasses import MISSING, fields

import pytest

from tensegrity.io import config, settings
from tensegrity.io.settings import KEYS, build
from tensegrity.locomotion.settings import RollSettings
from tensegrity.physics.params import Params


def _keyed(cls):
    """The fields that are configuration keys: all but RollSettings.motors (the actuator section,
    `settings.motors`)."""
    return [f for f in fields(cls) if (cls, f.name) != (RollSettings, "motors")]


@pytest.mark.parametrize("cls", list(KEYS), ids=lambda c: c.__name__)
def test_defaults_are_the_schemas(cls):
    """Each field's default equals the schema's default of its key (lists as tuples)."""
    schema = config.defaults()
    drift = []
    for f in _keyed(cls):
        section, name = KEYS[cls][f.name].split(".")
        want = schema[section][name]
        want = tuple(want) if isinstance(want, list) else want
        have = f.default if f.default is not MISSING else f.default_factory()
        if have != want or type(have) is not type(want) and not (isinstance(have, float) and isinstance(want, float)):
            drift.append(f"{cls.__name__}.{f.name} = {have!r}, schema {KEYS[cls][f.name]} = {want!r}")
    assert not drift, "\n".join(drift)
    assert build(cls, schema) == cls()


@pytest.mark.parametrize("cls", list(KEYS), ids=lambda c: c.__name__)
def test_every_field_has_a_key_of_the_schema(cls):
    props = config.schema()["properties"]
    assert set(KEYS[cls]) == {f.name for f in _keyed(cls)}
    for key in KEYS[cls].values():
        section, name = key.split(".")
        assert name in props[section]["properties"], key


def test_params_defaults_are_the_schemas():
    assert settings.params(config.defaults()) == Params()


def test_a_missing_key_is_an_error_naming_it():
    cfg = config.defaults()
    del cfg["locomotion"]["brake_margin"]
    with pytest.raises(KeyError, match="config key locomotion.brake_margin"):
        build(RollSettings, cfg)
    with pytest.raises(KeyError, match="config section params"):
        settings.params({})


def test_the_drift_check_can_fail(monkeypatch):
    """A default changed in the class is seen (RollSettings.escape_attempts was 0 against the
    schema's 8, so `roll_to` rolled unlike the pipeline)."""
    monkeypatch.setattr(RollSettings.__dataclass_fields__["escape_attempts"], "default", 0)
    with pytest.raises(AssertionError, match="escape_attempts = 0, schema locomotion.escape_attempts = 8"):
        test_defaults_are_the_schemas(RollSettings)


def test_keyword_defaults_of_the_public_api_are_the_settings():
    """`plan_roll`'s combine and min_alignment are RollSettings' (so the schema's)."""
    import inspect

    from tensegrity.locomotion.plan import plan

    sig, s = inspect.signature(plan).parameters, RollSettings()
    assert (sig["combine"].default, sig["min_alignment"].default) == (s.combine, s.min_alignment)
