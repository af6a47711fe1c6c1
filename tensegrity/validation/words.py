"""The pieces every check's words are made of: the `Verdict` row (what is claimed, what was
measured with units, the paper's value or the goal, the status), the `Table` of per-pair or per-run
rows, and the writing of lengths (mm), faces and edges, and of the largest of a set of differences.
`validation.summary` gathers each check's verdicts and tables from them."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ..physics import topology as topo
from ..physics.topology import CONTACTS
from .common import PASS

__all__ = ["Verdict", "Table", "mm", "label", "edge_label", "largest", "largest_case"]

Table = tuple[str, list[str], list[list[str]]]  # title, header, rows


@dataclass(frozen=True)
class Verdict:
    """One row of the summary table: what is claimed, what was measured (with units), the
    paper's value or the goal, and the status PASS, FAIL or SKIP."""

    id: str
    statement: str
    measured: str
    reference: str
    status: str

    @property
    def passed(self) -> bool:
        return self.status == PASS


def mm(x: float, digits: int = 3) -> str:
    """A length `x` in m written in mm with `digits` significant digits ('n/a' if not finite)."""
    if not np.isfinite(x):
        return "n/a"
    v = 1e3 * float(x)
    return f"{v:.{digits}g} mm" if abs(v) < 10**digits else f"{v:.0f} mm"


def label(face: int) -> str:
    """A face (1..20) by its sorted nodes, e.g. '(9,10,12)'."""
    return topo.face_label(int(face))


def edge_label(edge: Sequence[int] | None) -> str:
    """An edge (two 1-based nodes; 0 or None: none) as '10-12', or 'none'."""
    return "-".join(str(int(n)) for n in sorted(edge)) if edge is not None and min(edge) > 0 else "none"


def largest_case(difference: np.ndarray, pressures: Sequence[float] | np.ndarray, faces: Mapping) -> str:
    """'largest X mm (#pair at P MPa on face) over N cases' of a (contact, pair, pressure)
    difference in m."""
    c, p, k = largest(difference)
    return (
        f"largest {mm(np.nanmax(difference))} (#{p + 1} at {pressures[k]:g} MPa on "
        f"{label(faces[CONTACTS[c]])}) over {int(np.isfinite(difference).sum())} cases"
    )


def largest(values: np.ndarray) -> tuple[int, ...]:
    """Index of the largest finite value."""
    return tuple(int(i) for i in np.unravel_index(int(np.nanargmax(values)), values.shape))
