"""The planner (paper III.C steps 2-3; docs/design.md §6).

On the current face, rank every pair (and, when no single pair makes progress, every two-pair
combination, from the measured two-pair curves or else by superposing the single-pair curves,
`Workspace.curve`) by how well the outward direction
of the edge its CoG projection crosses matches the target, then by the least pressure. `plan`
returns a `Plan` with its reasons, sentences a person can check.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..physics import contact as ct
from ..physics import frames
from ..physics import topology as topo
from ..physics.terrain import Terrain
from ..workspace.lookup import Face, Workspace, predict

__all__ = ["Candidate", "Plan", "candidates", "direction_of", "plan"]


@dataclass(frozen=True)
class Candidate:
    """One way to roll: `pairs` (1-based) driven at the same pressure. edge: the crossed edge
    (1-based nodes) of the predicted CoG projection, or the edge it approaches most if it never
    crosses one; next_face: the face across it; pressure: predicted least pressure that rolls
    the robot (`frames.first_crossing` of the margin), MPa, NaN if none within the workspace;
    reach: predicted margin at the highest level, m (negative: outside); alignment: cosine
    between the edge's outward direction (horizontal) and the target direction."""

    pairs: tuple[int, ...]
    edge: tuple[int, int]
    next_face: int
    pressure: float
    reach: float
    alignment: float

    @property
    def predicted(self) -> bool:
        """The workspace predicts that this candidate rolls the robot."""
        return bool(np.isfinite(self.pressure))

    def label(self) -> str:
        """The pairs as a person writes them, e.g. '#10' or '#9+#10'."""
        return "+".join(f"#{p}" for p in self.pairs)


@dataclass(frozen=True)
class Plan:
    """The chosen actuation on `face` (1-based) and why. pairs: 1-based pairs driven together
    (usually one); pressure: predicted least rolling pressure, MPa (NaN if the workspace predicts
    no roll: then the roll escalates to the highest level); edge, next_face, reach (m) and
    alignment as in `Candidate`; margin: the current CoG projection's margin, m; direction (3,):
    horizontal unit target direction, world; candidates: every option in the order to try (the
    first is the choice); reasons: sentences a person can check."""

    face: int
    pairs: tuple[int, ...]
    pressure: float
    edge: tuple[int, int]
    next_face: int
    reach: float
    alignment: float
    margin: float
    direction: np.ndarray
    candidates: tuple[Candidate, ...]
    reasons: tuple[str, ...]

    @property
    def pair(self) -> int:
        """The first (usually the only) pair of the plan."""
        return self.pairs[0]

    @property
    def predicted(self) -> bool:
        """The workspace predicts that the plan rolls the robot."""
        return bool(np.isfinite(self.pressure))

    def __str__(self) -> str:
        return "\n".join(self.reasons)


def direction_of(nodes: np.ndarray, direction: ArrayLike | None, goal: ArrayLike | None) -> np.ndarray:
    """Horizontal unit target direction (3,), world, toward `goal` (m) or along `direction`."""
    if (direction is None) == (goal is None):
        raise ValueError("give exactly one of direction (a world vector) or goal (a world point)")
    if goal is not None:
        gpt = np.asarray(goal, float).ravel()
        if gpt.size not in (2, 3) or not np.all(np.isfinite(gpt)):
            raise ValueError(f"goal must be a finite world point (x, y) or (x, y, z) m, got {goal!r}")
        v = gpt[:2] - nodes.mean(axis=0)[:2]
    else:
        v = np.asarray(direction, float).ravel()
        if v.size not in (2, 3) or not np.all(np.isfinite(v)):
            raise ValueError(f"direction must be a finite 2- or 3-vector, got {direction!r}")
        v = v[:2]
    n = float(np.linalg.norm(v))
    if n < 1e-6:
        raise ValueError(
            "the target direction is zero: the goal is right above the robot's CoG"
            if goal is not None
            else "direction has no horizontal component"
        )
    return np.array([v[0] / n, v[1] / n, 0.0])


def candidates(
    workspace: Workspace, f: int, nodes: np.ndarray, actions: list[tuple[int, ...]], u: np.ndarray
) -> list[Candidate]:
    """One Candidate per action on 1-based face f, for target direction u (3,)."""
    pred = predict(workspace, f, nodes, actions)
    out_world = ct.edge_outward(nodes[topo.FACES[f - 1]])
    horiz = out_world[:, :2] / np.maximum(np.linalg.norm(out_world[:, :2], axis=1, keepdims=True), 1e-12)
    align = horiz @ u[:2]
    res = []
    for a, act in enumerate(actions):
        p, k = frames.first_crossing(pred.pressure, pred.margin[a])
        if k >= 0:  # the edge crossed at the first level outside
            e = frames.crossed_edge(pred.projection_2d[a, k], pred.support[a, k])
        else:  # never crosses: the edge it comes closest to at the highest level
            e = int(np.argmin(pred.edge_dist[a, -1]))
        edge = topo.edge_nodes(f, e)
        res.append(
            Candidate(
                tuple(int(x) for x in act), edge, topo.neighbour(f, edge), p, float(pred.margin[a, -1]), float(align[e])
            )
        )
    return res


def plan(
    workspace: Workspace,
    face: Face,
    nodes: ArrayLike,
    *,
    direction: ArrayLike | None = None,
    goal: ArrayLike | None = None,
    terrain: Terrain | None = None,
    avoid: Iterable[Face] = (),
    combine: bool = True,
    min_alignment: float = 0.0,
    unit: str = "MPa",
) -> Plan:
    """Choose the actuation that rolls the robot standing on `face` (1..20 or three node
    numbers) with node positions `nodes` (12, 3) m toward a target `direction` (world vector)
    or `goal` (world point, m), from the workspace (paper III.C steps 2-3).

    Ranking: candidates predicted to roll come first, by the alignment of the crossed edge's
    outward direction with the target (best first), then single pairs before combinations,
    then the least pressure. A roll onto a face in `avoid` (faces, e.g. the last few visited)
    is ranked after the others, so that the robot does not rock back and forth or go round in
    a circle. Two-pair combinations are added when no single pair is predicted to roll onto a
    face not avoided over an edge with alignment > min_alignment (e.g. uphill on a slope); if
    `combine` is False they never are. Candidates not predicted to roll follow, closest to
    rolling first. `terrain`, if given, is checked to be under every node. `unit`: the
    workspace's level in the reasons, MPa or V (a workspace in volts, `RollSettings.unit`)."""
    f = topo.face_number(face)
    p = ct.check_nodes(nodes)
    if terrain is not None:
        ct.clearance(p, terrain, 0.0)  # raises if nothing is under a node
    singles = [(int(q),) for q in workspace.pairs(f)]
    if not singles:
        raise ValueError(f"the workspace has no curve for face {topo.face_label(f)}")
    u = direction_of(p, direction, goal)
    avoid = {topo.face_number(a) for a in avoid}
    cands = candidates(workspace, f, p, singles, u)
    good = [c for c in cands if c.predicted and c.next_face not in avoid and c.alignment > min_alignment]
    combined = False
    if not good and combine and len(singles) > 1:
        cands += candidates(workspace, f, p, list(itertools.combinations([s[0] for s in singles], 2)), u)
        combined = True

    def rank(c: Candidate):
        back = c.next_face in avoid
        if c.predicted:
            return (0, back, -round(c.alignment, 9), len(c.pairs), c.pressure, c.pairs)
        return (1, back, c.alignment <= min_alignment, round(c.reach, 9), len(c.pairs), c.pairs)

    cands.sort(key=rank)
    best = cands[0]
    here = ct.judge(p, f)
    reasons = _reasons(workspace, f, here.margin, u, combined, best, cands[1:], avoid)
    if unit != "MPa":
        reasons = [r.replace(" MPa", f" {unit}") for r in reasons]
    return Plan(
        f,
        best.pairs,
        best.pressure,
        best.edge,
        best.next_face,
        best.reach,
        best.alignment,
        here.margin,
        u,
        tuple(cands),
        tuple(reasons),
    )


def _reasons(
    workspace: Workspace,
    f: int,
    margin: float,
    u: np.ndarray,
    combined: bool,
    best: Candidate,
    rest: Sequence[Candidate],
    avoid: set[int],
) -> list[str]:
    """The sentences of a Plan: where the robot stands, the target, the choice, the options."""
    reasons = [
        f"standing on face {topo.face_label(f)} ({topo.FACE_TYPES[f - 1]}); the CoG projection "
        f"is {margin * 1e3:.1f} mm inside the support triangle",
        f"target direction {math.degrees(math.atan2(u[1], u[0])):.1f} deg from +x",
    ]
    if combined:
        how = "measured two-pair curves" if workspace.combos is not None else "superposed workspace curves"
        reasons.append(
            f"no single pair is predicted to roll the robot toward the target: two-pair combinations ({how}) considered"
        )
    if best.predicted:
        reasons.append(
            f"chosen {best.label()} at {best.pressure:.2f} MPa: the CoG projection leaves the "
            f"triangle over edge {best.edge[0]}-{best.edge[1]} (alignment {best.alignment:+.2f}) "
            f"and reaches {-best.reach * 1e3:.1f} mm outside at {workspace.max_pressure:g} MPa; "
            f"next face {topo.face_label(best.next_face)}"
        )
        if best.next_face in avoid:
            reasons.append(
                f"face {topo.face_label(best.next_face)} was visited recently: rolling "
                "back onto it only because nothing else is predicted to roll"
            )
    else:
        reasons.append(
            f"the workspace predicts no roll: the best option, {best.label()} toward edge "
            f"{best.edge[0]}-{best.edge[1]}, keeps the CoG projection {best.reach * 1e3:.1f} mm "
            f"inside at {workspace.max_pressure:g} MPa; the simulation will escalate to that level"
        )
    others = [c for c in rest if c.predicted][:4] or list(rest[:3])
    if others:
        reasons.append(
            "next options: "
            + "; ".join(
                f"{c.label()} over {c.edge[0]}-{c.edge[1]} "
                + (f"at {c.pressure:.2f} MPa" if c.predicted else "(no roll predicted)")
                + f", alignment {c.alignment:+.2f}"
                for c in others
            )
        )
    return reasons
