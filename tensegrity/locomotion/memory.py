"""The states a run has stood at since its CoG last came horizontally closer to its goal than
ever before (`Memory`; docs/design.md §6): `lookahead.choose` refuses a roll back to one of them,
so a route cannot cycle without progress, and a route that made progress may go back the way it
came. Progress is judged by the horizontal distance alone, which does not depend on the face the
robot stands on (the planner's ranking, `progress.rolls_to_goal`, does: each face has its own lift).
Where no roll is acceptable (a dead end), a roll back to a state that still has an acceptable roll
the run did not take is (`Memory.opens`): the route backtracks, as a depth-first search does."""

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
    along a direction or over edges) nothing is forgotten.

    Per state, `found` holds the landings (face, CoG (2,) m) of the acceptable rolls found there
    (`record`, by `lookahead.choose`). A state is open while one of them is not in the memory: an
    alternative the run never took. Where no roll is acceptable, a roll back to an open state is
    (`opens`, a backtrack), and standing at a state again replaces the records of the states it
    matches by what is found now. No backtrack can make the route cycle: after a cycle's first
    round no state of it comes closer than ever (nothing is forgotten) and every one is in the
    memory, so the later rounds are backtracks only (an acceptable roll lands outside the memory).
    In a stretch of backtracks only, each stand found no acceptable roll and records nothing, yet
    empties the record of the open state it came back to (the roll made is the one simulated,
    `lookahead.foresee`), and the memory, only growing, reopens none: each backtrack leaves one
    open state fewer, and the stretch ends after at most as many backtracks as there were open
    states, stuck or by an acceptable roll to a state not in the memory."""

    radius: float
    goal: np.ndarray | None = None
    states: list[tuple[int, np.ndarray]] = field(default_factory=list)
    nearest: float = np.inf
    found: list[list[tuple[int, np.ndarray]]] = field(default_factory=list)

    def add(self, face: int, cog: np.ndarray) -> None:
        c = np.asarray(cog, float)[:2].copy()
        if self.goal is not None:
            dist = float(np.linalg.norm(c - np.asarray(self.goal, float)[:2]))
            if dist < self.nearest:
                self.nearest = dist
                self.states.clear()
                self.found.clear()
        for i in self._at(int(face), c):  # here again: what is found now replaces their records
            self.found[i] = []
        self.states.append((int(face), c))
        self.found.append([])

    def seen(self, face: int | None, cog: np.ndarray) -> bool:
        return bool(self._at(face, cog))

    def record(self, landings: list[tuple[int, np.ndarray]]) -> None:
        """The landings (face, CoG (2,) or (3,) m) of the acceptable rolls found at the state added last."""
        if self.states:
            self.found[-1] = [(int(f), np.asarray(c, float)[:2].copy()) for f, c in landings]

    def opens(self, face: int | None, cog: np.ndarray) -> bool:
        """Whether (face, cog) returns to an open state: one whose record holds a landing not in the memory."""
        return any(not self.seen(*x) for i in self._at(face, cog) for x in self.found[i])

    def _at(self, face: int | None, cog: np.ndarray) -> list[int]:
        """The indices of the states on `face` within `radius` of `cog`."""
        c = np.asarray(cog, float)[:2]
        return [i for i, (f, p) in enumerate(self.states) if f == face and np.linalg.norm(c - p) < self.radius]
