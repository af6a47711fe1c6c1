"""Typed settings from the resolved configuration, built once at the seam (`stages`, `cli`):
`build(SweepSetup, cfg)` and so on for every settings class of the domain. `KEYS` maps each
class's fields to their configuration keys; it is the one table of that mapping, and
tests/io/test_settings.py holds every class's defaults to the schema's through it. The one field
that is not a key, `RollSettings.motors`, comes from the `actuator` section (`motors`).

`cfg` is a resolved configuration, or the keys of it a stage reads (`stages.config.stage_config`):
a field whose key is missing is a KeyError naming the key, never a silent default.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import fields
from typing import Any, TypeVar

from ..locomotion.demos import Scenarios
from ..locomotion.settings import RollSettings
from ..physics.params import Params
from ..physics.twisted import TwistedString
from ..validation.common import CheckSettings
from ..validation.prototype import ExperimentSettings
from ..workspace.gravity import GravitySetup
from ..workspace.sensitivity import ActuationSettings
from ..workspace.sweep import SweepSetup
from ..workspace.two_pair import TwoPairSetup
from .config import params_from_config

__all__ = ["KEYS", "build", "params", "motors", "twisted_strings"]

T = TypeVar("T")


def _section(section: str, cls: type, **other: str) -> dict[str, str]:
    """Every field of `cls` from `section`, but those named in `other` (field -> key)."""
    return {f.name: other.get(f.name, f"{section}.{f.name}") for f in fields(cls)}


KEYS: dict[type, dict[str, str]] = {
    SweepSetup: _section("sweep", SweepSetup, dt="sim.dt", record_every="sim.record_every"),
    TwoPairSetup: _section("two_pair", TwoPairSetup, dt="sim.dt"),
    GravitySetup: _section(
        "gravity",
        GravitySetup,
        dt="sim.dt",
        **{k: f"locomotion.{k}" for k in ("ramp_rate", "interval", "lift_tolerance", "hold_time", "strut_damping")},
    ),
    RollSettings: {k: v for k, v in _section("locomotion", RollSettings, dt="sim.dt").items() if k != "motors"},
    Scenarios: _section("locomotion", Scenarios),
    CheckSettings: _section("validate", CheckSettings),
    ActuationSettings: _section("locomotion", ActuationSettings),
    ExperimentSettings: _section("prototype", ExperimentSettings),
}


def value(cfg: Mapping, key: str) -> Any:
    """The value of config key `key` ('section.name') in `cfg`; KeyError naming it if absent."""
    section, _, name = key.partition(".")
    try:
        return cfg[section][name]
    except (KeyError, TypeError):
        raise KeyError(f"config key {key} is needed here but was not given") from None


def build(cls: type[T], cfg: Mapping) -> T:
    """An instance of the settings class `cls` (a key of `KEYS`) from `cfg`; lists become
    tuples. KeyError naming a missing key; the class's own checks raise ValueError."""
    kw = {}
    for name, key in KEYS[cls].items():
        v = value(cfg, key)
        kw[name] = tuple(v) if isinstance(v, list) else v
    if cls is RollSettings and "actuator" in cfg:  # the rolls drive the configured actuator
        kw["motors"] = motors(cfg)
    return cls(**kw)


def params(cfg: Mapping) -> Params:
    """The robot's `Params` from the `params` section of `cfg` (`io.config.params_from_config`)."""
    if "params" not in cfg:
        raise KeyError("config section params is needed here but was not given")
    return params_from_config({"params": cfg["params"]})


def motors(cfg: Mapping) -> TwistedString | None:
    """The prototype's twisted-string actuators from the `actuator` section of `cfg` when its
    kind is twisted_string; None for the pneumatic muscles (docs/design.md §10)."""
    kind = value(cfg, "actuator.kind")
    if kind == "pneumatic":
        return None
    if kind != "twisted_string":
        raise ValueError(f"config key actuator.kind: unknown actuator {kind!r}")
    return TwistedString.from_dict(dict(cfg["actuator"].get("twisted_string", {})))


def twisted_strings(cfg: Mapping) -> TwistedString:
    """The twisted strings of the `actuator.twisted_string` section of `cfg`, whatever
    actuator.kind says: `tensegrity calibrate` replays a run driven in volts with them, and the
    experiment of validation check 8 runs the prototype with them (docs/design.md §10).
    KeyError naming the section if `cfg` lacks it."""
    if "actuator" not in cfg:
        raise KeyError("config section actuator is needed here (a run driven in volts) but was not given")
    return TwistedString.from_dict(dict(cfg["actuator"].get("twisted_string", {})))
