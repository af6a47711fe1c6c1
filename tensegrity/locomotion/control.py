"""Rolling control in the dynamic simulator (paper III.C step 4; docs/design.md §6).

A roll ramps the pressure slowly (quasi-static, as the paper's rolling is), holds it once a
support node lifts, releases it once the unactuated robot would fall over the pivot edge anyway
(`contact.past_edge`), catches the robot on the next face and lets it settle. Controllers are
generators: they yield the pair pressures (12,) MPa for the next check interval and receive an
observation of the robot after it; `yield from` composes them, and their return value is their
result; `lockstep.lockstep` drives any number of them as one simulated batch. Each robot's
samples are recorded (`lockstep.Record`). With `RollSettings.motors` (the prototype's twisted
strings) the same law drives the motor voltages: every pressure below is then a voltage, and
MPa reads V (docs/design.md §6, "Locomotion in volts").
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from ..physics import contact as ct
from ..physics import dynamics as d
from ..physics import topology as topo
from ..physics.params import Params
from ..physics.schedule import check_pressures, hold_step
from ..physics.terrain import Terrain
from .brake import Brake, ramp_fade
from .lockstep import Controller, Obs, Record, lockstep, rested, widths
from .settings import RollSettings

__all__ = ["RollResult", "action_weights", "roll", "roll_controller", "settle", "settle_controller"]


@dataclass(frozen=True)
class RollResult:
    """One roll attempt. rolled: the robot ended on another face; face_before/face_after
    (1-based; face_after None if it settled on no face); tip_pressure: the pressure held when a
    support node lifted, if the robot then rolled (MPa, NaN if not; the peak pressure if it
    rolled only after the ramp gave up, as the pressure came down); peak_pressure MPa;
    t_start, t_end s; cog_before, cog_after (3,) m world. From `roll` also the final `state`
    and the `record`. weights (12,): the action's weight vector if it was given as one (None:
    the `pairs` at one pressure)."""

    pairs: tuple[int, ...]
    rolled: bool
    face_before: int
    face_after: int | None
    tip_pressure: float
    peak_pressure: float
    t_start: float
    t_end: float
    cog_before: np.ndarray
    cog_after: np.ndarray
    state: d.State | None = field(default=None, repr=False)
    record: Record | None = field(default=None, repr=False)
    weights: np.ndarray | None = field(default=None, repr=False)


def action_weights(
    pairs: int | Sequence[int] | None = None, weights: np.ndarray | None = None
) -> tuple[tuple[int, ...], np.ndarray]:
    """An action as its 1-based pairs and its weight vector w (12,): the roll ramps the pair
    pressures s w from s = 0 (MPa). 1-based `pairs` driven together give w = 1 on them, 0
    elsewhere; or a non-negative `weights` (12,), or (24,) per cable (kept so), whose largest entry
    is 1 (its pairs: those with w > 0 on a cable). Raises ValueError naming the bad value."""
    if weights is None:
        pairs = tuple(topo.check_pair(q) for q in np.atleast_1d(pairs))
        w = np.zeros(topo.N_PAIRS)
        w[np.asarray(pairs, int) - 1] = 1.0
        return pairs, w
    w = check_pressures(weights, "action weights")  # finite and >= 0 (the check of a pressure)
    if w.shape not in ((topo.N_PAIRS,), (topo.N_CABLES,)) or abs(float(w.max()) - 1.0) > 1e-9:
        raise ValueError(f"action weights {w.tolist()} must be (12,) or (24,) with largest entry 1")
    on = np.flatnonzero(w > 0) if w.size == topo.N_PAIRS else np.unique(topo.CABLE_PAIR[w > 0])
    return tuple(int(q) + 1 for q in on), w


_CALM = 3  # checks in a row that count as settled


def _slew(target: np.ndarray, last: np.ndarray, s: RollSettings) -> np.ndarray:
    """Pressures (12,) MPa moved from `last` toward `target` by at most brake_rate (MPa/s) over
    one interval, up or down: a brake that comes or goes at once kicks the robot."""
    step = s.brake_rate * s.interval
    return np.minimum(np.maximum(target, last - step), last + step)  # np.clip's values, sooner


def settle_controller(s: RollSettings, obs: Obs, brake: Brake | None = None) -> Controller:
    """Zero pressure (or the `brake` of the face it rests on), changing at most at brake_rate from
    the pressures applied before, `obs.pressure`, until settled (see RollSettings; with the
    twisted strings also their pairs at 0 V unwound, `rested`). Returns (face or None, last
    observation)."""
    calm, waited = 0, 0.0
    pres = obs.pressure
    while waited < s.settle_time - 1e-9:
        calm_face = None if obs.speed >= s.settle_speed else obs.face  # never mid-tumble
        to = brake.for_face(calm_face, obs.nodes) if brake else np.zeros(topo.N_PAIRS)
        pres = _slew(widths(to, pres), pres, s)
        obs = yield pres
        waited += s.interval
        calm = calm + 1 if (obs.face is not None and obs.speed < s.settle_speed and rested(s, obs, pres)) else 0
        if calm >= _CALM:
            break
    return obs.face, obs


def roll_controller(
    params: Params,
    s: RollSettings,
    obs: Obs,
    pairs: tuple[int, ...] | None,
    max_pressure: float,
    brake: Brake | None = None,
    expect: float = float("nan"),
    weights: np.ndarray | None = None,
    foresee: bool = False,
    brake_acts: bool | None = None,
) -> Controller:
    """See `roll`; `pairs` or `weights` (12,) or (24,) give the action (`action_weights`: the
    pressures are min(level w, `RollSettings.max_level`) as the level ramps to max_pressure MPa;
    per cable (24,) for (24,) weights or `obs.pressure`, the brake's pairs on both cables).
    With a `brake` (`brake.Brake`), the braking pressures of the start face stay on while the
    pressure rises (fading out over hold_time once it is at the top without a roll;
    given the `expect`ed rolling pressure, MPa, the plan's, as the pressure rises to it: kept
    on, the brake fights the roll, which then tips late and fast or not at all); once the
    robot tips over, those of the face it rolls onto (`Brake.landing`). Where the brake does
    not act on the start face (`Brake.active`, or `brake_acts` if the caller knows), the roll
    is the unbraked one: a brake left on (`obs.pressure`) comes off first at brake_rate and the
    robot settles (at once, it throws the robot; while it comes off, the robot relaxes and may lift
    support nodes), then the ramp starts on the face it rests on, lift measured from there (the
    result's face_before, t_start, cog_before: the roll's start). With `foresee`
    (a roll simulated ahead, `lookahead.foresee`), an unbraked roll ends as soon as the ramp
    gives up with every support node down on its start face: not rolled (the release and settling
    that follow do not move it; braked, the brake coming back on can still roll it; moved onto
    another face as the brake came off, it is judged at its settled end, as it lands). Returns
    (RollResult, last observation)."""
    if obs.face is None:
        raise ct.ContactError("a roll must start from a robot resting on a face")
    start, t0, cog0 = obs.face, obs.t, obs.nodes.mean(axis=0)  # the result's face, time, CoG before
    pairs, w = action_weights(pairs, weights)
    if brake is not None and not (brake.active(start, obs.nodes) if brake_acts is None else brake_acts):
        brake = None  # where the brake does not act (flat or rough ground): the unbraked roll
    while brake is None and obs.face is not None and obs.pressure.any():  # a brake left on
        _, obs = yield from settle_controller(s, obs)
    if obs.face is None:
        return RollResult(pairs, False, start, None, np.nan, 0.0, t0, obs.t, cog0, obs.cog, weights=weights), obs
    face0, t_ramp = obs.face, obs.t
    w = widths(w, obs.pressure)  # per cable if the robot commands its cables already
    support = topo.FACES[face0 - 1].tolist()  # node indices of the support triangle
    base = obs.gap[support].tolist()  # m (lists: cheaper than numpy for three nodes)
    S = float(params.strut_length)
    lanes = [(j, w[j]) for j in np.flatnonzero(w > 0).tolist()]  # (0-based pair or cable, weight)
    top = s.max_level
    level, tip, peak, phase, t_phase = 0.0, float("nan"), 0.0, "ramp", 0.0
    t_hold, rearmed = 0.0, True  # s in the hold (`schedule.hold_step`); a lift may start one
    landed, apex = None, -1
    held = widths(brake.for_face(face0, obs.nodes) if brake else np.zeros(topo.N_PAIRS), w)
    fade, rolling = 1.0, False  # share of the start face's brake still on; it is rolling over
    last = widths(obs.pressure, w)  # braking pressures go on from those applied before (brake_rate)
    release = s.brake_release_time if brake else s.release_time
    while phase != "settle":
        if phase == "ramp":
            level = min(level + s.ramp_rate * s.interval, max_pressure)
        elif phase == "release":
            level = max(0.0, level - peak * s.interval / release)
        elif phase == "land":
            # catch the robot on the new face: let go slowly, hold while it tips back over the
            # edge it came across, let go fast if it tips on over another edge
            up = obs.gap[topo.FACES[landed - 1]] > s.lift_tolerance
            if not (up[apex] and up.sum() == 1 and t_phase < 2 * s.catch_time):
                level = max(0.0, level - peak * s.interval / (release if up.any() else s.catch_time))
        if phase == "top":
            fade = max(0.0, fade - s.interval / s.hold_time)
        elif phase == "ramp":  # handed over to the roll as it nears its pressure
            fade = min(fade, ramp_fade(level, expect))
        pres = held * fade
        if brake and phase in ("release", "land"):  # braced for the face it is rolling onto,
            pres = widths(brake.for_face(landed, obs.nodes), w) if rolling else held  # or back on its own
        if brake:  # braking pressures change at most at brake_rate
            pres = _slew(pres, last, s)
        for j, wj in lanes:  # floats, not arrays, for the one or two pairs driven: the same numbers
            pres[j] = max(pres[j], min(level * wj, top))
        last = pres
        peak = max(peak, level)
        obs = yield pres
        t_phase += s.interval
        if phase in ("release", "land"):
            if landed is None and obs.face is not None and obs.face != face0:
                back = topo.common_edge(face0, obs.face)
                if back is not None:
                    landed, phase, t_phase = obs.face, "land", 0.0
                    apex = int(np.flatnonzero(~np.isin(topo.FACES[landed - 1] + 1, back))[0])
            if level <= 0.0:
                phase = "settle"
            continue
        gap = obs.gap.tolist()
        lifted = [gap[n] - g0 > s.lift_tolerance for n, g0 in zip(support, base)]
        # unbraked, a lift that persists after a hold ran out is not held again; braked, each
        # step is held while a node is up (slopes need it)
        n_up = sum(lifted)  # support nodes up
        up = n_up > 0
        holding, t_hold, rearmed, _ = hold_step(
            phase == "hold", t_hold, rearmed, up, s.interval, s.hold_time, rearm=brake is not None
        )
        over = False
        if n_up == 1:
            pivot = tuple(n + 1 for n, u in zip(support, lifted) if not u)
            over = ct.past_edge(obs.nodes, face0, pivot, S) > s.release_margin
        if over or (obs.face is not None and obs.face != face0 and up):
            if not np.isfinite(tip):
                tip = level
            rolling = True
            if brake and over:  # brace for the landing on the face across the pivot edge
                brake.landing(face0, pivot, obs.nodes)
            phase, t_phase = "release", 0.0
        elif phase == "ramp" and holding:
            tip, phase = level, "hold"
        elif phase == "ramp" and level >= max_pressure:
            phase, t_phase = "top", 0.0
        elif phase == "hold" and not holding:
            if level < max_pressure:  # rocking without rolling: keep raising
                phase, tip = "ramp", float("nan")
            else:
                phase, t_phase = "release", 0.0  # escalated to the limit: give up
        elif phase == "top" and t_phase >= s.hold_time - 1e-9 and fade <= 1e-9:
            phase, t_phase = "release", 0.0
        elif obs.t - t_ramp > max_pressure / s.ramp_rate + 10 * s.hold_time:
            phase, t_phase = "release", 0.0  # a safety net: no attempt runs on forever
        if foresee and brake is None and phase == "release" and not rolling and not up and face0 == start:
            cog = obs.nodes.mean(axis=0)
            res = RollResult(pairs, False, start, face0, np.nan, peak, t0, obs.t, cog0, cog, weights=weights)
            return res, obs
    after, obs = yield from settle_controller(s, obs, brake)
    rolled = after is not None and after != start
    return RollResult(
        pairs,
        rolled,
        start,
        after,
        (tip if np.isfinite(tip) else peak) if rolled else float("nan"),
        peak,
        t0,
        obs.t,
        cog0,
        obs.nodes.mean(axis=0),
        weights=None if weights is None else np.asarray(weights, float),
    ), obs


def settle(
    params: Params, state: d.State, terrain: Terrain, settings: RollSettings | None = None
) -> tuple[d.State, int | None]:
    """Let one robot settle at zero pressure (see RollSettings). Returns the state and its
    1-based contact face (None if it rests on no face)."""
    s = settings or RollSettings()
    if state.batch != 1:
        raise ValueError(f"settle drives one robot; the state holds {state.batch}")
    (face, _), st, _ = lockstep(params, terrain, state, lambda b, o: settle_controller(s, o), s)[0]
    return st, face


def roll(
    params: Params,
    state: d.State,
    terrain: Terrain,
    pairs: int | Sequence[int] | None,
    max_pressure: float,
    settings: RollSettings | None = None,
    weights: np.ndarray | None = None,
) -> RollResult:
    """One roll in the dynamic simulator (paper III.C step 4) of one robot resting on a face:
    drive 1-based `pairs` together from 0 toward `max_pressure` MPa at ramp_rate (or, given
    `weights` (12,) or (24,) (`action_weights`), the pressures level w). When a support
    node lifts the pressure is held (at most hold_time s, then the ramp resumes: escalation,
    held again only by a lift after the support was down again; braked rolls, see
    `roll_controller`, hold at every step while a node is lifted);
    once the unactuated robot would fall over the pivot edge (`contact.past_edge`), or it has
    landed on another face, the pressure is released, slowly once it has landed (held while it
    tips back); then it settles. If nothing lifts by max_pressure (held hold_time s), it is
    released too. Returns the RollResult with the final state and the record.
    Raises SimulationError if the simulation blows up or leaves the terrain, ContactError if
    the robot does not rest on a face."""
    s = settings or RollSettings()
    pairs, _ = action_weights(pairs, weights)
    if not (np.isfinite(max_pressure) and 0 < max_pressure <= s.max_level):
        raise ValueError(f"max_pressure {np.asarray(max_pressure).tolist()!r} {s.unit} must be in (0, {s.max_level}]")
    if state.batch != 1:
        raise ValueError(f"roll drives one robot; the state holds {state.batch}")
    (res, _), st, rec = lockstep(
        params, terrain, state, lambda b, o: roll_controller(params, s, o, pairs, max_pressure, weights=weights), s
    )[0]
    return replace(res, state=st, record=rec)
