"""Mappings checked against a JSON schema, for the configuration (`io.config`) and the design
studies (`io.study_config`). `filling_validator` fills the schema's defaults while it validates;
`check_against` first coerces what YAML and Snakemake's `--config` deliver as strings (numbers,
`null`) to the schema's types, then lists every problem, one message naming its key each: schema
errors (an unknown key with the closest known one) and non-finite numbers. `plain` copies any
mapping into plain dicts, lists and scalars.
"""

from __future__ import annotations

import copy
import difflib
import math
from collections.abc import Callable, Iterable, Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    import jsonschema


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
