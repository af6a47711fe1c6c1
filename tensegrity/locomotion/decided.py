"""A candidate roll simulated ahead ends once its outcome is decided (issue 30's planning cost;
docs/design.md §6). `until_decided` wraps the roll controller of one candidate of
`lookahead.foresee` and ends it, with the RollResult the planner judges, as soon as:

- slid: its CoG is more than SLIDE m (horizontally) from where it started: a tumble or a slide,
  whatever follows (the result then on no face, not rolled);
- at rest at its held level without rolling (unbraked rolls only): every pair of the action at
  the top of its ramp, the same command as the check before, the robot on its start face with no
  support node lifted, its CoG slower than REST_SPEED and, for the twisted strings, every motor
  of the action turning slower than MOTOR_REST (twisted to its level, or held by its gears'
  friction) for _CALM checks in a row: the hold at the top would end in giving
  up (the result: not rolled, on its face), as the roll controller's own cut when the ramp
  gives up (`control.roll_controller`'s `foresee`). The braked rolls keep their whole hold
  (the brake fades out over it and can still roll the robot) and their release: one at rest at
  its top with the brake faded out (volts, 15 deg, for _CALM checks, the motors stalled) still
  rolled onto another face as its level fell and the brake came back on (docs/benchmarks.md,
  "Braked candidates simulated in chunks").

A roll that lands on another face is simulated to its end, settled as the run settles it: its
CoG there is what the planner ranks it by (with the twisted strings the strands unwinding after
the landing move the CoG by centimetres: not decided before they have).
"""

from __future__ import annotations

import numpy as np

from ..physics import topology as topo
from .control import RollResult
from .lockstep import Controller, Obs, widths
from .settings import RollSettings

__all__ = ["MOTOR_REST", "REST_SPEED", "SLIDE", "until_decided"]

SLIDE = 0.5  # m: a roll that moves the CoG further (horizontally) slid: a tumble (issue 30's definition)
REST_SPEED = 1e-3  # m/s: a CoG this slow at the top of the ramp is at rest (settle_speed is 0.03)
MOTOR_REST = 0.15  # rad/s (0.3 % of the no-load speed): a motor this slow has twisted its strands to its level
_CALM = 3  # checks in a row (control._CALM)


def _held(pres: np.ndarray, top: np.ndarray, j: int, last: np.ndarray | None) -> bool:
    """The command `pres` (12,) is the action's held level `top` (12,) (nothing else driven) and
    the same as the `last` one; pair j (0-based, weight 1) tested first (the ramp: below it)."""
    if last is None or pres.size != top.size or pres[j] != top[j]:  # a brake coming off first: (12,)
        return False
    return bool(np.array_equal(pres, top) and np.array_equal(pres, last))


def until_decided(
    gen: Controller,
    obs: Obs,
    pairs: tuple[int, ...],
    w: np.ndarray | None,
    s: RollSettings,
    max_pressure: float,
    braked: bool,
) -> Controller:
    """The roll controller `gen` of a candidate (1-based `pairs`, or weights `w` (12,) or (24,)) started
    from the observation `obs`, with settings `s`, ramping to max_pressure (MPa or V), `braked`
    or not, ended as soon as its outcome is decided (module docstring). Returns its
    (RollResult, last observation)."""
    cog0, start = obs.cog, obs.face
    weights = np.zeros(topo.N_PAIRS) if w is None else np.asarray(w, float)
    if w is None:
        weights[np.asarray(pairs, int) - 1] = 1.0
    weights = widths(weights, obs.pressure)  # per cable if the robot commands its cables (`control`)
    top = np.where(weights > 0, np.minimum(max_pressure * weights, s.max_level), 0.0)
    support = topo.FACES[start - 1] if start is not None else None
    base = None if support is None else obs.gap[support].copy()
    on = np.flatnonzero(weights > 0)
    cables = on if weights.size == topo.N_CABLES else topo.PAIR_CABLES[on].ravel()
    j = int(np.argmax(weights))  # a pair of weight 1: its command is the ramp's level
    calm, last = 0, None
    pres = next(gen)
    while True:
        ob = yield pres
        cog = ob.cog
        if np.hypot(cog[0] - cog0[0], cog[1] - cog0[1]) > SLIDE:
            gen.close()
            return RollResult(pairs, False, start, None, np.nan, np.nan, obs.t, ob.t, cog0, cog, weights=w), ob
        if not braked and support is not None and ob.face == start and _held(pres, top, j, last):
            still = ob.speed < REST_SPEED and bool(np.all(ob.gap[support] - base <= s.lift_tolerance))
            if still and s.motors is not None:
                st = ob.state
                still = (
                    st is not None
                    and st.motor_speed is not None
                    and bool(np.all(np.abs(st.motor_speed[0, cables]) <= MOTOR_REST))
                )
            calm = calm + 1 if still else 0
        else:
            calm = 0
        if calm >= _CALM:
            gen.close()
            res = RollResult(pairs, False, start, start, np.nan, max_pressure, obs.t, ob.t, cog0, cog, weights=w)
            return res, ob
        last = pres
        try:
            pres = gen.send(ob)
        except StopIteration as stop:
            return stop.value
