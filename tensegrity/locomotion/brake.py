"""Braking and escaping, chosen from the workspace (issue 10, item 3; docs/design.md §6).

On a slope (or a tilted patch of rough ground) the unactuated robot may not stay on the face it
lands on: its CoG projection along gravity lies near or beyond the downhill edge. `Brake` holds it
there with the single pair and level the workspace predicts to move the projection furthest
inside the support triangle, chosen as the robot lands (from its pose rotated onto the next face,
`contact.roll_over`) so that it is on before the robot can tumble on. It keeps a robot standing on a
20 deg slope where it tumbles off without, and with a slow release of the rolling pressure
(`brake_release_time`) it keeps most rolls on 15 deg slopes under control; not yet on 20 deg
(benchmarks/bench_locomotion.py). It acts only where the unbraked robot is predicted not to stand
on its face or on a face it can roll onto (`Brake.active`), whatever the ground.
`escape` orders the actions not yet tried on a face where the planned candidates all failed
("stuck"): those predicted to roll toward the target first, then the others.
"""

from __future__ import annotations

import itertools

import numpy as np

from ..physics import contact as ct
from ..physics import topology as topo
from ..workspace.lookup import Workspace, predict
from .plan import candidates, direction_of

__all__ = ["Brake", "hold", "escape", "ramp_fade"]


def _actions(workspace: Workspace, face: int, combos: bool) -> list[tuple[int, ...]]:
    singles = [int(q) for q in workspace.pairs(face)]
    out = [(q,) for q in singles]
    return out + (list(itertools.combinations(singles, 2)) if combos else [])


def ramp_fade(level: float, expect: float) -> float:
    """Share of the start face's brake left at `level` (MPa or V) of a ramp whose roll is expected
    at `expect` (NaN or negative: the brake is not handed over, 1; 0: gone at once)."""
    if not expect >= 0:
        return 1.0
    return max(0.0, 1.0 - level / expect) if expect > 0 else 0.0


def hold(workspace: Workspace, face: int, nodes: np.ndarray, margin: float) -> np.ndarray:
    """Pair pressures (12,) MPa that keep the robot resting on 1-based `face` with nodes
    (12, 3) m: zero if the unactuated CoG projection along gravity is predicted at least `margin`
    m inside the support triangle; else the single pair and level with the largest predicted
    margin (if larger than the unactuated one). The largest, not the least that reaches
    `margin`: the free-mode workspace leaves out how the robot moves as it is set down or lands
    (its static sag is only 0-7 mm at 15-20 deg, by the gravity-aware workspace), and on a
    20 deg slope a brake predicted 35 mm inside holds, 20 mm does not.
    Combinations are not used: superposed, they hold worse than predicted."""
    out = np.zeros(topo.N_PAIRS)
    acts = _actions(workspace, face, False)
    if not acts:
        return out
    pred = predict(workspace, face, nodes, acts)
    if pred.margin[0, 0] >= margin:
        return out
    a, k = np.unravel_index(int(np.argmax(pred.margin[:, 1:])), pred.margin[:, 1:].shape)
    if pred.margin[a, k + 1] > pred.margin[0, 0]:
        out[acts[a][0] - 1] = pred.pressure[k + 1]
    return out


class Brake:
    """The braking policy of a run: `for_face(face, nodes)` returns the pressures (12,) MPa of
    `hold` on `face`, chosen once per visit of a face (a new face, a new choice) so that the
    actuation does not chatter while the robot settles. A roll is braked only where the brake
    acts (`active`); elsewhere it is the unbraked roll (`control.roll_controller`)."""

    def __init__(self, workspace: Workspace, margin: float, confirm: int = 3):
        self.workspace, self.margin, self.confirm = workspace, float(margin), int(confirm)
        self._face, self._p, self._seen = None, np.zeros(topo.N_PAIRS), (None, 0)

    def active(self, face: int, nodes: np.ndarray) -> bool:
        """The unbraked robot `nodes` (12, 3) m is predicted not to stand on 1-based `face` or on
        a face across one of its edges (posed as it lands there, `contact.roll_over`): `hold`
        would brake it there (its CoG projection predicted less than `margin` inside)."""
        if hold(self.workspace, face, nodes, self.margin).any():
            return True
        for k in range(3):
            nxt, posed = ct.roll_over(nodes, face, topo.edge_nodes(face, k))
            if hold(self.workspace, nxt, posed, self.margin).any():
                return True
        return False

    def state(self) -> tuple:
        """What a roll's simulation reads of this brake besides its workspace: the braced face, its
        pressures (as bytes) and the face seen in a row (`for_face`)."""
        return self._face, self._p.tobytes(), self._seen

    def forget(self) -> None:
        """Drop the braced face (after a roll made without this brake): the next face is taken at once."""
        self._face, self._seen = None, (None, 0)

    def _hold(self, face: int, nodes: np.ndarray) -> np.ndarray:
        return hold(self.workspace, face, nodes, self.margin)

    def for_face(self, face: int | None, nodes: np.ndarray) -> np.ndarray:
        """Pressures (12,) MPa for the robot on `face` (None: in the air, keep the last). A
        face other than the braced one is taken once seen `confirm` times in a row (the first
        time, with nothing braced yet), so that a momentary contact while rocking does not
        switch the brake."""
        if face is not None and face != self._face:
            n = self._seen[1] + 1 if self._seen[0] == face else 1
            self._seen = (face, n)
            if n >= self.confirm or self._face is None:
                self._face, self._p = face, self._hold(face, nodes)
        return self._p.copy()

    def landing(self, face: int, pivot: tuple[int, int], nodes: np.ndarray) -> np.ndarray:
        """Pressures (12,) MPa of `hold` on the face across edge `pivot` (1-based nodes) of
        `face`, for the robot `nodes` (12, 3) m tipping over it, posed as it will land
        (`contact.roll_over`); that face's choice for its visit."""
        nxt = topo.neighbour(face, pivot)
        self._seen = (None, 0)
        self._face, self._p = nxt, self._hold(nxt, ct.roll_over(nodes, face, pivot)[1])
        return self._p.copy()


def escape(
    workspace: Workspace,
    face: int,
    nodes: np.ndarray,
    tried: set[tuple[int, ...]],
    *,
    direction: np.ndarray | None = None,
    goal: np.ndarray | None = None,
) -> list[tuple[int, ...]]:
    """Actions (single pairs and two-pair combinations) not in `tried`, the way off 1-based
    `face` when the planned candidates all failed: those predicted to roll the robot first, over
    the edge best aligned with `direction` (world vector) or the direction to `goal` (world
    point, m), then the others, the
    furthest outside at the highest level first."""
    acts = [a for a in _actions(workspace, face, True) if a not in tried]
    if not acts:
        return []
    u = direction_of(nodes, direction, goal)
    cands = candidates(workspace, face, nodes, acts, u)
    cands.sort(
        key=lambda c: (
            not c.predicted,
            -round(c.alignment, 9) if c.predicted else 0.0,
            round(c.reach, 9),
            len(c.pairs),
            c.pairs,
        )
    )
    return [c.pairs for c in cands]
