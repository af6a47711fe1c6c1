"""Progress on stderr for the commands that run longer than a few seconds (`simulate`, `roll`,
the benchmarks): tqdm bars in simulated seconds, shown only when stderr is a terminal."""
from __future__ import annotations

import contextlib
import sys
from collections.abc import Iterator
from typing import Any

__all__ = ["bar", "simulated"]


def bar(total: float | None, desc: str, leave: bool = True) -> Any:
    """A tqdm bar in simulated seconds (total s; None: a count without a bar)."""
    from tqdm import tqdm
    if total is None:
        fmt = "{desc}: {n:.1f} s simulated [{elapsed}, {rate_fmt}]"
    else:
        fmt = "{desc}: {percentage:3.0f}%|{bar}| {n:.1f}/{total:.1f} s simulated [{elapsed}<{remaining}]"
    return tqdm(total=None if total is None else round(total, 6), desc=desc, unit="s sim",
                disable=None, file=sys.stderr, bar_format=fmt, leave=leave)


@contextlib.contextmanager
def simulated(desc: str, leave: bool = True) -> Iterator[Any]:
    """While the block runs, count on a bar (no total: a run's length is not known beforehand)
    the simulated seconds of every `physics.dynamics.simulate` call, per robot of its batch."""
    from .physics import dynamics
    simulate = dynamics.simulate

    def counted(params, state, schedule, *a, **k):
        out = simulate(params, state, schedule, *a, **k)
        b.update(schedule.duration)
        return out
    with bar(None, desc, leave) as b:
        dynamics.simulate = counted
        try:
            yield b
        finally:
            dynamics.simulate = simulate
