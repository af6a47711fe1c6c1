"""The commands of a braked candidate of `lookahead.foresee` predicted, for `ahead.lockstep_ahead`
to simulate them several check intervals per call (issue 30/31's planning cost; docs/design.md §6).

`Braked` is to a braked roll (`control.roll_controller` with a brake) what `ahead.Ramp` is to an
unbraked one: the controller's own arithmetic, replayed from its last two commands. A wrong
prediction costs only time: `ahead` hands the controller the simulated observations one interval
at a time and, at the first command that differs, simulates the batch again up to there.
"""

from __future__ import annotations

import numpy as np

from .ahead import Ramp
from .brake import ramp_fade
from .control import _slew
from .lockstep import widths
from .settings import RollSettings

__all__ = ["Braked"]


class Braked(Ramp):
    """The braked roll of an action of weights w (12,) or (24,) up to max_pressure (`roll_controller`
    with a brake) while it does not roll: the brake `held` (12,) of the start face (on both cables
    of each pair for (24,) weights), faded as the level
    nears `expect` (NaN: not faded) and over hold_time at the top, back on as the level comes
    down, moved toward at most at brake_rate from the last command (`control._slew`); the
    action's pairs at least min(L w, s.max_level). Predicted from a pair of weight 1 that the
    brake leaves at 0 (its command is the level): its ramp, its top, its release from the top;
    else as `Ramp` where the command stays the same (a hold, the brake faded out, a settling),
    but with the twisted strings only while that pair is driven (settling, the controller reads
    the motors' state, `lockstep.rested`)."""

    def __init__(self, w: np.ndarray, s: RollSettings, max_pressure: float, held: np.ndarray, expect: float):
        super().__init__(w, s, max_pressure)
        self.s, self.brake, self.expect = s, widths(np.asarray(held, float), self.w), float(expect)
        free = np.flatnonzero((self.w == 1.0) & (self.brake == 0))
        self.j = int(free[0]) if free.size else -1  # the pair whose command is the level (-1: none)
        self.down = max_pressure * s.interval / s.brake_release_time  # the release's step from the top
        self._tops: tuple[list, dict] | None = None

    def _step(self, level: float, last: np.ndarray, fade: float | None = None) -> np.ndarray:
        """The controller's command at `level` after the command `last` (its own numbers), the
        brake faded by `fade` (None: as the ramp fades it)."""
        if fade is None:
            fade = ramp_fade(level, self.expect)  # the min over a rising ramp: its latest
        pres = _slew(self.brake * fade, last, self.s)
        lanes = self.w > 0
        pres[lanes] = np.maximum(pres[lanes], np.minimum(level * self.w[lanes], self.top))
        return pres

    def _top(self) -> tuple[list, dict]:
        """The commands at the top while the brake fades out, and each one's index."""
        if self._tops is None:
            cmds: list[np.ndarray] = []
            fade = ramp_fade(self.max, self.expect)  # the ramp's last
            cmd = self._step(self.max, self.brake * fade, fade)  # the ramp's last command (not slewed)
            while fade > 1e-9:
                fade = max(0.0, fade - self.s.interval / self.s.hold_time)
                cmd = self._step(self.max, cmd, fade)
                cmds.append(cmd)
            self._tops = cmds, {c.tobytes(): k for k, c in enumerate(cmds)}
        return self._tops

    def next(self, prev: np.ndarray, cmd: np.ndarray, n: int) -> np.ndarray | None:
        """The next (up to n) commands (n', 12) if `prev` and `cmd` are two of the roll's
        (class docstring); else None."""
        if n < 1 or self.j < 0 or self.max > self.top or prev.size != self.w.size or cmd.size != self.w.size:
            return None
        if np.array_equal(prev, cmd):
            if self.volts and not cmd[self.j] > 0:
                return None
            return np.broadcast_to(cmd, (n, cmd.size))
        a, b = float(prev[self.j]), float(cmd[self.j])
        out: list[np.ndarray] = []
        if a == b == self.max:  # the top, the brake fading out
            cmds, index = self._top()
            k = index.get(cmd.tobytes())
            out = [] if k is None else cmds[k + 1 : k + 1 + n]
        elif b < self.max and b == min(a + self.inc, self.max) and np.array_equal(self._step(b, prev), cmd):
            for _ in range(n):  # the ramp
                b = min(b + self.inc, self.max)
                if b >= self.max:
                    break
                out.append(self._step(b, out[-1] if out else cmd))
        elif a > b > 0 and b == max(0.0, a - self.down) and np.array_equal(self._step(b, prev, 1.0), cmd):
            for _ in range(n):  # the release from the top, the brake coming back on
                b = max(0.0, b - self.down)
                if b <= 0.0:
                    break
                out.append(self._step(b, out[-1] if out else cmd, 1.0))
        return np.asarray(out) if out else None
