"""The look past a landing (`drive.onward`, docs/design.md §6): a roll simulated ahead leaves the
state the run then reaches, so the next step can be simulated from it before the roll is made;
a landing from which the next step finds an acceptable roll is no dead end, and one that rests on
no face is."""

from dataclasses import replace

import numpy as np

from tensegrity import locomotion as lo
from tensegrity.locomotion import drive, lookahead
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
    assert drive.onward(ws, DAMPED, slope, s, target, brk, memory, [EQUI], r)
    fallen = replace(r, state=replace(r.state, x=r.state.x + [0.0, 0.0, 1.0]))  # 1 m up: on no face
    assert not drive.onward(ws, DAMPED, slope, s, target, brk, memory, [EQUI], fallen)
