"""How far a robot is from its goal, in rolls (issue 30 item 2; docs/design.md §6): the travel and
lift of one roll of the robot as it stands (`stride`), and the rolls still needed (`rolls_to_goal`),
by which `lookahead.choose` ranks the simulated rolls; the costs of a run over edges (`over_edge`) or along
a direction (`along`)."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..physics import topology as topo
from ..physics.terrain import Terrain
from .control import RollResult

__all__ = ["along", "over_edge", "rolls_to_goal", "stride"]


def stride(nodes: np.ndarray, face: int) -> tuple[float, float]:
    """(travel m, lift m) of one roll of the robot `nodes` (12, 3) on 1-based `face`, means over
    the face's three edges: the CoG's travel 2 r and its rise sqrt(h^2 + r^2) - h as it tips onto
    the edge, r the distance from the CoG's foot on the face plane to the edge, h its height above
    that plane. A rigid roll onto a congruent face; the robot's faces differ (two types), so a
    single roll's travel differs from this by up to ~30 %, its lift by up to ~50 %."""
    p = np.asarray(nodes, float)
    tri = p[topo.FACES[face - 1]]
    c = p.mean(axis=0)
    n = np.cross(tri[1] - tri[0], tri[2] - tri[0])
    n /= np.linalg.norm(n)
    h = abs(float((c - tri[0]) @ n))
    foot = c - ((c - tri[0]) @ n) * n
    r = np.empty(3)
    for k in range(3):
        a, b = tri[k], tri[(k + 1) % 3]
        e = (b - a) / np.linalg.norm(b - a)
        v = foot - a
        r[k] = np.linalg.norm(v - (v @ e) * e)
    return float(np.mean(2 * r)), float(np.mean(np.hypot(h, r) - h))


def rolls_to_goal(point: np.ndarray, goal: np.ndarray, terrain: Terrain, travel: float, lift: float) -> float:
    """Rolls still needed from the CoG `point` (3,) m to `goal` (3,) m (on the ground): the
    horizontal distance over the travel of one roll, plus the height the ground under the CoG
    lies below the goal's over the lift of one roll (each roll can raise the robot by at most
    about its lift against gravity: height lost on an incline costs the rolls that regain it).
    An estimate for ranking, not a count: rolls zig-zag, and on a slope not every roll climbs."""
    c = np.asarray(point, float)
    below = max(0.0, float(goal[2] - terrain.height(c[0], c[1])))
    return float(np.linalg.norm(c[:2] - np.asarray(goal[:2], float))) / travel + below / lift


def over_edge(face: int, edge: tuple[int, int]) -> Callable[[RollResult], float]:
    """The cost of a roll toward `edge` (1-based nodes) of 1-based `face`: 0 onto the face across
    it, else 1 (another face: the plan may choose any pair, not any edge)."""
    to = topo.neighbour(face, edge)
    return lambda r: 0.0 if r.face_after == to else 1.0


def along(direction: np.ndarray, travel: float) -> Callable[[RollResult], float]:
    """The cost of a roll toward a world `direction` (3,): minus its CoG's travel along it, in rolls."""
    u = np.asarray(direction, float)[:2]
    u = u / np.linalg.norm(u)
    return lambda r: -float(np.subtract(r.cog_after, r.cog_before)[:2] @ u) / travel
