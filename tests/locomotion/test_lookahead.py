"""Issue 10 item 3: rolls tried in simulation before the robot acts on steep slopes
(`locomotion.lookahead`). What is simulated must be what the run then does: the same state, the
same controller and brake, so the executed roll equals its prediction to round-off."""

import numpy as np
import pytest

from tensegrity import locomotion as lo
from tensegrity.locomotion import lookahead
from tensegrity.locomotion.control import RollResult
from tensegrity.locomotion.lockstep import Obs
from tensegrity.physics import dynamics as d
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.physics.terrain import Terrain

EQUI = topo.face_number(topo.CONTACT_FACES["equilateral"])  # (9,10,12)
DAMPED = Params(strut_damping=1.0)


def test_the_roll_made_is_the_roll_foreseen(ws):
    """On a 20 deg slope (lookahead applies: an even incline of at least lookahead_tilt) the
    first step simulates the plan's candidates and escape actions from the robot's settled state;
    the attempt the run then makes is the first of `rank`'s order toward the switchback's turning
    point (the goal lies across the slope), and it ends exactly as its simulation did: the same
    face, the same CoG and times, the same peak pressure."""
    s = lo.RollSettings(lookahead=4, max_attempts=1, max_rolls=1, escape_attempts=0)
    slope = Terrain.slope(20.0)
    run = lo.roll_to(ws, (0.0, -2.0), DAMPED, slope, settings=s)
    step = run.steps[0]
    assert len(step.simulated) == 4 and len(step.attempts) == 1
    done = step.attempts[0]
    via = lookahead.switchback(slope, done.cog_before, run.goal)  # from the settled robot
    assert via is not None and via[0] > 1.5  # straight uphill (+x) first
    assert f"by a switchback: straight uphill toward ({via[0]:.2f}, {via[1]:.2f}) m" in run.message
    first = step.simulated[
        lookahead.rank(step.simulated, via, slope, [], lookahead.INCLINE_CLIMB_COST, lookahead.SLIDE)[0]
    ]
    assert done.pairs == first.pairs
    assert (done.rolled, done.face_after) == (first.rolled, first.face_after)
    assert np.allclose(done.cog_after, first.cog_after, rtol=0, atol=1e-12)
    assert (done.t_start, done.t_end, done.peak_pressure) == (first.t_start, first.t_end, first.peak_pressure)
    # with lookahead off the same run plans blindly: nothing simulated
    off = lo.roll_to(
        ws,
        (0.0, -2.0),
        DAMPED,
        Terrain.slope(20.0),
        settings=lo.RollSettings(lookahead=0, max_attempts=1, max_rolls=1, escape_attempts=0),
    )
    assert off.steps[0].simulated == ()


def test_no_lookahead_on_gentler_slopes(ws):
    """Below lookahead_tilt (17 deg) a run plans from the workspace alone."""
    s = lo.RollSettings(lookahead=4, max_attempts=1, max_rolls=1, escape_attempts=0)
    assert lo.roll_to(ws, (0.0, -2.0), DAMPED, Terrain.slope(10.0), settings=s).steps[0].simulated == ()


@pytest.mark.parametrize("azimuth", [0.0, 30.0, -120.0])
def test_switchback_climbs_first_then_descends_at_the_descent_cone(azimuth):
    """A goal across a steep slope is reached via a turning point straight uphill of the start,
    from which the goal lies DESCENT_CONE deg from uphill; goals within CLIMB_CONE of uphill or
    at least DESCENT_CONE from it, and level ground, need none."""
    slope = Terrain.slope(20.0, azimuth)
    up = np.array([np.cos(np.radians(azimuth)), np.sin(np.radians(azimuth))])
    assert slope.height(*(up * 0.1)) > slope.height(0.0, 0.0)  # uphill: along the azimuth
    start = np.array([0.3, -0.2, 0.4])

    def goal(angle, dist=2.0):  # `angle` deg from uphill, to the left
        a = np.radians(azimuth + angle)
        p = start[:2] + dist * np.array([np.cos(a), np.sin(a)])
        return np.array([p[0], p[1], float(slope.height(*p))])

    for angle in (20.0, 90.0, 120.0, -100.0):
        g = goal(angle)
        via = lookahead.switchback(slope, start, g)
        off = via[:2] - start[:2]
        assert np.allclose(off / np.linalg.norm(off), up)  # straight uphill
        assert via[2] == pytest.approx(float(slope.height(via[0], via[1])))
        leg = g[:2] - via[:2]
        seen = np.degrees(np.arccos(leg @ up / np.linalg.norm(leg)))
        assert seen == pytest.approx(lookahead.DESCENT_CONE)
    for angle in (0.0, 5.0, -10.0, 10.0, 135.0, 180.0, -150.0):
        assert lookahead.switchback(slope, start, goal(angle)) is None
    assert lookahead.switchback(Terrain.flat(), start, goal(90.0)) is None


def _res(pairs, rolled, face_after, cog, before=(0.0, 0.0, 0.0)):
    return RollResult(
        pairs, rolled, EQUI, face_after, np.nan, 1.0, 0.0, 1.0, np.asarray(before, float), np.asarray(cog, float)
    )


def test_rank_puts_landed_rolls_first_and_tumbles_last():
    """Landed rolls by distance to the goal (ending below it costs CLIMB_COST per m of height),
    then the attempts that did not roll, then the tumbles, however close they ended."""
    slope = Terrain.slope(20.0)
    goal = np.array([0.0, -2.0, 0.0])  # across the slope, at the start's height
    t = np.tan(np.radians(20.0))
    res = [
        _res((1,), False, None, (0.0, -2.0, 0.0)),  # tumbled, right at the goal
        _res((2,), False, EQUI, (0.0, 0.0, 0.0)),  # did not roll
        _res((3,), True, 5, (0.0, -0.2, 0.0)),  # 1.8 m away, level
        _res((4,), True, 6, (-0.1, -0.3, -0.1 * t)),  # 1.70 m away, 0.036 m lower: 1.88
        _res((5,), True, 7, (0.0, -0.25, 0.0)),
    ]  # 1.75 m away, level
    assert lookahead.rank(res, goal, slope) == [4, 2, 3, 1, 0]
    assert lookahead.rank(res, goal, slope, climb=0.0) == [3, 4, 2, 1, 0]  # height ignored
    # a landing whose CoG moved further than `slide` (1.0 m from (0, 0.8)) is a tumble
    slid = res[:4] + [_res((5,), True, 7, (0.0, -0.25, 0.0), before=(0.0, 0.8, 0.0))]
    assert lookahead.rank(slid, goal, slope) == [4, 2, 3, 1, 0]
    assert lookahead.rank(slid, goal, slope, slide=0.5) == [2, 3, 1, 0, 4]
    assert lookahead.lands(slid[4], 1.06) and not lookahead.lands(slid[4], 1.04)
    # a face of the last steps costs REVISIT_COST: landing back on 7 falls behind 5 and 6
    assert lookahead.REVISIT_COST > 0.18
    assert lookahead.rank(res, goal, slope, avoid=[7, 9]) == [2, 3, 4, 1, 0]
    with pytest.raises(ValueError, match="no state"):
        lookahead.foresee(
            DAMPED,
            slope,
            lo.RollSettings(),
            Obs(0.0, np.zeros((12, 3)), np.zeros(12), EQUI, np.nan),
            [(1,)],
            4.8,
            None,
            {},
        )


def test_choose_foresees_every_action_before_giving_up(ws, monkeypatch):
    """When every one of the first `lookahead` actions tumbles, `choose` foresees the face's
    other actions (each once) before a run ends stuck, and returns those that land."""
    batches = []

    def fake(params, terrain, s, obs, acts, max_pressure, brake, expect):
        batches.append(list(acts))
        land = len(batches) > 1  # the first batch all tumbles, the second lands
        return [_res(a, land, 5 if land else None, (0.0, -0.1 * k, 0.0)) for k, a in enumerate(acts)]

    monkeypatch.setattr(lookahead, "foresee", fake)
    s = lo.RollSettings(lookahead=3, max_attempts=2)
    slope = Terrain.slope(20.0)
    st = d.stand_on(DAMPED, EQUI, slope)
    obs = Obs(0.0, d.nodes(st.x, st.q, DAMPED.strut_length)[0], np.zeros(12), EQUI, 0.0)
    pl = lo.plan(ws, EQUI, obs.nodes, goal=np.array([0.0, -2.0, 0.0]))
    todo, simulated = lookahead.choose(
        ws, DAMPED, slope, s, obs, EQUI, pl, set(), np.array([0.0, -2.0, 0.0]), None, dict(goal=np.array([0.0, -2.0]))
    )
    first, rest = batches
    assert len(first) == 3 and rest and not set(first) & set(rest)
    every = {(int(q),) for q in ws.pairs(EQUI)}
    assert set(first) | set(rest) >= every  # every single pair foreseen
    assert len(simulated) == len(first) + len(rest)
    assert len(todo) == 2 and all(a in rest for a in todo)
