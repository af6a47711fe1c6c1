"""What every validation check shares: the verdict statuses, the settings of the checks (the
configuration's `validate` section as a dataclass), the result every check derives from and the
result of check 3 (two modules make it).
Numbers and statuses only: the words are written by `validation.summary`, the datasets by
`validation.report`."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..physics import topology as topo

PASS, FAIL, SKIP = "pass", "fail", "not evaluated"
INFO = "reported"  # a row of numbers, not a check
N_CONTACTS = len(topo.CONTACTS)
LEVEL_TOL = 1e-9  # MPa: a pressure within this of a swept level is that level
# why a check is not evaluated on files in volts (the twisted-string actuator)
STATICS_IN_VOLTS = (
    "the statics (physics.statics) solves the pneumatic muscles' equilibrium (eq. 1-2) and knows no motor stall"
)
IN_VOLTS = {
    "paper": "the paper's statements (III.A, III.C) hold for its pneumatic muscles (eq. 1), not for the "
    "prototype's motors; the prototype's experiment in volts (IV.B) is check 8",
    "statics": STATICS_IN_VOLTS,
}


def status(ok: bool) -> str:
    """PASS if `ok`, else FAIL."""
    return PASS if ok else FAIL


@dataclass(frozen=True)
class CheckSettings:
    """The configuration's `validate` section (config/README.md; the defaults are the schema's,
    pinned by tests/validation). Pressures in MPa, lengths in m, times in s."""

    ranking_pressure: float = 2.4  # MPa, pairs ranked by CoG migration here (1.1)
    tip_pressure_tolerance: float = 0.2  # MPa, around the paper's 4.2 MPa (1.2)
    orbit_tolerance: float = 1e-4  # m, 3-fold orbit members' CoG (1.5)
    statics_pressures: tuple[float, ...] = (0.8, 2.4, 4.0)  # MPa, among the swept levels (2)
    statics_tolerance: float = 1e-4  # m (2)
    faces: tuple[int, ...] = (1, 7, 9, 18)  # sample faces of the mapping check (3)
    mapping_tolerance: float = 1e-4  # m (3)
    grounded_settle: float = 0.5  # s on the ground before the first level (4)
    grounded_tolerance: float = 5e-3  # m, in-plane CoG shift (4.1)
    timestep_tolerance: float = 1e-4  # m (5)
    averaging_tolerance: float = 5e-5  # m, estimated averaging error of every level (7)


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


@dataclass(frozen=True)
class NotEvaluated(Result):
    """A check that does not apply to the configured robot: its `name` ('statics'), verdict
    numbers (`status`: each SKIP) and `reason` (why it is not evaluated, e.g. the statics of the
    pneumatic muscles knows no motor stall)."""

    name: str
    reason: str

    @classmethod
    def of(cls, name: str, numbers: tuple[str, ...], reason: str) -> NotEvaluated:
        return cls(status=dict.fromkeys(numbers, SKIP), name=name, reason=reason)


@dataclass(frozen=True)
class MappingResult(Result):
    """Numbers of check 3 on the F sample `faces` (1..20), all N_PAIRS pairs and the P `levels`
    MPa: tolerance m, min_per_kind, levels_match (the workspace was swept at `levels`), kinds
    (face type -> number of non-canonical sample faces), cog (F, N_PAIRS, P, 3) m of the direct
    simulations (reference 'simulation') or of the statics solve ('statics'), difference
    (F, N_PAIRS, P) m from the mapped CoG and support_difference (F, N_PAIRS, P) m, the largest
    corner distance of the triangles; NaN where not computed."""

    faces: np.ndarray
    levels: np.ndarray
    tolerance: float
    min_per_kind: int
    levels_match: bool
    kinds: dict[str, int]
    cog: np.ndarray
    difference: np.ndarray
    support_difference: np.ndarray
    reference: str = "simulation"  # or "statics" (`statics_mapping`: a workspace made by statics)

    @property
    def faces_with_data(self) -> int:
        """Number of sample faces for which the workspace held data."""
        return int(np.isfinite(self.difference).any(axis=(1, 2)).sum())
