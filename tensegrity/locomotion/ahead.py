"""The candidates of `lookahead.foresee` simulated several check intervals per call of the
simulator while their ramps are predictable (issue 30's planning cost; docs/design.md §6).

Most of a candidate's simulated time is its ramp: each check interval the roll controller
raises its level by ramp_rate * interval (`control.roll_controller`) and nothing else happens until
a support node lifts; braked, the brake also fades at the top and comes back on as the level falls
(`braked.Braked`). `lockstep_ahead` drives the batch as `lockstep.lockstep` does (record=False),
but where every robot's last two commands are two steps of its ramp or the same (`Ramp.next`), it
simulates up to CHUNK intervals at once (2, then twice as many after each chunk handed whole) with
the commands the ramps would give (one `dynamics.simulate` call
of one segment per interval), observes them all at once, and hands each controller its
observations one interval at a time; at the first command that differs from the one simulated
(a hold, the top, a release, a finished roll), the batch is simulated again from the chunk's start
up to that interval. Each controller thus sees the observations, and each robot the commands, of
the one-interval-at-a-time simulation: the same rolls to the last bit (tests/locomotion/
test_decided_cuts.py), at a fraction of the calls. The observations of a chunk carry no robot
state (Obs.state None): the roll controller reads none in its ramp or a hold; with the twisted
strings no chunk holds the top (`decided` reads the motors there) or zero (`lockstep.rested`), and
the pairs commanded 0 V are unwound (within `lockstep.UNWIND_TOLERANCE`, their voltage then the
command: `lockstep.applied`) at a chunk's start and end: a motor at 0 V is held by its gear
friction, so they stay so in between.

Twins, robots of the batch in the same state given the same commands, are simulated once, as one row
(`_regroup`), and part when their commands do: from a robot held by its brake every unbraked candidate
first lets the brake come off the same way (on a steep slope most tumble then, before their ramps
part), and a braked action and its twin with the brake kept on share their ramp until it nears the
plan's pressure. The simulator advances each robot on its own, so a twin gets the bits it gets alone
(tests/locomotion/test_braked_cuts.py).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from ..physics import contact as ct
from ..physics import dynamics as d
from ..physics import topology as topo
from ..physics.params import Params
from ..physics.terrain import Terrain
from .lockstep import Controller, Obs, _threads, advance, applied, first_commands, observe, own, put, widths
from .settings import RollSettings

__all__ = ["CHUNK", "Ramp", "lockstep_ahead", "row_bytes"]

CHUNK = 32  # check intervals simulated at once, at most (0.64 s at the default 20 ms)
WIDEST = 8  # robots, at most, in a batch simulated in chunks: in a wider one the simulator's own
# work, which a chunk cut short repeats, outweighs the calls saved (40 candidates on flat ground:
# 1.5 times the CPU of one interval at a time; 2 and 8: 0.7 and 0.9 times)


class Ramp:
    """The unbraked ramp of an action of weights w (12,) up to max_pressure: the command at
    level L is min(L w, s.max_level) on the action's pairs, 0 elsewhere (`roll_controller`);
    with s.motors (the twisted strings) `volts`."""

    def __init__(self, w: np.ndarray, s: RollSettings, max_pressure: float):
        self.w, self.top, self.max = np.asarray(w, float), s.max_level, max_pressure
        self.inc = s.ramp_rate * s.interval  # the controller's own product
        self.j = int(np.argmax(self.w))
        self.volts = s.motors is not None
        self.held = self.command(max_pressure)

    def command(self, level: float) -> np.ndarray:
        """The command (12,) at `level` (at most max_pressure: L w is then at most s.max_level)."""
        return level * self.w

    def next(self, prev: np.ndarray, cmd: np.ndarray, n: int) -> np.ndarray | None:
        """The next (up to n) commands (n', 12): if `prev` and `cmd` are two steps of the ramp,
        its next steps below its top; if they are the same, that command (a hold, the top, a
        settle), but with the twisted strings not at the top nor at zero, where the controllers
        read the motors' state (`decided`, `lockstep.rested`); else None."""
        if n < 1:
            return None
        if np.array_equal(prev, cmd):
            if self.volts and (not cmd.any() or np.array_equal(cmd, self.held)):
                return None
            return np.broadcast_to(cmd, (n, cmd.size))
        if self.w[self.j] != 1.0 or self.max > self.top or prev.size != self.w.size or cmd.size != self.w.size:
            return None  # (a cable action's brake coming off first commands its pairs)
        a, b = float(prev[self.j]), float(cmd[self.j])
        if b != min(a + self.inc, self.max) or not (
            np.array_equal(prev, self.command(a)) and np.array_equal(cmd, self.command(b))
        ):
            return None
        levels = []
        for _ in range(n):
            b = min(b + self.inc, self.max)
            if b >= self.max:
                break
            levels.append(b)
        return np.asarray(levels)[:, None] * self.w if levels else None


def _observe_all(params: Params, terrain: Terrain, s: RollSettings, X, Q, ts, before: list[Obs], cmds, wide) -> list:
    """Observations [k][i] of robots i after interval k of a chunk from the recorded strut
    centres X (B, K, 6, 3) and quaternions Q, times ts (K,) s, the observations `before` it and
    the commands cmds (B, K, 12 or 24; `wide` (B,): per robot, `lockstep.own`):
    `lockstep.observe`'s numbers (without states), all at once."""
    B, K = X.shape[:2]
    P = d.nodes(X.reshape(B * K, 6, 3), Q.reshape(B * K, 6, 4), params.strut_length).reshape(B, K, 12, 3)
    gaps = ct.clearance(P, terrain, float(params.strut_radius))
    faces = ct.resting_face(gaps, s.contact_tolerance).tolist()
    cog = P.mean(axis=2)
    prev = np.concatenate([np.stack([o.cog for o in before])[:, None], cog[:, :-1]], axis=1)
    dt = np.asarray(ts) - np.concatenate([[before[0].t], ts[:-1]])
    step = cog - prev
    speed = (np.sqrt(np.vecdot(step, step)) / dt[None]).tolist()
    return [
        [
            Obs(ts[k], P[i, k], gaps[i, k], faces[i][k] or None, speed[i][k], own(cmds[i, k], wide[i]), None, cog[i, k])
            for i in range(B)
        ]
        for k in range(K)
    ]


def _simulate(params, terrain, s, batch, cmds, every):
    """The batch simulated over the commands cmds (B, K, 12), one check interval each."""
    K = cmds.shape[1]
    sched = type(s.schedule(cmds[:, 0]))(np.full(K, s.interval), cmds)
    return d.simulate(params, batch, sched, terrain, s.dt, every, s.motors)


def _chunk(params, terrain, s, batch, every, groups, gens, last, pres, prev, ramps, span, wide):
    """Up to `span` intervals of the batch at once (module docstring), one row per group of twins
    (`lockstep_ahead`). Returns (the batch after the last interval its controllers were handed, the
    robots that finished: {b: (result, row)}, whether all `span` were handed), or None where a
    robot's ramp is not predictable or a group's twins predict different commands at once (then
    one interval as `lockstep`)."""
    if len(groups) > WIDEST:
        return None
    ahead = []
    for g in groups:
        got = [
            None if ramps[b] is None else ramps[b].next(own(prev[b], wide[b]), own(pres[b], wide[b]), span - 1)
            for b in g
        ]
        if any(a is None for a in got):
            return None
        a = widths(got[0], pres)  # in the batch's width; the twins' common prefix
        for other in got[1:]:
            other = widths(other, pres)
            m = min(len(a), len(other))
            same = np.all(a[:m] == other[:m], axis=1)
            a = a[: m if same.all() else int(np.argmin(same))]
        if not len(a):
            return None
        ahead.append(a)
    n = min(len(a) for a in ahead)
    cmds = np.stack([np.concatenate([pres[g[0]][None], a[:n]]) for g, a in zip(groups, ahead)])  # (B, K, 12)
    if s.motors is not None and not np.array_equal(applied(s, cmds[:, 0], batch), cmds[:, 0]):
        return None  # a pair unwinding (`lockstep.applied`): its voltage follows the state
    try:
        end, traj = _simulate(params, terrain, s, batch, cmds, every)
    except d.SimulationError:
        return None
    if s.motors is not None and not np.array_equal(applied(s, cmds[:, -1], end), cmds[:, -1]):
        return None
    K = n + 1
    ts, t = [], batch.t
    for _ in range(K):  # `dynamics.simulate`'s clock, one interval at a time
        t += every * s.dt
        ts.append(t)
    lead = [g[0] for g in groups]
    obs = _observe_all(params, terrain, s, traj.x, traj.q, ts, [last[b] for b in lead], cmds, [wide[b] for b in lead])
    done: dict[int, tuple[Any, int]] = {}
    for k in range(K):
        stop = False
        for i, g in enumerate(groups):
            ob = obs[k][i]
            for b in g:
                if b in done:
                    continue
                last[b] = ob
                prev[b] = cmds[i, k]
                try:
                    _put(pres, wide, b, gens[b].send(ob))
                except StopIteration as e:
                    done[b] = (e.value, i)
                    stop = True
                    continue
                stop |= k < K - 1 and not np.array_equal(pres[b], cmds[i, k + 1])
        if stop or k == K - 1:
            break
    if k < K - 1:  # the state after interval k: simulated again from the chunk's start
        end, _ = _simulate(params, terrain, s, batch, cmds[:, : k + 1], every)
    return end, done, k == K - 1 and not done


def _put(pres: np.ndarray, wide: list[bool], b: int, cmd: np.ndarray) -> None:
    """`lockstep.put` in place: the batch's width is fixed at its start (`lockstep_ahead`)."""
    if put(pres, wide, b, cmd) is not pres:
        raise RuntimeError("a per-cable command in a batch simulated per pair")


def lockstep_ahead(
    params: Params,
    terrain: Terrain,
    state: d.State,
    make: Callable[[int, Obs], Controller],
    s: RollSettings,
    ramps: list[Ramp | None],
) -> list[tuple[Any, d.State]]:
    """`lockstep.lockstep(params, terrain, state, make, s, record=False)`, with chunks where the
    ramps are predictable: ramps[b] is robot b's ramp, `Ramp` or `braked.Braked` (None: never predicted;
    the list may be filled by `make`). The commands are per cable for all robots if one robot
    starts per cable or has a ramp of (24,) weights (`lockstep.put`; a pair robot's levels on
    both cables). Twins, robots in the same state given the same commands (candidates whose
    controllers agree so far: the unbraked ones while the brake comes off, a braked action and
    its twin with the brake kept while the ramp is below the planned pressure), are simulated once,
    as one row of the batch, and part when their commands do: the simulator advances each robot
    on its own, so each gets the same bits. Returns per robot (result, final State)."""
    state.check()
    params = s.rolling(params)
    every = int(round(s.interval / s.dt))
    B = state.batch
    states = s.motors is not None
    first = observe(params, terrain, state, s, states=states)
    last = list(first)
    gens = [make(b, first[b]) for b in range(B)]
    cables = any(o.pressure.size == topo.N_CABLES for o in first) or any(
        r is not None and r.w.size == topo.N_CABLES for r in ramps
    )
    wide = [False] * B
    pres, live, out, batch = first_commands(gens, state, wide, topo.N_CABLES if cables else topo.N_PAIRS)
    prev = np.full(pres.shape, np.nan)
    rows = [row_bytes(batch, i) for i in range(batch.batch)]
    batch, groups = _regroup(batch, [[b] for b in live], {}, pres, wide, rows)
    span = min(2, CHUNK)  # a chunk's length: doubled after each chunk handed whole, up to CHUNK; 2 after one cut
    with _threads(len(groups)):
        while groups:
            got = _chunk(params, terrain, s, batch, every, groups, gens, last, pres, prev, ramps, span, wide)
            if got is not None:
                batch, done, whole = got
                span = min(2 * span, CHUNK) if whole else 2
            else:
                batch, done = _one(params, terrain, s, batch, every, groups, gens, last, pres, prev, states, wide)
            for b, (res, i) in done.items():
                out[b] = (res, batch.take([i]))
            batch, groups = _regroup(batch, groups, done, pres, wide)
    return out


def row_bytes(batch: d.State, i: int) -> bytes:
    """Robot i's state in the batch, as bytes: equal for robots in the same state."""
    fields = (batch.x, batch.v, batch.q, batch.w, batch.anchor, batch.stuck, batch.motor_angle, batch.motor_speed)
    return b"".join(np.ascontiguousarray(a[i]).tobytes() for a in fields if a is not None)


def _regroup(batch: d.State, groups: list[list[int]], done: dict, pres: np.ndarray, wide: list[bool], rows=None):
    """The batch and its groups of twins (one row each) after a check: the robots `done` leave, a
    group's robots part where their commands `pres` differ (in their order); robots of different
    rows join where their `rows` (`row_bytes`, given only at the start) and commands are the same."""
    key, index, new = {}, [], []
    for i, g in enumerate(groups):
        for b in g:
            if b in done:
                continue
            k = (rows[i] if rows is not None else i, pres[b].tobytes(), wide[b])
            if k not in key:
                key[k] = len(new)
                index.append(i)
                new.append([])
            new[key[k]].append(b)
    if index != list(range(len(groups))):
        batch = batch.take(index)
    return batch, new


def _one(params, terrain, s, batch, every, groups, gens, last, pres, prev, states, wide):
    """One check interval of the batch, one row per group of twins, as `lockstep.lockstep` advances it
    (record=False)."""
    lead = [g[0] for g in groups]
    batch, failed, _ = advance(params, terrain, s, batch, pres[lead], lead, every)
    ob = observe(params, terrain, batch, s, [last[b] for b in lead], [own(pres[b], wide[b]) for b in lead], states)
    done = {}
    for i, g in enumerate(groups):
        for b in g:
            prev[b] = pres[b]
            try:
                if g[0] in failed:
                    gens[b].throw(failed[g[0]])
                    raise RuntimeError("a controller ignored a SimulationError")
                last[b] = ob[i]
                _put(pres, wide, b, gens[b].send(ob[i]))
            except StopIteration as stop:
                done[b] = (stop.value, i)
    return batch, done
