"""Braking and escaping, chosen from the workspace (issue 10, item 3; docs/design.md §6).

On a slope (or a tilted patch of rough ground) the unactuated robot may not stay on the face it
lands on: its CoG projection along gravity lies near or beyond the downhill edge. `Brake` holds it
there with the single pair and level the workspace predicts to move the projection furthest
inside the support triangle, chosen as the robot lands (from its pose rotated onto the next face,
`contact.roll_over`) so that it is on before the robot can tumble on. It keeps a robot standing on a
20 deg slope where it tumbles off without, and with a slow release of the rolling pressure
(`brake_release_time`) it keeps most rolls on 15 deg slopes under control; not yet on 20 deg
(benchmarks/bench_locomotion.py). It acts only on even inclines (`Brake.active`).
`escape` orders the actions not yet tried on a face where the planned candidates all failed
("stuck"): those predicted to roll toward the target first, then the others.
"""

from __future__ import annotations

import itertools

import numpy as np

from ..physics import contact as ct
from ..physics import topology as topo
from ..physics.terrain import Terrain
from ..workspace.lookup import Workspace, predict
from .plan import candidates, direction_of

__all__ = ["Brake", "hold", "escape", "on_incline"]


def _actions(workspace: Workspace, face: int, combos: bool) -> list[tuple[int, ...]]:
    singles = [int(q) for q in workspace.pairs(face)]
    out = [(q,) for q in singles]
    return out + (list(itertools.combinations(singles, 2)) if combos else [])


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


def on_incline(terrain: Terrain, face: int, nodes: np.ndarray, min_tilt: float) -> bool:
    """The ground under 1-based `face` of the robot `nodes` (12, 3) m is one plane tilted by at
    least `min_tilt` deg (`Terrain.incline`; uneven ground is not)."""
    p = np.asarray(nodes)[topo.FACES[face - 1]]
    return bool(terrain.incline(p[:, 0], p[:, 1]) >= min_tilt)  # NaN: uneven


class Brake:
    """The braking policy of a run: `for_face(face, nodes)` returns the pressures (12,) MPa of
    `hold` on `face`, chosen once per visit of a face (a new face, a new choice) so that the
    actuation does not chatter while the robot settles. Given the `terrain`, it brakes only
    where the ground under the face is an even incline of at least `min_tilt` deg (`active`):
    on rough ground the workspace's planar prediction misleads the brake, which then throws the
    robot more often than it holds it (benchmarks/bench_locomotion.py, config/README.md)."""

    def __init__(
        self,
        workspace: Workspace,
        margin: float,
        confirm: int = 3,
        terrain: Terrain | None = None,
        min_tilt: float = 0.0,
    ):
        self.workspace, self.margin, self.confirm = workspace, float(margin), int(confirm)
        self.terrain, self.min_tilt = terrain, float(min_tilt)
        self._face, self._p, self._seen = None, np.zeros(topo.N_PAIRS), (None, 0)

    def active(self, face: int, nodes: np.ndarray) -> bool:
        """Braking applies to the robot `nodes` (12, 3) m on 1-based `face`: everywhere without
        a terrain, else where the ground under the face's nodes is one plane tilted by at least
        min_tilt deg (`Terrain.incline`)."""
        return self.terrain is None or on_incline(self.terrain, face, nodes, self.min_tilt)

    def _hold(self, face: int, nodes: np.ndarray) -> np.ndarray:
        if not self.active(face, nodes):
            return np.zeros(topo.N_PAIRS)
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
