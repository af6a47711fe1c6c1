"""Rolls simulated ahead, kept for the step after (issue 30's planning cost; docs/design.md §6).

Before a roll is made, `drive.onward` simulates the next step's first candidates from its landing;
the run lands as foreseen, to the last bit (tests/locomotion/test_onward.py), so the next step
starts from those simulations instead of repeating them. `Foreseen` is `lookahead.foresee` with a
memory of its results, keyed by all a candidate's simulation depends on within a run: the robot's
state, time and levels, the ramp's top, the action with its planned pressure and, where the brake
acts on the start face, the brake's own state (`brake.Brake.state`; a braked roll leaves the brake
braced for its landing, which the look past it does not know: there nothing is reused).
"""

from __future__ import annotations

from collections.abc import Sequence

from ..physics.params import Params
from ..physics.terrain import Terrain
from . import lookahead
from .ahead import row_bytes
from .brake import Brake
from .control import RollResult
from .lockstep import Obs
from .settings import RollSettings

__all__ = ["Foreseen"]


class Foreseen:
    """`lookahead.foresee` for one run (its params, terrain and settings), each candidate simulated
    once from a start; `keep(obs)` drops the rolls from other states (a run never returns to a
    state to the last bit)."""

    def __init__(self):
        self._rolls: dict[tuple, dict[tuple, RollResult]] = {}

    def keep(self, obs: Obs) -> None:
        """Drop every roll simulated from a state other than `obs.state`."""
        at = row_bytes(obs.state, 0)
        self._rolls = {k: v for k, v in self._rolls.items() if k[0] == at}

    def __call__(
        self,
        params: Params,
        terrain: Terrain,
        s: RollSettings,
        obs: Obs,
        todo: Sequence[lookahead.Act],
        max_pressure: float,
        brake: Brake | None,
        expect: dict[tuple[int, ...], float],
    ) -> list[RollResult]:
        """`lookahead.foresee(params, terrain, s, obs, todo, max_pressure, brake, expect)`, simulating
        only the candidates not simulated from this start before."""
        acts = obs.face is not None and brake is not None and brake.active(obs.face, obs.nodes)
        start = (row_bytes(obs.state, 0), obs.t, obs.pressure.tobytes(), max_pressure, brake.state() if acts else None)
        rolls = self._rolls.setdefault(start, {})
        keys = [(a, _planned_pressure(a, expect)) for a in todo]
        new = list(dict.fromkeys(k for k in keys if k not in rolls))
        for k, r in zip(
            new, lookahead.foresee(params, terrain, s, obs, [a for a, _ in new], max_pressure, brake, expect)
        ):
            rolls[k] = r
        return [rolls[k] for k in keys]


def _planned_pressure(act: lookahead.Act, expect: dict) -> float | None:
    """The planned pressure MPa a pairs action `act` ramps toward (`lookahead.foresee`), None if none."""
    p = expect.get(act[0]) if lookahead.weights_of(act) is None else None
    return None if p is None or p != p else float(p)
