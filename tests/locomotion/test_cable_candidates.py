"""Per-cable candidates of the planner (issue 30: "as a configured option, of the 24 cables one by
one, as the prototype can"; `locomotion.cable_actions`): a cable action with both cables of each
pair equal is the pair action, in the planner's list and in the simulator to the bit; a pair
candidate simulated in one batch with cable candidates (the batch then per cable) is the same roll
as alone; and on the pose where the statics say the cables climb and the pairs do not (the
isosceles face (10,11,12) on 23 deg, uphill at heading 270: docs/planner_evaluation.md, "The slope
limit with per-cable actions"), the braked cable candidate rolls the robot uphill over 11-12, as
foreseen and in the world. The workspace `ws` (conftest) comes from the independent static
solver."""

import copy
from dataclasses import replace

import numpy as np
import pytest

from tensegrity import locomotion as lo
from tensegrity.locomotion import actuation, control, lookahead
from tensegrity.locomotion.brake import Brake
from tensegrity.locomotion.control import roll_controller, settle_controller
from tensegrity.locomotion.lockstep import lockstep, observe
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.physics.terrain import Terrain
from tensegrity.workspace.slopes import place

S = lo.RollSettings()
DAMPED = S.rolling(Params())
SETTINGS = actuation.ActuationSettings()


def test_a_cable_action_with_equal_cables_is_the_pair_action():
    flat = Terrain.flat()
    face = topo.face_number((9, 10, 12))
    st, _ = control.settle(DAMPED, place(DAMPED, face, flat, (0.0, 0.0), 0.0), flat, S)
    w = np.zeros(12)
    w[[9, 10]] = [1.0, 0.5]
    assert lookahead._act(topo.cable_levels(w)) == lookahead._act(w)  # the same candidate, once
    assert lookahead._act(topo.cable_levels(np.eye(12)[9])) == ((10,),)
    one = topo.cable_levels(w)
    one[topo.PAIR_CABLES[10, 1]] = 0.0  # one cable only of pair #11: a cable action
    pairs, weights = lookahead._act(one)
    assert pairs == (10, 11) and len(weights) == topo.N_CABLES
    a = control.roll(DAMPED, st, flat, None, 3.0, S, weights=w)
    b = control.roll(DAMPED, st, flat, None, 3.0, S, weights=topo.cable_levels(w))
    assert a.pairs == b.pairs == (10, 11) and b.record.pressure.shape[1] == topo.N_CABLES
    np.testing.assert_array_equal(topo.cable_levels(a.record.pressure), b.record.pressure)
    for name in ("t", "nodes", "face"):
        np.testing.assert_array_equal(getattr(a.record, name), getattr(b.record, name), err_msg=name)


@pytest.fixture(scope="module")
def climb(ws):
    """The isosceles face on 23 deg with uphill at heading 270, settled with the run's brake:
    (settings, brake, observation, state, cable candidates, pair candidates)."""
    slope = Terrain.slope(23.0)  # uphill along +x
    face = topo.face_number((10, 11, 12))
    brk = Brake(ws, S.brake_margin)

    def settle(b, obs):
        return (yield from settle_controller(S, obs, brk))

    (((f, obs), st, _),) = lockstep(
        DAMPED, slope, place(DAMPED, face, slope, (0.0, 0.0), 270.0), settle, S, record=False
    )
    assert f == face
    (ob,) = observe(DAMPED, slope, st, S, pressure=obs.pressure[None])
    ob = replace(ob, face=f)
    up = (1.0, 0.0)
    cables = actuation.candidates(DAMPED, slope, st, face, up, SETTINGS, ws.max_pressure, levers=topo.N_CABLES)
    pairs = actuation.candidates(DAMPED, slope, st, face, up, SETTINGS, ws.max_pressure)
    return slope, brk, ob, st, cables, pairs


def test_the_cable_candidate_climbs_where_the_pair_candidates_do_not(ws, climb):
    """The statics' cable action over 11-12 (uphill, `along` 1) drives some pair on one cable
    only; braked, it lands on the face across 11-12 with the CoG 0.1 m or more uphill and higher,
    foreseen and in the world (the run's controller, `lockstep`) at the same place within 1 cm.
    The statics' pair actions over 11-12 do not roll it over there in the simulator."""
    slope, brk, ob, st, cables, pairs = climb
    c = cables[0]
    assert c.edge == (11, 12) and c.along > 0.99 and c.weights.shape == (topo.N_CABLES,)
    w = c.weights[topo.PAIR_CABLES]  # (12, 2)
    assert np.any((w > 0).sum(axis=1) == 1)  # one cable only of some pair: not a pair action
    act = lookahead._act(c.weights)
    up = [lookahead._act(p.weights) for p in pairs if p.edge == (11, 12)]
    assert up  # the statics find pair actions over 11-12 too ...
    todo = [(act[0], True, act[1]), *[(a[0], True, *a[1:]) for a in up], (act[0], False, act[1])]
    ahead, *others, free = lookahead.foresee(DAMPED, slope, S, ob, todo, ws.max_pressure, brk, {})
    assert ob.pressure.any() and free.weights.shape == (topo.N_CABLES,)  # unbraked: the brake (pairs)
    # comes off first, then the ramp per cable
    assert ahead.rolled and lookahead.lands(ahead) and ahead.face_after == c.next_face
    rise = np.subtract(ahead.cog_after, ahead.cog_before)
    assert rise[0] > 0.1 and rise[2] > 0.0, rise
    assert not any(r.face_after == c.next_face for r in others)  # ... which do not roll it over there

    def world(b, o):  # the run's brake as it is (a copy), the pressures applied before
        o = replace(o, pressure=ob.pressure.copy())
        return roll_controller(
            DAMPED, S, o, act[0], ws.max_pressure, copy.deepcopy(brk, {id(ws): ws}), weights=c.weights
        )

    ((played, _), _, rec) = lockstep(DAMPED, slope, st, world, S)[0]
    assert played.face_after == c.next_face and rec.pressure.shape[1] == topo.N_CABLES
    assert np.linalg.norm(np.subtract(played.cog_after, ahead.cog_after)) < 0.01


def test_a_pair_candidate_in_a_batch_with_cable_candidates_is_the_same_roll(ws, climb):
    """The batch is simulated per cable once one candidate is (`lockstep.put`); the pair
    candidates' commands are their pair levels on both cables: the same rolls to the bit."""
    slope, brk, ob, st, cables, pairs = climb
    todo = [((q,), b) for q in (3, 8) for b in (True, False)]
    alone = lookahead.foresee(DAMPED, slope, S, ob, todo, ws.max_pressure, brk, {})
    act = lookahead._act(cables[0].weights)
    mixed = lookahead.foresee(DAMPED, slope, S, ob, [*todo, (act[0], True, act[1])], ws.max_pressure, brk, {})
    for a, b in zip(alone, mixed):
        assert (a.face_after, a.rolled, a.t_end) == (b.face_after, b.rolled, b.t_end)
        np.testing.assert_array_equal(a.cog_after, b.cog_after)
        np.testing.assert_array_equal(a.peak_pressure, b.peak_pressure)
