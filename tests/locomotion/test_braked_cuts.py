"""Braked candidates simulated ahead (`lookahead.foresee`, issue 30/31's planning cost): their ramp,
their top (the brake fading out) and their release from the top simulated in chunks of check
intervals (`braked.Braked`) are the rolls simulated one interval at a time, to the last bit, and
the whole rolls (`roll_controller` to its end): braked candidates are not cut before they settle
(`decided.until_decided`: at rest at the top with the brake faded out, one still rolled)."""

import copy

import numpy as np

from tensegrity import locomotion as lo
from tensegrity.locomotion import ahead, lookahead
from tensegrity.locomotion.brake import Brake
from tensegrity.locomotion.control import roll_controller, settle_controller
from tensegrity.locomotion.lockstep import Obs, lockstep
from tensegrity.physics import dynamics as d
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.physics.terrain import Terrain
from tensegrity.physics.twisted import TwistedString

EQUI = topo.face_number(topo.CONTACT_FACES["equilateral"])  # (9,10,12)
DAMPED = Params(strut_damping=1.0)
VOLTS = lo.RollSettings(motors=TwistedString(), hold_time=20.0, settle_time=15.0, ramp_rate=0.25)


def _settled(s, terrain, brk):
    def ctl(b, obs):
        _, obs = yield from settle_controller(s, obs, copy.deepcopy(brk))
        return obs

    ((obs, _, _),) = lockstep(DAMPED, terrain, d.stand_on(DAMPED, EQUI, terrain), ctl, s)
    return obs


def _fields(r):
    return (r.pairs, r.rolled, r.face_before, r.face_after, r.tip_pressure, r.peak_pressure, r.t_start, r.t_end)


def _same(a, b):
    assert all(x == y or (x != x and y != y) for x, y in zip(_fields(a), _fields(b)))  # NaN: NaN
    assert np.array_equal(a.cog_before, b.cog_before) and np.array_equal(a.cog_after, b.cog_after)


def _one_at_a_time(monkeypatch, chunked, args):
    with monkeypatch.context() as m:
        m.setattr(ahead, "CHUNK", 1)
        one = lookahead.foresee(*args)
    for a, b in zip(one, chunked):
        _same(a, b)


def _whole(s, terrain, obs, todo, top, brk, expect):
    """Each braked candidate of `todo` rolled to its end (the run's roll), from `obs`."""

    def make(b, ob):
        ob = Obs(obs.t, ob.nodes, ob.gap, ob.face, obs.speed, obs.pressure.copy(), cog=ob.cog)
        pairs = todo[b][0]
        return roll_controller(DAMPED, s, ob, pairs, top, copy.deepcopy(brk), expect.get(pairs, np.nan))

    state = d.State.concat([obs.state] * len(todo))
    return [r for (r, _), _, _ in lockstep(DAMPED, terrain, state, make, s, record=False)]


def _chunked(monkeypatch, args):
    """`lookahead.foresee(*args)` and the check intervals each of its chunks simulated."""
    sizes: list[int] = []
    sim = ahead._simulate

    def counted(params, terrain, s, batch, cmds, every):
        sizes.append(cmds.shape[1])
        return sim(params, terrain, s, batch, cmds, every)

    with monkeypatch.context() as m:
        m.setattr(ahead, "_simulate", counted)
        return lookahead.foresee(*args), sizes


def test_braked_candidates_in_chunks_are_the_rolls_one_interval_at_a_time(ws, monkeypatch):
    """On a 20 deg slope, where the brake acts: braked candidates of the first step, alone (one
    that stays on its face: its ramp, the brake fading out at the top and coming back on as the
    pressure falls, mostly in chunks) and four together, one with the plan's pressure (the brake
    fades as the ramp nears it) and three without."""
    s, slope = lo.RollSettings(), Terrain.slope(20.0)
    brk = Brake(ws, s.brake_margin)
    obs = _settled(s, slope, brk)
    goal = np.array([0.0, 2.0])
    pl = lo.plan(ws, obs.face, obs.nodes, goal=goal)
    braked = [a for a in lookahead.acts(ws, obs.face, obs.nodes, pl, dict(goal=goal), brk) if a[1]]
    expect = {c.pairs: c.pressure for c in pl.candidates}
    alone = [a for a in braked if a[0] == (6,)]
    todo = [braked[0], *braked[-3:]]
    assert todo[0][0] in expect and all(a[0] not in expect for a in todo[1:])
    for batch in (alone, todo):
        args = (DAMPED, slope, s, obs, batch, ws.max_pressure, brk, expect)
        chunked, sizes = _chunked(monkeypatch, args)
        _one_at_a_time(monkeypatch, chunked, args)
        assert max(sizes) == ahead.CHUNK
        if batch is alone:  # not rolled: ramp (240 intervals), top (50) and release (75) in chunks
            (r,) = chunked
            assert not r.rolled and r.face_after == obs.face
            assert sum(sizes) > 300 and len(sizes) < 60


def test_braked_twisted_strings_in_chunks_are_the_whole_rolls(ws, monkeypatch):
    """The prototype's motors ramped at 0.25 V/s (config/README.md's volts table ramps at 0.1) on a
    15 deg slope, braked: #10 up to 9 V does not roll the robot off (9,10,12); its ramp and top in
    chunks (the settling, as the strands unwind after the release, one interval at a time), the
    roll one interval at a time and the whole roll, to the last bit."""
    s, slope = VOLTS, Terrain.slope(15.0)
    brk = Brake(ws, s.brake_margin)
    obs = _settled(s, slope, brk)
    todo = [((10,), True)]
    expect = {(10,): 9.5}  # a plan's level above the top: the brake fades as the ramp nears it
    args = (DAMPED, slope, s, obs, todo, 9.0, brk, expect)
    cut, sizes = _chunked(monkeypatch, args)
    assert sum(sizes) > 2500  # most of the 36 s ramp and the 20 s top
    _one_at_a_time(monkeypatch, cut, args)
    full = _whole(s, slope, obs, todo, 9.0, brk, expect)
    _same(cut[0], full[0])
    assert not cut[0].rolled and cut[0].face_after == obs.face


def test_twins_are_simulated_once_and_get_the_bits_they_get_alone(ws, monkeypatch):
    """On a 20 deg slope, from the robot held by its brake: six unbraked candidates (the brake comes
    off the same way for all six; here all six tumble as it does, before their ramps) and a braked
    action with its twin with the brake kept on (the same commands until the ramp nears the plan's
    pressure; then one tumbles, the other rolls), simulated together, each get the RollResult, final
    state and last levels they get alone (`ahead.lockstep_ahead`'s twins, one row of the batch while
    their commands agree), in fewer robot-intervals of the simulator than alone."""
    s, slope = lo.RollSettings(), Terrain.slope(20.0)
    brk = Brake(ws, s.brake_margin)
    obs = _settled(s, slope, brk)
    goal = np.array([0.0, 2.0])
    pl = lo.plan(ws, obs.face, obs.nodes, goal=goal)
    expect = {c.pairs: c.pressure for c in pl.candidates}
    unbraked = [a for a in lookahead.acts(ws, obs.face, obs.nodes, pl, dict(goal=goal), brk) if not a[1]][:6]
    (kept, *_) = lookahead.kept(pl)
    todo = [*unbraked, (kept[0], True), kept]
    args = (DAMPED, slope, s, obs, todo, ws.max_pressure, brk, expect)
    rows = []
    simulate = d.simulate

    def counted(params, batch, sched, *a, **k):
        rows.append(batch.batch * len(sched.durations))  # robot-intervals
        return simulate(params, batch, sched, *a, **k)

    def run(batch):
        with monkeypatch.context() as m:
            m.setattr(d, "simulate", counted)
            m.setattr(ahead, "CHUNK", 1)  # one interval a call: no chunk simulated again
            return lookahead.foresee(*args[:4], batch, *args[5:])

    together = run(todo)
    shared = sum(rows)
    alone = [run([a])[0] for a in todo]
    assert shared < 0.6 * (sum(rows) - shared)  # six twins of 70 intervals as one
    assert [r.face_after is None for r in together] == [True] * 7 + [False]  # the kept twin rolls
    for a, b in zip(together, alone):
        _same(a, b)
        for x, y in zip((a.state.x, a.state.v, a.state.q, a.state.w), (b.state.x, b.state.v, b.state.q, b.state.w)):
            assert np.array_equal(x, y)
        assert np.array_equal(a.record.pressure, b.record.pressure)
    _one_at_a_time(monkeypatch, lookahead.foresee(*args), args)  # twins in chunks
