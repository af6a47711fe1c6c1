"""Progress on stderr for the commands that run longer than a few seconds (`simulate`, `roll`,
the benchmarks): tqdm bars in simulated seconds, shown only when stderr is a terminal. The
simulations report their time through a callback (`progress=bar.update`)."""

from __future__ import annotations

import sys
from typing import Any

__all__ = ["bar"]


def bar(total: float | None, desc: str, leave: bool = True) -> Any:
    """A tqdm bar in simulated seconds (total s; None: a count without a bar)."""
    from tqdm import tqdm

    if total is None:
        fmt = "{desc}: {n:.1f} s simulated [{elapsed}, {rate_fmt}]"
    else:
        fmt = "{desc}: {percentage:3.0f}%|{bar}| {n:.1f}/{total:.1f} s simulated [{elapsed}<{remaining}]"
    return tqdm(
        total=None if total is None else round(total, 6),
        desc=desc,
        unit="s sim",
        disable=None,
        file=sys.stderr,
        bar_format=fmt,
        leave=leave,
    )
