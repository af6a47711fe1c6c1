"""The states a run has stood at since it last came closer to its goal (`Memory`; docs/design.md
§6): `lookahead.choose` refuses a roll back to one of them, so a route cannot cycle without
progress, and a route that made progress may go back the way it came."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["Memory"]


@dataclass
class Memory:
    """The states a run has been at since its best cost last fell: (1-based face, CoG (2,) m
    horizontal). A roll may not return to a face at a place within `radius` m of where the
    robot stood on it (half a roll's travel). A state added at a cost below every cost added
    before (`best`: a new best, e.g. fewer rolls to the goal) clears the states first: between
    two bests the memory only grows, and the bests strictly fall, so a route cannot cycle; it
    ends stuck, at the step limit or arrived. A state added without a cost never clears it."""

    radius: float
    states: list[tuple[int, np.ndarray]] = field(default_factory=list)
    best: float = np.inf

    def add(self, face: int, cog: np.ndarray, cost: float = np.inf) -> None:
        if cost < self.best:
            self.best = float(cost)
            self.states.clear()
        self.states.append((int(face), np.asarray(cog, float)[:2].copy()))

    def seen(self, face: int | None, cog: np.ndarray) -> bool:
        c = np.asarray(cog, float)[:2]
        return any(f == face and np.linalg.norm(c - p) < self.radius for f, p in self.states)
