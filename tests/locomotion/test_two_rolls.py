"""Two rolls ahead where no single roll is acceptable (`locomotion.sequence`, issue 30): from a
state where every roll that lands goes back to a state the run has been at, `lookahead.choose`
has nothing, and `sequence.two_rolls` finds a first roll whose landing has a roll onward to a new
state nearer the goal, simulated from the landing; where every state is one the run has been at,
it has nothing either (a route still cannot cycle)."""

from dataclasses import replace

import numpy as np

from tensegrity import locomotion as lo
from tensegrity.locomotion import lookahead, progress, sequence
from tensegrity.locomotion.brake import Brake
from tensegrity.locomotion.control import settle_controller
from tensegrity.locomotion.drive import _next
from tensegrity.locomotion.lockstep import lockstep
from tensegrity.locomotion.plan import plan
from tensegrity.physics import dynamics as d
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.physics.terrain import Terrain

EQUI = topo.face_number(topo.CONTACT_FACES["equilateral"])  # (9,10,12)
DAMPED = Params(strut_damping=1.0)
GOAL = np.array([2.0, 0.0, 0.0])


def _singles(ws, s, target):
    """drive's next-step candidates, single pairs only (a smaller batch, the same method)."""

    def after(ob, bk):
        acts, expect = _next(ws, DAMPED, Terrain.flat(), s, ob, bk, visited=[EQUI], target=target)
        return [a for a in acts if len(a[0]) == 1], expect

    return after


def _settled_obs(ws, s, brk):
    """The robot settled on (9,10,12) on flat ground, as a run starts: its Obs with its state."""

    def ctl(b, obs):
        _, obs = yield from settle_controller(s, obs, brk)
        return obs

    ((obs, state, _),) = lockstep(DAMPED, Terrain.flat(), d.stand_on(DAMPED, EQUI, Terrain.flat()), ctl, s)
    return replace(obs, state=state)


def test_when_every_roll_returns_two_rolls_ahead_find_a_way_on(ws):
    s = lo.RollSettings(lookahead=4)
    flat, brk, target = Terrain.flat(), Brake(ws, s.brake_margin), dict(goal=GOAL)
    obs = _settled_obs(ws, s, brk)
    pl = plan(ws, EQUI, obs.nodes, **target)
    expect = {c.pairs: c.pressure for c in pl.candidates}
    todo = [a for a in lookahead.acts(ws, EQUI, obs.nodes, pl, target, brk) if len(a[0]) == 1]
    sim = lookahead.foresee(DAMPED, flat, s, obs, todo, ws.max_pressure, brk, expect)
    travel, lift = progress.stride(obs.nodes, EQUI)
    cost = lambda r: progress.rolls_to_goal(r.cog_after, GOAL, flat, travel, lift)  # noqa: E731
    now = progress.rolls_to_goal(obs.cog, GOAL, flat, travel, lift)
    memory = lookahead.Memory(travel / 2)
    memory.add(EQUI, obs.cog)
    landed = [r for r in sim if r.rolled and lookahead.lands(r)]
    assert {r.face_after for r in landed} == {topo.neighbour(EQUI, topo.edge_nodes(EQUI, k)) for k in range(3)}
    for r in landed:  # the run has stood wherever a single roll lands
        memory.add(r.face_after, r.cog_after)
    args = (DAMPED, flat, s, obs, todo, ws.max_pressure, brk, expect, cost, memory, now)
    assert lookahead.choose(*args)[0] == []

    firsts, count = sequence.two_rolls(*args[:5], sim, *args[5:], _singles(ws, s, target))
    assert firsts and count > len(sequence.landings(sim, cost, memory.radius))
    # the sequence simulated again, roll by roll: the first lands where the run has been, the
    # second, planned from there as the run would, goes on to a new state nearer the goal
    ((r1, ob1, bk1),) = lookahead.foresee(DAMPED, flat, s, obs, firsts[:1], ws.max_pressure, brk, expect, landings=True)
    assert r1.rolled and memory.seen(r1.face_after, r1.cog_after)
    acts, expect1 = _singles(ws, s, target)(ob1, bk1)
    second = lookahead.foresee(DAMPED, flat, s, ob1, acts, ws.max_pressure, bk1, expect1)
    onward = [r for r in second if r.rolled and lookahead.lands(r) and not memory.seen(r.face_after, r.cog_after)]
    assert onward and min(cost(r) for r in onward) < now

    # every face seen everywhere (one memory radius over the whole ground): no sequence either
    everywhere = lookahead.Memory(1e3, [(f, np.zeros(2)) for f in range(1, 21)])
    args = (DAMPED, flat, s, obs, todo, sim, ws.max_pressure, brk, expect, cost, everywhere, now)
    firsts, count = sequence.two_rolls(*args, _singles(ws, s, target))
    assert firsts == [] and count > 3


def test_the_best_roll_into_a_dead_end_gives_way_to_one_with_a_way_on(ws):
    """`sequence.alive`: of the acceptable rolls, the first whose landing has an acceptable roll
    onward goes first. On flat ground, with every face seen (one memory radius over the whole
    ground) but the start face's three neighbours and the faces beyond the second-best one, the
    best roll (toward the goal) lands where every roll onward returns: the second goes first."""
    s = lo.RollSettings(lookahead=4)
    flat, brk = Terrain.flat(), Brake(ws, s.brake_margin)
    obs = _settled_obs(ws, s, brk)
    target = dict(goal=GOAL)
    pl = plan(ws, EQUI, obs.nodes, **target)
    expect = {c.pairs: c.pressure for c in pl.candidates}
    todo = [a for a in lookahead.acts(ws, EQUI, obs.nodes, pl, target, brk) if len(a[0]) == 1]
    travel, lift = progress.stride(obs.nodes, EQUI)
    cost = lambda r: progress.rolls_to_goal(r.cog_after, GOAL, flat, travel, lift)  # noqa: E731
    sim = lookahead.foresee(DAMPED, flat, s, obs, todo, ws.max_pressure, brk, expect)
    ranked = sorted((i for i, r in enumerate(sim) if r.rolled and lookahead.lands(r)), key=lambda i: cost(sim[i]))
    faces = list(dict.fromkeys(sim[i].face_after for i in ranked))  # the neighbours, best first
    assert len(faces) == 3
    beyond = {topo.neighbour(faces[1], topo.edge_nodes(faces[1], k)) for k in range(3)} - {EQUI}
    seen = set(range(1, 21)) - set(faces) - beyond
    memory = lookahead.Memory(1e3, [(f, np.zeros(2)) for f in sorted(seen)])
    chosen = [todo[i] for i in ranked]
    got, count = sequence.alive(
        DAMPED, flat, s, obs, chosen, ws.max_pressure, brk, expect, cost, memory, _singles(ws, s, target)
    )
    first = lookahead.foresee(DAMPED, flat, s, obs, got[:1], ws.max_pressure, brk, expect)[0]
    assert sim[ranked[0]].face_after == faces[0] and first.face_after == faces[1]
    assert len(got) == s.max_attempts and count > 2
