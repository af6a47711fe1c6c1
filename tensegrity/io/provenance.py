"""Do files belong together? Every file of the pipeline names the configuration that made it (the
netCDF attribute `config`, the key `config` of the JSON files): the keys its stage and its inputs'
stages read. Two files belong together when they agree on every key both hold; a command that
combines files (`query`: curves and workspace; `plan`, `roll`, the runs: the workspace and the
two-pair workspace) refuses files of different runs, naming both and the keys that differ.
"""

from __future__ import annotations

from collections.abc import Mapping

__all__ = ["differences", "check_together"]


def _leaves(cfg: Mapping, prefix: str = "") -> dict:
    out = {}
    for k, v in cfg.items():
        key = f"{prefix}{k}"
        if isinstance(v, Mapping):
            out |= _leaves(v, key + ".")
        else:
            out[key] = v
    return out


def differences(a: Mapping, b: Mapping) -> list[str]:
    """The keys ('section.key') both configurations hold with different values, sorted."""
    la, lb = _leaves(a), _leaves(b)
    return sorted(k for k in la.keys() & lb.keys() if la[k] != lb[k])


def check_together(configs: Mapping[str, Mapping | None]) -> None:
    """Raise ValueError unless the configurations of the files (name -> configuration, None for
    a file that names none: a file written before files named theirs) agree on every key any two
    of them hold; the message names both files and the first keys that differ, with their values."""
    named = [(n, c) for n, c in configs.items() if c is not None]
    for i, (na, ca) in enumerate(named):
        for nb, cb in named[i + 1 :]:
            diff = differences(ca, cb)
            if diff:
                la, lb = _leaves(ca), _leaves(cb)
                shown = "; ".join(f"{k}: {la[k]!r} against {lb[k]!r}" for k in diff[:4])
                more = f" (and {len(diff) - 4} more)" if len(diff) > 4 else ""
                raise ValueError(
                    f"{na} and {nb} were made by different configurations ({shown}{more}): "
                    "they do not belong together; use the files of one run"
                )
