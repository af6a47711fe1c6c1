"""Issue 30: the optimised actions of any set of pairs (`actuation.candidates`) in the one-method
planner (`lookahead`). An action with a weight vector is simulated ahead with the run's own
controller, so the roll made equals its simulation; it is stored in the run file; the lazy
generator is computed only when no earlier action is acceptable."""

import numpy as np
import pytest

from tensegrity import locomotion as lo
from tensegrity.io.formats.run import run_dataset
from tensegrity.locomotion import lookahead, progress
from tensegrity.locomotion.control import RollResult
from tensegrity.locomotion.lockstep import Obs
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.physics.terrain import Terrain

EQUI = topo.face_number(topo.CONTACT_FACES["equilateral"])  # (9,10,12)
DAMPED = Params(strut_damping=1.0)


def _res(pairs, face_after, cog):
    z = np.zeros(3)
    return RollResult(pairs, face_after is not None, EQUI, face_after, np.nan, 1.0, 0.0, 1.0, z, np.asarray(cog, float))


def test_optimised_actions_enter_next_after_the_first_once_it_is_not_acceptable(monkeypatch):
    """`choose` calls the lazy generator (`more`) only once the first action is not acceptable
    (here: it tumbles), and simulates its actions next, before the other actions; they may be
    chosen. Where the first is acceptable, `more` is not called."""
    w = tuple([1.0, 0.5] + [0.0] * 10)
    rolls = {
        (1,): _res((1,), None, (0.2, 0, 0)),  # tumbles
        (2,): _res((2,), 5, (-0.2, 0, 0)),  # lands, but away from the goal
        (1, 2): _res((1, 2), 7, (0.2, 0, 0)),  # the optimised action: lands toward the goal
    }
    asked = []
    simulate = lambda *a: asked.extend(t[0] for t in a[4]) or [rolls[t[0]] for t in a[4]]  # noqa: E731
    monkeypatch.setattr(lookahead, "foresee", simulate)
    calls = []

    def more():
        calls.append(1)
        return [((1, 2), False, w)]

    goal = np.array([2.0, 0.0, 0.0])
    cost = lambda r: progress.rolls_to_goal(r.cog_after, goal, Terrain.flat(), 0.2, 0.01)  # noqa: E731
    now = cost(_res((), 1, (0, 0, 0)))
    s = lo.RollSettings(lookahead=2, max_attempts=1)
    obs = Obs(0.0, np.zeros((12, 3)), np.zeros(12), EQUI, 0.0)
    args = (DAMPED, Terrain.flat(), s, obs)
    chosen, sim = lookahead.choose(
        *args, [((1,), False), ((2,), False)], 4.8, None, {}, cost, lookahead.Memory(0.05), now, more
    )
    assert calls == [1] and chosen == [((1, 2), False, w)] and asked == [(1,), (1, 2)] and len(sim) == 2
    rolls[(1,)] = _res((1,), 5, (0.2, 0, 0))  # now the first makes progress: nothing lazy is computed
    asked.clear()
    chosen, sim = lookahead.choose(
        *args, [((1,), False), ((2,), False)], 4.8, None, {}, cost, lookahead.Memory(0.05), now, more
    )
    assert calls == [1] and chosen == [((1,), False)] and asked == [(1,)] and len(sim) == 1
    # off (the default) or without a state, the generator gives nothing; a 0/1 vector is a pairs action
    world = lookahead.World(DAMPED, Terrain.flat(), None, 4.8, optimised=True)
    assert lookahead._optimised(None, EQUI, np.zeros((12, 3)), None, {}, world) == []
    assert lookahead._act(np.eye(12)[3]) == ((4,),) and lookahead._act(np.array(w)) == ((1, 2), w)


@pytest.mark.slow  # ~13 s: the optimised actions of one pose and their rolls, simulated
def test_a_weighted_action_rolls_as_foreseen_and_is_stored(ws, monkeypatch):
    """With only the optimised generator's weighted actions, a flat run's first step simulates the optimised actions
    from the robot's state and makes the best: the roll made equals its simulation to round-off
    (face, CoG, times, peak level), its weights are those of `actuation.candidates`, and the
    run file stores them (`step_weight`) with the action's nonzero pairs in `step_pair`."""
    weighted = lambda *a: [w for w in lookahead._optimised(*a) if not np.all((w == 0) | (w == 1))]  # noqa: E731
    monkeypatch.setattr(lookahead, "GENERATORS", [weighted])  # (a vector of ones and zeros is a pairs action)
    s = lo.RollSettings(max_rolls=1, max_attempts=1, optimised_actions=True)
    run = lo.roll_to(ws, (2.0, 0.0), DAMPED, settings=s)
    step = run.steps[0]
    done = step.attempts[0]
    assert done.weights is not None and done.rolled
    twin = [r for r in step.simulated if r.weights is not None and np.array_equal(r.weights, done.weights)]
    assert twin and twin[0].face_after == done.face_after
    assert np.allclose(twin[0].cog_after, done.cog_after, rtol=0, atol=1e-12)
    assert (twin[0].t_end - twin[0].t_start, twin[0].peak_pressure) == (done.t_end - done.t_start, done.peak_pressure)
    ds = run_dataset(run, Terrain.flat(), DAMPED)
    stored = ds["step_weight"].values[0]
    assert np.array_equal(stored, done.weights) and stored.max() == 1.0
    assert [q for q in ds["step_pair"].values[0] if q] == [int(q) + 1 for q in np.flatnonzero(stored > 0)]
