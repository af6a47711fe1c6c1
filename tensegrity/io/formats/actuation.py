"""The actuation level's unit in the files (docs/datasets.md, "One contract, two actuators"): one
dataset contract serves both actuators. The dimension and variables keep their names (`pressure`,
`pressure_cmd`, `tip_pressure`, ...); a file of the twisted-string actuator (docs/design.md §10)
holds motor voltages there, says so with `units: "V"` and a long_name naming the motor voltage,
and carries the global attribute `actuator = "twisted_string"`. A file without the attribute is
of the pneumatic muscles (MPa), as every file before issue 31: the pneumatic files are unchanged
byte for byte.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping

import numpy as np
import xarray as xr

PNEUMATIC, TWISTED = "pneumatic", "twisted_string"
ATTR = "actuator"  # the global attribute naming the kind (absent: pneumatic)
UNITS = {PNEUMATIC: "MPa", TWISTED: "V"}
QUANTITY = {PNEUMATIC: "pressure", TWISTED: "motor voltage"}

# long_name phrases of the pneumatic files and their twisted-string wording, longest first; a
# variable's name in a text (pressure_a) stays
_WORDS = (
    (r"\bmuscle pressure\b", "motor voltage"),
    (r"\bequal-pressure\b", "equal-voltage"),
    (r"\bPressure\b", "Motor voltage"),
    (r"\bpressures\b", "motor voltages"),
    (r"\bpressure(?!_)\b", "motor voltage"),
    (r"\bMPa\b", "V"),
)


def check_kind(kind: str) -> str:
    """`kind` if it is an actuator the files know; ValueError naming config key actuator.kind."""
    if kind not in UNITS:
        raise ValueError(f"config key actuator.kind: unknown actuator {kind!r}: use one of {sorted(UNITS)}")
    return kind


def kind_of(obj: xr.Dataset | Mapping) -> str:
    """The actuator kind of a dataset (its attribute `actuator`) or of a JSON document (its key
    `actuator`); pneumatic where absent."""
    attrs = obj.attrs if isinstance(obj, xr.Dataset) else obj
    return check_kind(str(attrs.get(ATTR, PNEUMATIC)))


def common_kind(sources: Iterable[xr.Dataset | Mapping]) -> str:
    """The one actuator kind of several inputs; ValueError if they mix kinds (a workspace of
    pressures and volts together has no unit)."""
    kinds = sorted({kind_of(s) for s in sources})
    if len(kinds) > 1:
        raise ValueError(f"the input files mix actuators {kinds}: make them with one actuator.kind")
    return kinds[0] if kinds else PNEUMATIC


def units(kind: str) -> str:
    """The unit of the actuation level: MPa (pneumatic) or V (twisted_string)."""
    return UNITS[check_kind(kind)]


def words(text: str, kind: str) -> str:
    """A pneumatic file's or figure's text in the wording of `kind`: pressure -> motor voltage,
    MPa -> V (identity for pneumatic)."""
    if check_kind(kind) == PNEUMATIC:
        return text
    for old, new in _WORDS:
        text = re.sub(old, new, text)
    return text


def label(kind: str, what: str = "pressure") -> str:
    """An axis label of the actuation level, e.g. 'pressure (MPa)' or 'motor voltage (V)'."""
    return f"{words(what, kind)} ({units(kind)})"


def relabel(ds: xr.Dataset, kind: str) -> xr.Dataset:
    """`ds` (written in the pneumatic wording) in the units and wording of `kind`: every variable
    in MPa becomes V, its long_name and every long_name mentioning pressure say motor voltage,
    and the global attribute `actuator` names the kind. The pneumatic dataset is returned as it
    is (no attribute added)."""
    if check_kind(kind) == PNEUMATIC:
        return ds
    out = ds.copy(deep=False)
    for v in out.variables.values():
        attrs = dict(v.attrs)
        if attrs.get("units") == UNITS[PNEUMATIC]:
            attrs["units"] = UNITS[kind]
        if "long_name" in attrs:
            attrs["long_name"] = words(str(attrs["long_name"]), kind)
        v.attrs = attrs
    out.attrs = {**ds.attrs, ATTR: kind}
    return out


def relabel_texts(ds: xr.Dataset, kind: str) -> xr.Dataset:
    """`relabel`, and the text data variables (a verdict's words, what sets a slope limit) in the
    wording of `kind` too."""
    out = relabel(ds, kind)
    if check_kind(kind) != PNEUMATIC:
        for name, v in out.data_vars.items():
            if v.dtype.kind == "U":
                text = [words(str(x), kind) for x in v.values.ravel()]
                out[name] = v.copy(data=np.array(text, dtype=str).reshape(v.shape))
    return out


def document(doc: dict, kind: str) -> dict:
    """A JSON curve document (curves.json, two_pair.json) in the wording of `kind`, in place:
    units {"pressure": "V"} (the key stays, as the files' dimension does), its `evaluate` text
    in volts, and the key `actuator`; a pneumatic document is left as it is."""
    if check_kind(kind) != PNEUMATIC:
        doc["units"]["pressure"] = units(kind)
        doc["evaluate"] = words(doc["evaluate"], kind)
        doc[ATTR] = kind
    return doc


def require_pneumatic(obj: xr.Dataset | Mapping, source: str, what: str) -> None:
    """ValueError naming `source` (a file) if `obj` (its dataset, attributes or JSON document) is
    of another actuator than the pneumatic muscle: `what` (a command) reads pressures only."""
    kind = kind_of(obj)
    if kind != PNEUMATIC:
        raise ValueError(
            f"{source} is of the {kind} actuator (its levels are in {units(kind)}: attribute {ATTR}), but "
            f"{what} works with the pneumatic muscle's pressures only"
        )


def require_kind(obj: xr.Dataset | Mapping, source: str, kind: str) -> None:
    """ValueError naming `source` (a file) and config key actuator.kind if `obj` (its dataset,
    attributes or JSON document) is of another actuator than `kind`, the configured one: levels
    in volts are not pressures, nor the reverse."""
    have = kind_of(obj)
    if have != check_kind(kind):
        raise ValueError(
            f"{source} is of the {have} actuator (its levels are in {units(have)}: attribute {ATTR}), but config "
            f"key actuator.kind is {kind!r} (levels in {units(kind)}): make the file with actuator.kind: "
            f"{kind}, or configure actuator.kind: {have}"
        )
