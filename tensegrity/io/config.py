"""Configuration: read config/config.yaml, fill defaults, validate, and turn it into `Params`.

The schema is tensegrity/io/config.schema.yaml (JSON Schema 2020-12, in YAML); every key has a
default, so `validate({})` is the complete default configuration. On top of the schema `validate`
converts numeric strings to numbers (Snakemake parses nested `--config` values with YAML's
BaseLoader, so `sweep='{levels: [0.5, 1.0]}'` arrives as ['0.5', '1.0'], and PyYAML reads `1e-4`
without a dot as a string) and the string `null` to None where the schema allows null, rejects NaN
and infinities (JSON Schema bounds let NaN through), and checks what the schema cannot say:
strictly increasing pressure levels, nominal.discard below sweep.hold, a muscle minimum length
below the cable rest length, a locomotion interval that is a whole number of time steps,
demonstration runs only with a workspace of both contact cases and goals at least the strut
length away, and jobs within the cost limits of `io.job_costs`. The schema's part is
`io.schema_checks` (the filling validator, the coercion, the messages), the rest `io.cross_checks`.
`read_yaml` (`io.config_files`) is the strict reader (a key given twice is an error) for any
configuration file; `read_file` also refuses a file that is not a mapping of sections, an empty
one included, as Snakemake does.

Which file: `base_file` is config/config.yaml of the current directory (where Snakemake reads
it), else of the checkout holding this package, else none (the schema's defaults); `load` reads
it and merges a file it is given over it, as `snakemake --configfile FILE` merges FILE over
config/config.yaml (`merge`).

Every error is a `ConfigError` naming the offending key, e.g.
``config key sweep.pairs[0]: 13 is greater than the maximum of 12``.
"""

from __future__ import annotations

import copy
import functools
import os
from collections.abc import Iterable, Mapping
from pathlib import Path

import yaml

from ..physics.params import Params
from .config_files import ConfigError, check_files, read_file, read_yaml
from .cross_checks import semantic_errors
from .schema_checks import check_against, filling_validator, plain

__all__ = [
    "ConfigError",
    "load",
    "validate",
    "params_from_config",
    "merge",
    "schema",
    "defaults",
    "read_yaml",
    "read_file",
    "base_file",
    "check_files",
    "SCHEMA_PATH",
    "DEFAULT_PATH",
]

SCHEMA_PATH = Path(__file__).with_name("config.schema.yaml")  # package data: works from any install
_CONFIG_REL = Path("config", "config.yaml")
DEFAULT_PATH = Path(__file__).resolve().parents[2] / _CONFIG_REL  # the checkout's file, if any


def base_file() -> Path | None:
    """The configuration every command starts from: config/config.yaml of the current directory
    (as Snakemake reads it, so a project copy uses its own), else of the checkout holding this
    package (`DEFAULT_PATH`), else None (the schema's defaults)."""
    for path in (Path.cwd() / _CONFIG_REL, DEFAULT_PATH):
        if path.is_file():
            return path
    return None


# -------------------------------------------------------------------------------------- schema


@functools.lru_cache(maxsize=1)
def _schema() -> dict:
    return read_yaml(SCHEMA_PATH)


def schema() -> dict:
    """The configuration schema as a dict (a copy)."""
    return copy.deepcopy(_schema())


@functools.lru_cache(maxsize=1)
def _validator():
    return filling_validator(_schema())


# ------------------------------------------------------------------------------------- public


def validate(cfg: Mapping | None) -> dict:
    """Validated copy of `cfg` with every default filled in; the input is not modified.

    `cfg` may be a partial configuration (an empty one gives all defaults) and may hold numbers
    as strings, as Snakemake's `--config` delivers them. Raises ConfigError listing every problem.
    """
    if cfg is None:
        cfg = {}
    if not isinstance(cfg, Mapping):
        raise ConfigError(f"config: expected a mapping of sections, got {type(cfg).__name__}")
    inst, errors = check_against(_validator(), _schema(), cfg)
    if errors:
        raise ConfigError(errors)
    errors = semantic_errors(inst, _schema_defaults())
    if errors:
        raise ConfigError(errors)
    return inst


@functools.lru_cache(maxsize=1)
def _schema_defaults() -> dict:
    """The schema's defaults alone (the cost checks name the key whose default costs least)."""
    return check_against(_validator(), _schema(), {})[0]


def defaults() -> dict:
    """The complete default configuration, from the schema alone."""
    return validate({})


def merge(base: Mapping, overrides: Mapping) -> dict:
    """Copy of `base` updated recursively with `overrides` (mappings merge, anything else
    replaces), the same rule as Snakemake's `--config`."""
    out = plain(base)
    for key, val in overrides.items():
        if isinstance(val, Mapping) and isinstance(out.get(key), dict):
            out[key] = merge(out[key], val)
        else:
            out[key] = plain(val)
    return out


def _parse_overrides(overrides: Mapping | Iterable[str]) -> dict:
    """A mapping as is; or strings "dotted.key=<YAML value>", e.g. "sweep.levels=[0.5, 1.0]"."""
    if isinstance(overrides, Mapping):
        return dict(overrides)
    if isinstance(overrides, str):
        overrides = [overrides]
    out: dict = {}
    for item in overrides:
        key, sep, text = item.partition("=")
        if not sep or not key.strip():
            raise ConfigError(f"config override {item!r}: expected key.path=value")
        try:
            val = yaml.safe_load(text)
        except yaml.YAMLError as e:
            raise ConfigError(f"config key {key.strip()}: cannot parse {text!r}: {e}") from None
        for part in reversed(key.strip().split(".")):
            val = {part: val}
        out = merge(out, val)
    return out


def load(
    path_or_dict: str | os.PathLike | Mapping | None = None, overrides: Mapping | Iterable[str] | None = None
) -> dict:
    """Read, merge, fill and validate a configuration.

    path_or_dict: None for config/config.yaml (`base_file`: of the current directory, else of
        the checkout, else the schema's defaults); a YAML file, merged over that file as
        `snakemake --configfile FILE` merges it (`merge`: a mapping updates the keys it names,
        anything else replaces); or an already-read mapping, taken as it is.
    overrides: a nested mapping merged over it as Snakemake's `--config` does, or strings
        "dotted.key=<YAML value>" such as "sweep.mode=grounded".
    Returns the resolved configuration (plain dicts, lists and scalars). Raises ConfigError; an
    empty file is refused naming it (`read_file`), as Snakemake refuses it.
    """
    if isinstance(path_or_dict, Mapping):
        cfg = plain(path_or_dict)
    else:
        base = base_file()
        cfg = read_file(base) if base is not None else {}
        if path_or_dict is not None:
            cfg = merge(cfg, read_file(path_or_dict))
    if overrides:
        cfg = merge(cfg, _parse_overrides(overrides))
    return validate(cfg)


def params_from_config(cfg: Mapping) -> Params:
    """`Params` from a configuration, or from its `params` section alone.

    Missing keys take their defaults; the cable rest length is derived from the pretension
    (L = l0 - T0/K) and `max_speed` keeps the `Params` default. Gravity is passed as configured:
    zeroing it in the free mode is the sweep's business.
    """
    if set(cfg) & set(_schema()["properties"]):
        section = cfg.get("params", {})
    else:
        section = cfg
    return Params(**validate({"params": section})["params"])
