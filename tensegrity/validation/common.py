"""What every validation check shares: the verdict statuses, the settings of the checks (the
configuration's `validate` section as a dataclass), the result every check derives from, and the
tipping pressure and crossed edge of one pair's nominal path. Numbers and statuses only: the words
are written by `validation.summary`, the datasets by `validation.report`."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..physics import frames, topology as topo

PASS, FAIL, SKIP = "pass", "fail", "not evaluated"
INFO = "reported"  # a row of numbers, not a check
N_CONTACTS = len(topo.CONTACTS)
LEVEL_TOL = 1e-9   # MPa: a pressure within this of a swept level is that level


def status(ok: bool) -> str:
    """PASS if `ok`, else FAIL."""
    return PASS if ok else FAIL


@dataclass(frozen=True)
class CheckSettings:
    """The configuration's `validate` section (config/README.md; the defaults are the schema's,
    pinned by tests/validation). Pressures in MPa, lengths in m, times in s."""
    ranking_pressure: float = 2.4              # MPa, pairs ranked by CoG migration here (1.1)
    tip_pressure_tolerance: float = 0.2        # MPa, around the paper's 4.2 MPa (1.2)
    orbit_tolerance: float = 1e-4              # m, 3-fold orbit members' CoG (1.5)
    statics_pressures: tuple[float, ...] = (0.8, 2.4, 4.0)  # MPa, among the swept levels (2)
    statics_tolerance: float = 1e-4            # m (2)
    faces: tuple[int, ...] = (1, 7, 9, 18)     # sample faces of the mapping check (3)
    mapping_tolerance: float = 1e-4            # m (3)
    grounded_settle: float = 0.5               # s on the ground before the first level (4)
    grounded_tolerance: float = 5e-3           # m, in-plane CoG shift (4.1)
    timestep_tolerance: float = 1e-4           # m (5)


@dataclass(frozen=True)
class Result:
    """Base of every check's result: `status` maps each verdict number ('1.1', '2', ...), in the
    order of the summary table, to PASS, FAIL or SKIP."""
    status: dict[str, str]


@dataclass(frozen=True)
class CheckError(Result):
    """A check that raised: its `name` ('statics'), `number` ('2') and the error
    ('RuntimeError: ...'); `status` is {number: FAIL}."""
    name: str
    number: str
    error: str


def tip(levels: ArrayLike, cog: np.ndarray, support: np.ndarray, margin: ArrayLike,
        face: int) -> tuple[float, tuple[int, int] | None]:
    """Least pressure (MPa, interpolated; NaN: never) at which the CoG projection leaves the
    triangle (`frames.first_crossing`), and the edge (two 1-based node numbers, smaller first) it
    crosses at the first level outside (`frames.crossed_edge`), None if it never leaves.
    levels (P,) MPa; cog (P, 3) m, support (P, 3, 3) m, margin (P,) m of one pair in the
    support frame of `face` (1..20)."""
    pressure, k = frames.first_crossing(levels, margin)
    if k < 0:
        return pressure, None
    return pressure, topo.edge_nodes(face, frames.crossed_edge(cog[k, :2], support[k, :, :2]))
