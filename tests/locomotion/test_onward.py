"""The look past a landing (`drive.onward`, docs/design.md §6): a roll simulated ahead leaves the
state the run then reaches, so the next step can be simulated from it before the roll is made;
a landing from which the next step finds an acceptable roll is no dead end, and one that rests on
no face is; the next step starts from the rolls the look simulated (`foreseen.Foreseen`)."""

from dataclasses import replace

import numpy as np

from tensegrity import locomotion as lo
from tensegrity.locomotion import drive, foreseen, lookahead
from tensegrity.locomotion.brake import Brake
from tensegrity.locomotion.control import settle_controller
from tensegrity.locomotion.lockstep import lockstep
from tensegrity.physics import dynamics as d
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.physics.terrain import Terrain

DAMPED = Params(strut_damping=1.0)
EQUI = topo.face_number(topo.CONTACT_FACES["equilateral"])  # (9,10,12)


def test_a_foreseen_roll_leaves_the_state_the_run_reaches_and_its_landing_is_judged_from_there(ws):
    """On a 15 deg slope: the first roll of a run, foreseen from the same settled state with the
    same brake, ends in the state the run's record ends in (every node to 1e-12 m, the same time),
    with its last levels; from there the next step has an acceptable roll (no dead end), and the
    same roll's end with the robot on no face is judged a dead end."""
    s = lo.RollSettings(lookahead=4, max_attempts=1, max_rolls=1)
    slope = Terrain.slope(15.0)
    goal = np.array([0.0, -2.0])
    run = lo.roll_to(ws, goal, DAMPED, slope, face=EQUI, settings=s)
    (done,) = run.steps[0].attempts
    assert done.rolled

    brk = Brake(ws, s.brake_margin)

    def settle(b, obs):
        _, obs = yield from settle_controller(s, obs, brk)
        return obs

    ((obs, _, _),) = lockstep(DAMPED, slope, d.stand_on(DAMPED, EQUI, slope), settle, s)
    expect = {c.pairs: c.pressure for c in run.steps[0].plan.candidates}
    twins = [(done.pairs, True), (done.pairs, False)]
    foreseen = lookahead.foresee(DAMPED, slope, s, obs, twins, ws.max_pressure, brk, expect)
    (r,) = [f for f in foreseen if (f.face_after, f.t_end) == (done.face_after, done.t_end)]
    nodes = d.nodes(r.state.x, r.state.q, DAMPED.strut_length)[0]
    assert r.state.t == run.record.t[-1]
    assert np.allclose(nodes, run.record.nodes[-1], rtol=0, atol=1e-12)
    assert r.record.pressure.shape == (1, topo.N_PAIRS) and np.all(r.record.pressure >= 0)

    memory = lookahead.Memory(0.1, np.r_[goal, 0.0])
    memory.add(EQUI, obs.cog)
    target = dict(goal=np.r_[goal, float(slope.height(*goal))])
    assert drive.onward(ws, DAMPED, slope, s, target, brk, memory, [EQUI], None, r)
    fallen = replace(r, state=replace(r.state, x=r.state.x + [0.0, 0.0, 1.0]))  # 1 m up: on no face
    assert not drive.onward(ws, DAMPED, slope, s, target, brk, memory, [EQUI], None, fallen)


def test_the_next_step_starts_from_the_rolls_the_look_past_its_landing_simulated(ws, monkeypatch):
    """Three rolls toward a goal on random terrain (std 0.03 m): with the rolls the look past each
    landing simulated kept for the next step, the run makes the same rolls and simulates ahead the
    same candidates, to the last bit, as one that simulates every step afresh, and simulates fewer."""
    s = lo.RollSettings(max_rolls=3)
    ground = Terrain.random(5, amplitude=0.03)
    goal = np.array([1.5, 1.0])
    counts = []
    simulate = lookahead.foresee

    def counted(*a):
        counts[-1] += len(a[4])
        return simulate(*a)

    class Afresh(foreseen.Foreseen):
        def __call__(self, *a):
            return counted(*a)

    def run(cls):
        counts.append(0)
        with monkeypatch.context() as m:
            m.setattr(lookahead, "foresee", counted)
            m.setattr(drive, "Foreseen", cls)
            return lo.roll_to(ws, goal, DAMPED, ground, face=EQUI, settings=s)

    kept, afresh = run(foreseen.Foreseen), run(Afresh)
    assert len(kept.steps) == len(afresh.steps) == 3 and counts[0] < counts[1]
    for a, b in zip(kept.steps, afresh.steps):
        for x, y in zip(a.attempts + a.simulated, b.attempts + b.simulated):
            assert (x.pairs, x.rolled, x.face_after, x.t_end) == (y.pairs, y.rolled, y.face_after, y.t_end)
            assert np.array_equal(x.cog_after, y.cog_after)
        assert len(a.simulated) == len(b.simulated)
    assert np.array_equal(kept.record.nodes, afresh.record.nodes)


def test_rolls_kept_are_reused_only_from_the_same_state_levels_and_brake(ws, monkeypatch):
    """On a 15 deg slope, from the robot settled with its brake on: two candidates asked again from
    the same start are not simulated again (the same results); asked with the brake braced for
    another face, or from other levels, they are, and equal `lookahead.foresee`'s afresh."""
    s, slope = lo.RollSettings(), Terrain.slope(15.0)
    brk = Brake(ws, s.brake_margin)

    def settle(b, obs):
        _, obs = yield from settle_controller(s, obs, brk)
        return obs

    ((obs, _, _),) = lockstep(DAMPED, slope, d.stand_on(DAMPED, EQUI, slope), settle, s)
    assert brk.active(obs.face, obs.nodes)
    todo = [((1,), True), ((2,), False)]
    n = [0]
    simulate = lookahead.foresee

    def counted(*a):
        n[0] += len(a[4])
        return simulate(*a)

    monkeypatch.setattr(lookahead, "foresee", counted)
    known = foreseen.Foreseen()
    first = known(DAMPED, slope, s, obs, todo, ws.max_pressure, brk, {})
    again = known(DAMPED, slope, s, obs, todo[::-1], ws.max_pressure, brk, {})
    assert n[0] == 2 and again == first[::-1]
    other = Brake(ws, s.brake_margin)
    other.for_face(topo.neighbour(EQUI, topo.edge_nodes(EQUI, 0)), obs.nodes)  # braced for another face
    lower = replace(obs, pressure=obs.pressure * 0.5)
    for o, b in ((obs, other), (lower, brk)):
        got = known(DAMPED, slope, s, o, todo, ws.max_pressure, b, {})
        fresh = simulate(DAMPED, slope, s, o, todo, ws.max_pressure, b, {})
        assert [(r.rolled, r.face_after, r.t_end) for r in got] == [(r.rolled, r.face_after, r.t_end) for r in fresh]
        assert all(np.array_equal(x.cog_after, y.cog_after) for x, y in zip(got, fresh))
        assert got[0].t_end != first[0].t_end  # another roll: not the one kept
    assert n[0] == 6
