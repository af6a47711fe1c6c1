"""Configuration: read config/config.yaml, fill defaults, validate, and turn it into `Params`.

The schema is tensegrity/io/config.schema.yaml (JSON Schema 2020-12, in YAML); every key has a
default, so `validate({})` is the complete default configuration. On top of the schema this module
converts numeric strings to numbers (Snakemake parses nested `--config` values with YAML's
BaseLoader, so `sweep='{levels: [0.5, 1.0]}'` arrives as ['0.5', '1.0'], and PyYAML reads `1e-4`
without a dot as a string) and the string `null` to None where the schema allows null, rejects NaN
and infinities (JSON Schema bounds let NaN through), and checks what the schema cannot say:
strictly increasing pressure levels, nominal.discard below sweep.hold, a muscle minimum length
below the cable rest length, a locomotion interval that is a whole number of time steps, and
demonstration runs only with a workspace of both contact cases.
`read_yaml` (`io.config_files`) is the strict reader (a key given twice is an error) for any
configuration file.

Every error is a `ConfigError` naming the offending key, e.g.
``config key sweep.pairs[0]: 13 is greater than the maximum of 12``.
"""

from __future__ import annotations

import copy
import difflib
import functools
import math
import os
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import yaml

from ..physics.params import Params
from .config_files import ConfigError, check_files, read_yaml
from .cross_checks import semantic_errors

if TYPE_CHECKING:
    import jsonschema

__all__ = [
    "ConfigError",
    "load",
    "validate",
    "params_from_config",
    "merge",
    "schema",
    "defaults",
    "read_yaml",
    "check_files",
    "SCHEMA_PATH",
    "DEFAULT_PATH",
]

SCHEMA_PATH = Path(__file__).with_name("config.schema.yaml")  # package data: works from any install
_CONFIG_REL = Path("config", "config.yaml")
DEFAULT_PATH = Path(__file__).resolve().parents[2] / _CONFIG_REL  # the checkout's file, if any


def _default_file() -> Path | None:
    """config/config.yaml of the checkout holding this package, else of the current directory."""
    for path in (DEFAULT_PATH, Path.cwd() / _CONFIG_REL):
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


def _extend_with_default(cls):
    """Validator class that fills `default`s while validating (jsonschema FAQ pattern). Defaults
    are deep-copied so that filling a nested section never alters the schema itself."""
    import jsonschema

    validate_properties = cls.VALIDATORS["properties"]

    def set_defaults(validator, properties, instance, schema):
        if validator.is_type(instance, "object"):
            for name, sub in properties.items():
                if "default" in sub:
                    instance.setdefault(name, copy.deepcopy(sub["default"]))
        yield from validate_properties(validator, properties, instance, schema)

    return jsonschema.validators.extend(cls, {"properties": set_defaults})


def filling_validator(schema: dict) -> Any:
    """A jsonschema validator of `schema` (checked first) that fills its defaults while it
    validates."""
    import jsonschema  # here: a job that validates no configuration does not pay its import

    cls = jsonschema.validators.validator_for(schema)
    cls.check_schema(schema)
    return _extend_with_default(cls)(schema)


@functools.lru_cache(maxsize=1)
def _validator():
    return filling_validator(_schema())


# ------------------------------------------------------------------------------------- helpers


def _keypath(path: Iterable) -> str:
    out = ""
    for p in path:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else str(p))
    return out


def _where(path: Iterable) -> str:
    kp = _keypath(path)
    return f"config key {kp}" if kp else "config"


def plain(obj: Any) -> Any:
    """Deep copy into dict/list/scalars (Snakemake's config may hold other Mapping types)."""
    if isinstance(obj, Mapping):
        return {k: plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [plain(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return [plain(v) for v in obj.tolist()]
    if isinstance(obj, np.generic):
        return obj.item()
    return obj


_YAML_SPECIAL = {".nan": "nan", ".inf": "inf", "+.inf": "inf", "-.inf": "-inf"}


def _to_number(s: str) -> float | None:
    try:
        return float(_YAML_SPECIAL.get(s.strip().lower(), s))
    except ValueError:
        return None


_YAML_NULL = ("null", "Null", "NULL", "~")


def _coerce(sch: dict, value: Any) -> Any:
    """Numbers given as strings -> numbers, integral floats -> int for integers, ints -> float for
    numbers, YAML's null given as a string -> None, where the schema says so."""
    if isinstance(value, dict):
        props = sch.get("properties", {})
        return {k: _coerce(props[k], v) if k in props else v for k, v in value.items()}
    if isinstance(value, list):
        items = sch.get("items")
        return [_coerce(items, v) for v in value] if isinstance(items, dict) else value
    t = sch.get("type")
    if isinstance(t, list) and "null" in t and isinstance(value, str) and value.strip() in _YAML_NULL:
        return None  # `animation_run: null` given with --config
    if t in ("number", "integer") and isinstance(value, str):
        x = _to_number(value)
        value = value if x is None else x
    if t == "integer" and isinstance(value, float) and value.is_integer():
        value = int(value)
    elif t == "number" and isinstance(value, int) and not isinstance(value, bool):
        value = float(value)  # canonical: `hold: 1` and `hold: 1.0` resolve identically
    return value


def _nonfinite(value: Any, path: tuple = ()) -> list[str]:
    if isinstance(value, dict):
        return [m for k, v in value.items() for m in _nonfinite(v, path + (k,))]
    if isinstance(value, list):
        return [m for i, v in enumerate(value) for m in _nonfinite(v, path + (i,))]
    if isinstance(value, float) and not math.isfinite(value):
        return [f"{_where(path)}: {value} is not a finite number"]
    return []


def _schema_message(err: jsonschema.ValidationError) -> list[str]:
    path = tuple(err.absolute_path)
    if err.validator == "additionalProperties" and isinstance(err.instance, dict):
        known = sorted(err.schema.get("properties", {}))
        out = []
        for key in sorted(set(err.instance) - set(known), key=str):
            close = difflib.get_close_matches(str(key), known, n=1)
            hint = f"did you mean {close[0]!r}?" if close else f"known keys: {', '.join(known)}"
            out.append(f"{_where(path + (key,))}: unknown key ({hint})")
        return out
    return [f"{_where(path)}: {err.message}"]


def _sort_key(err: jsonschema.ValidationError):
    return [(0, p, "") if isinstance(p, int) else (1, 0, str(p)) for p in err.absolute_path]


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
    errors = semantic_errors(inst)
    if errors:
        raise ConfigError(errors)
    return inst


def check_against(
    validator: Any, schema: dict, data: Mapping, message: Callable[[Any], list[str] | None] | None = None
) -> tuple[dict, list[str]]:
    """`data` coerced to `schema` (numbers given as strings, null), its defaults filled in by
    `validator` (`filling_validator`), and every problem: schema errors (worded by `message`
    where it returns a list) and non-finite numbers, one message per problem naming its key."""
    inst = _coerce(schema, plain(data))
    errors = []
    for err in sorted(validator.iter_errors(inst), key=_sort_key):
        errors += (message(err) if message else None) or _schema_message(err)
    return inst, errors + _nonfinite(inst)


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

    path_or_dict: a YAML file, an already-read mapping, or None for the repository's
        config/config.yaml (found next to the package, else under the current directory).
    overrides: a nested mapping merged over it as Snakemake's `--config` does, or strings
        "dotted.key=<YAML value>" such as "sweep.mode=grounded".
    Returns the resolved configuration (plain dicts, lists and scalars). Raises ConfigError.
    """
    if path_or_dict is None:
        path_or_dict = _default_file() or {}
    if isinstance(path_or_dict, Mapping):
        cfg = plain(path_or_dict)
    else:
        cfg = read_yaml(path_or_dict)
        if cfg is None:  # an empty file is an empty configuration
            cfg = {}
        if not isinstance(cfg, Mapping):
            raise ConfigError(f"config file {path_or_dict}: expected a mapping of sections, got {type(cfg).__name__}")
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
