"""The states a run has stood at since its CoG last came horizontally closer to its goal than
ever before (`Memory`; docs/design.md §6): `lookahead.choose` refuses a roll back to one of them,
so a route cannot cycle without progress, and a route that made progress may go back the way it
came. Progress is judged by the horizontal distance alone, which does not depend on the face the
robot stands on (the planner's ranking, `progress.rolls_to_goal`, does: each face has its own lift)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["Memory"]


@dataclass
class Memory:
    """The states a run has been at since it last came closer to `goal`: (1-based face, CoG
    (2,) m horizontal). A roll may not return to a face at a place within `radius` m of where
    the robot stood on it (half a roll's travel). A state whose CoG lies horizontally closer to
    `goal` than every state added before (`nearest`, m: a new least distance) clears the states
    first: between two such states the memory only grows, and the least distances strictly fall,
    so a route cannot cycle; it ends stuck, at the step limit or arrived. Without a goal (a run
    along a direction or over edges) nothing is forgotten."""

    radius: float
    goal: np.ndarray | None = None
    states: list[tuple[int, np.ndarray]] = field(default_factory=list)
    nearest: float = np.inf

    def add(self, face: int, cog: np.ndarray) -> None:
        c = np.asarray(cog, float)[:2].copy()
        if self.goal is not None:
            dist = float(np.linalg.norm(c - np.asarray(self.goal, float)[:2]))
            if dist < self.nearest:
                self.nearest = dist
                self.states.clear()
        self.states.append((int(face), c))

    def seen(self, face: int | None, cog: np.ndarray) -> bool:
        c = np.asarray(cog, float)[:2]
        return any(f == face and np.linalg.norm(c - p) < self.radius for f, p in self.states)
