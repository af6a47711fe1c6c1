"""`tensegrity stage NAME ARG=VALUE ...`: any stage of `stages.config.STAGES`, its arguments by
the names of its function's parameters (after `cfg`), read from the command line."""

from __future__ import annotations

import inspect
from collections.abc import Sequence
from typing import Any


def _parameters(stage: str) -> dict[str, inspect.Parameter]:
    from ..stages import function

    params = list(inspect.signature(function(stage)).parameters.values())
    return {p.name: p for p in params[1:] if p.name != "progress"}  # after cfg


def _is_list(p: inspect.Parameter) -> bool:
    return any(k in str(p.annotation) for k in ("Sequence", "Iterable", "list["))


def _value(p: inspect.Parameter, text: str) -> Any:
    """`text` as the parameter `p` takes it: an int, a float, a mapping (YAML) or a string."""
    ann = str(p.annotation)
    if ann.startswith("int") and "|" not in ann.split("int", 1)[1][:3]:
        return int(text)
    if ann.startswith("float"):
        return float(text)
    if "Mapping" in ann or "dict" in ann:
        import yaml

        return yaml.safe_load(text)
    return text


def parse(stage: str, arguments: Sequence[str]) -> dict[str, Any]:
    """name=value pairs -> keyword arguments of the stage function (a repeated name, or a
    Sequence parameter, gives a list); ValueError naming an unknown or missing argument."""
    params, out = _parameters(stage), {}
    for item in arguments:
        name, sep, text = item.partition("=")
        if not sep or name not in params:
            raise ValueError(f"stage {stage}: {item!r} is not ARG=VALUE with ARG one of {', '.join(params)}")
        v = _value(params[name], text)
        if _is_list(params[name]):
            out.setdefault(name, []).append(v)
        elif name in out:
            raise ValueError(f"stage {stage}: argument {name} given twice")
        else:
            out[name] = v
    missing = [n for n, p in params.items() if p.default is inspect.Parameter.empty and n not in out]
    if missing:
        raise ValueError(f"stage {stage}: missing argument(s) {', '.join(missing)} ({describe(stage)})")
    return out


def call(stage: str, cfg: dict, arguments: Sequence[str]) -> Any:
    """Run `stage` with the configuration keys `cfg` and the command-line `arguments`."""
    from ..stages import function

    return function(stage)(cfg, **parse(stage, arguments))


def describe(stage: str) -> str:
    """The stage's arguments and the first line of its docstring."""
    from ..stages import function
    from ..stages.config import STAGES

    args = " ".join(
        f"{n}=..." + ("[...]" if _is_list(p) else "") + ("" if p.default is inspect.Parameter.empty else "?")
        for n, p in _parameters(stage).items()
    )
    doc = (inspect.getdoc(function(stage)) or "").split("\n\n")[0].replace("\n", " ")
    return f"tensegrity stage {stage} {args}\n  (rule {STAGES[stage].rule or '-'}) {doc}"
