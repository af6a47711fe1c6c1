"""The brake kept on as a candidate of its own (`lookahead.kept`): where only the brake holds the
robot on a slope, the plan's pressure is the fall the brake prevents (the unbraked CoG projection
outside at 0 MPa), a braked roll that hands its brake over at that pressure lets it go at once and
tumbles, as every unbraked roll does; with the brake kept on while the action ramps, some land
(docs/planner_evaluation.md, "The brake kept on where the plan's pressure is the fall it
prevents"). The workspace `ws` (conftest) comes from the independent static solver."""

from dataclasses import replace

import numpy as np

from tensegrity import locomotion as lo
from tensegrity.locomotion import lookahead
from tensegrity.locomotion.brake import Brake
from tensegrity.locomotion.control import settle_controller
from tensegrity.locomotion.lockstep import lockstep, observe
from tensegrity.physics import dynamics as d
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.physics.terrain import Terrain

DAMPED = Params(strut_damping=1.0)  # the rolling runs' default
SLOPE = Terrain.slope(24.0)
UPHILL = (1.0, 0.0)


def _held(ws, s):
    """The robot set down on face 8, (9,10,12), at yaw 45 deg on the 24 deg slope and settled with
    its brake: (observation with its state and the brake's pressures, the run's brake)."""
    brk = Brake(ws, s.brake_margin)

    def ctl(b, obs):
        return (yield from settle_controller(s, obs, brk))

    (((face, obs), st, _),) = lockstep(DAMPED, SLOPE, d.stand_on(DAMPED, 8, SLOPE, yaw_deg=45.0), ctl, s, record=False)
    (ob,) = observe(DAMPED, SLOPE, st, s, pressure=obs.pressure[None])
    return replace(ob, face=face), brk


def test_the_brake_kept_on_lands_where_every_other_roll_tumbles(ws):
    """From the held state, with the plan of a dead end (every single pair's pressure 0 MPa:
    the unbraked robot predicted outside already), every single pair braked and handed over
    there, and unbraked, tumbles or slides (`lookahead.lands` false): `choose` finds nothing
    among them. The lazy actions add each braked action with its brake kept on (weights of
    ones, no planned pressure), simulated next after the first candidate; some of those land on
    another face, and `choose` returns only those, before it simulates the other candidates."""
    s = lo.RollSettings(brake=True)
    ob, brk = _held(ws, s)
    assert ob.face == topo.face_number((9, 10, 12)) and ob.pressure.any()  # the brake on
    assert brk.active(ob.face, ob.nodes)
    pl = lo.plan(ws, ob.face, ob.nodes, direction=UPHILL)
    singles = [replace(c, pressure=0.0) for c in pl.candidates if len(c.pairs) == 1]
    pl0 = replace(pl, candidates=tuple(singles))  # the plan of the dead ends on 20 deg (results/workspace.nc)
    expect = {c.pairs: c.pressure for c in singles}
    todo = [(c.pairs, True) for c in singles] + [(c.pairs, False) for c in singles]
    target = dict(direction=np.array([*UPHILL, 0.0]))
    alone = lookahead.foresee(DAMPED, SLOPE, s, ob, todo, ws.max_pressure, brk, expect)
    assert not any(lookahead.lands(r) for r in alone)  # handed over at 0 MPa, or unbraked: a fall
    chosen, simulated = lookahead.choose(
        DAMPED,
        SLOPE,
        s,
        ob,
        todo,
        ws.max_pressure,
        brk,
        expect,
        lambda r: 0.0,
        lookahead.Memory(0.1),
        more=lambda: lookahead.acts(ws, ob.face, ob.nodes, pl0, target, brk, lazy=True),
    )
    assert chosen and all(lookahead.weights_of(a) is not None for a in chosen)  # main: none
    assert np.array_equal(simulated[0].cog_after, alone[0].cog_after)  # the plan's first; then kept ones only
    assert simulated[0].weights is None and all(r.weights is not None for r in simulated[1:])  # no world: no optimised
    assert 1 < len(simulated) <= 1 + len(singles) < len(todo)
    for r in simulated[1:]:
        if r.rolled and lookahead.lands(r):
            assert r.face_after != ob.face and lookahead.moved(r) <= lookahead.SLIDE


def test_no_brake_no_kept_actions(ws, equi):
    """On level ground the brake does not act: no action is added (the planner's rolls there are
    unchanged, bit for bit: benchmarks/bench_foresee.py's flat digest)."""
    s = lo.RollSettings(brake=True)
    state = d.stand_on(DAMPED, equi, Terrain.flat())
    (ob,) = observe(DAMPED, Terrain.flat(), state, s)
    pl = lo.plan(ws, equi, ob.nodes, direction=UPHILL)
    brk = Brake(ws, s.brake_margin)
    assert not brk.active(equi, ob.nodes)
    assert lookahead.acts(ws, equi, ob.nodes, pl, dict(direction=np.array([*UPHILL, 0.0])), brk, lazy=True) == []
