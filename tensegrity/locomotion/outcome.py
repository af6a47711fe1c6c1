"""What a run produced (design.md section 6): its outcome (one of OUTCOMES) and message, its
`Step`s (plan, attempts, face after), the samples, and `describe`, the run in words. The runs
themselves are made by `runs` (roll_to, roll_many, roll_over)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from ..physics import contact as ct
from ..physics import dynamics as d
from ..physics import topology as topo
from .control import RollResult
from .lockstep import Record
from .plan import Plan

if TYPE_CHECKING:
    from ..physics.terrain import Terrain

__all__ = ["OUTCOMES", "Step", "Run", "action_kind", "describe", "sample"]

OUTCOMES = ("arrived", "step_limit", "stuck", "no_contact", "off_terrain", "sim_error")


@dataclass(frozen=True)
class Step:
    """One step of a run: the plan made on `face` (1-based), the attempts in order, and the
    face the robot ended on (None if on no face); `simulated`: the rolls tried in simulation
    first (`lookahead.foresee`; none with lookahead 0), in the order they were simulated;
    plan_cpu: CPU seconds (process time, all threads) the step spent planning: the plan and the
    rolls simulated ahead, not the rolls made."""

    face: int
    plan: Plan
    attempts: tuple[RollResult, ...]
    face_after: int | None
    simulated: tuple[RollResult, ...] = ()
    plan_cpu: float = 0.0

    @property
    def rolled(self) -> bool:
        """The step's last attempt rolled the robot onto another face."""
        return bool(self.attempts) and self.attempts[-1].rolled

    @property
    def used(self) -> RollResult:
        """The attempt that rolled the robot (or the last one)."""
        return self.attempts[-1]


@dataclass(frozen=True)
class Run:
    """A run. outcome: one of OUTCOMES; message: why it ended; goal (3,) m (NaN for a run over
    a list of edges); start (3,) m: the CoG at the start; steps; record: the samples; wall:
    wall-clock time, s (shared by the runs of a batch); state: the final state; start_face: the
    face the robot first settled on (None: on none, or not known); stuck_cpu: the planning CPU s of
    a last plan that made no roll (none of its simulated rolls acceptable: the run ended stuck
    there without a `Step`; else 0)."""

    outcome: str
    message: str
    goal: np.ndarray
    start: np.ndarray
    steps: tuple[Step, ...]
    record: Record
    wall: float
    state: d.State = field(repr=False)
    start_face: int | None = None
    stuck_cpu: float = 0.0

    @property
    def final(self) -> np.ndarray:
        """Final CoG (3,) m."""
        return self.record.cog[-1] if len(self.record.t) else self.start

    @property
    def distance_to_goal(self) -> float:
        """Horizontal distance of the final CoG to the goal, m (NaN without a goal)."""
        return float(np.linalg.norm(self.final[:2] - self.goal[:2]))

    @property
    def travelled(self) -> float:
        """Horizontal distance from the start to the final CoG, m."""
        return float(np.linalg.norm(self.final[:2] - self.start[:2]))

    @property
    def rolls(self) -> int:
        """Number of steps that rolled the robot."""
        return sum(1 for st in self.steps if st.rolled)

    @property
    def faces(self) -> list[int]:
        """The contact faces visited, in order (start, then after each roll); a run that made no
        roll: its start face alone (none if it came to rest on no face)."""
        first = [self.start_face] if self.start_face is not None else [st.face for st in self.steps[:1]]
        return first + [st.face_after for st in self.steps if st.rolled]


def action_kind(r: RollResult) -> str:
    """What the action of `r` was beyond its pairs, for the step lines: "" for pairs driven
    together (no weights), " (per cable: k of 24 cables)" for a per-cable weight vector (24,),
    " (weighted: #3 0.62, #7 1.00)" for a weighted pair vector (12,) (an optimised action)."""
    if r.weights is None:
        return ""
    w = np.asarray(r.weights, float)
    if w.size == topo.N_CABLES:
        return f" (per cable: {int(np.count_nonzero(w > 0))} of {topo.N_CABLES} cables)"
    return " (weighted: " + ", ".join(f"#{q + 1} {w[q]:.2f}" for q in np.flatnonzero(w > 0)) + ")"


def describe(run: Run, name: str = "", unit: str = "MPa") -> str:
    """A few lines a person can read: the outcome and every step, levels in `unit` (MPa, or V
    for the twisted strings: `RollSettings.unit`)."""
    lines = [
        f"run {name}: {run.outcome} ({run.message}); {run.rolls} rolls, "
        f"{run.travelled:.2f} m from the start"
        + ("" if np.isnan(run.goal[0]) else f", {run.distance_to_goal:.2f} m from the goal")
    ]
    for k, st in enumerate(run.steps, 1):
        r = st.used
        lines.append(
            f"  step {k}: {topo.face_label(st.face)} -> "
            f"{topo.face_label(st.face_after) if st.face_after else 'no face'}: planned "
            f"{st.plan.pairs} at {st.plan.pressure:.2f} {unit} over {st.plan.edge}; rolled by "
            f"{r.pairs}{action_kind(r)} at {r.tip_pressure:.2f} {unit} (peak {r.peak_pressure:.2f}), "
            f"{len(st.attempts)} attempt(s)"
        )
    if not run.steps:
        where = "settled on no face" if run.start_face is None else f"rests on {topo.face_label(run.start_face)}"
        lines.append(f"  no step: the robot made no roll (it {where})")
    return "\n".join(lines)


PIVOT_TOUCH = 0.002  # m: a support node this close to the terrain still touches it (the pivot edge)
ROLLING_MARGIN = -0.025  # m: the CoG projection this far outside shows a robot rolling


def sample(
    nodes: np.ndarray,
    pressure: np.ndarray,
    k0: int,
    k1: int,
    face: int,
    tip: float,
    terrain: Terrain,
    radius: float,
    which: str,
) -> int:
    """Index of a sample of one step of a run, samples k0..k1-1 of nodes (T, 12, 3) m and
    pressure (T,) MPa (the highest pair's), on `face` with tipping pressure `tip` MPa (NaN:
    none), contact spheres of `radius` m: 'stable' (the pressure at half the tipping pressure,
    the robot still on its face; else k0) or 'rolling' (pivoting on an edge of its face, the
    first sample with the CoG projection ROLLING_MARGIN outside, else the furthest; ValueError
    if the step never leaves its face)."""
    best = None
    for k in range(k0, k1):
        if which == "stable" and np.isfinite(tip) and pressure[k] >= 0.5 * tip:
            return k
        if which == "rolling":
            touching = ct.clearance(nodes[k], terrain, radius)[topo.FACES[face - 1]] < PIVOT_TOUCH
            m = ct.judge(nodes[k], face).margin
            if touching.sum() == 2 and m < 0:
                if m < ROLLING_MARGIN:
                    return k
                if best is None or m < best[0]:
                    best = (m, k)
    if which == "stable":
        return k0
    if best is not None:
        return best[1]
    raise ValueError("the step never leaves its face")
