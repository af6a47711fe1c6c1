"""Braked candidates simulated ahead (`lookahead.foresee`, issue 30/31's planning cost): their ramp,
their top (the brake fading out) and their release from the top simulated in chunks of check
intervals (`ahead.Braked`) are the rolls simulated one interval at a time, to the last bit."""

import copy

import numpy as np

from tensegrity import locomotion as lo
from tensegrity.locomotion import ahead, lookahead
from tensegrity.locomotion.brake import Brake
from tensegrity.locomotion.control import settle_controller
from tensegrity.locomotion.lockstep import lockstep
from tensegrity.physics import dynamics as d
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.physics.terrain import Terrain

EQUI = topo.face_number(topo.CONTACT_FACES["equilateral"])  # (9,10,12)
DAMPED = Params(strut_damping=1.0)


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
        with monkeypatch.context() as m:
            m.setattr(ahead, "CHUNK", 1)
            one = lookahead.foresee(*args)
        for a, b in zip(one, chunked):
            _same(a, b)
        assert max(sizes) == ahead.CHUNK
        if batch is alone:  # not rolled: ramp (240 intervals), top (50) and release (75) in chunks
            (r,) = chunked
            assert not r.rolled and r.face_after == obs.face
            assert sum(sizes) > 300 and len(sizes) < 60
