"""Issue 10 item 3: measured two-pair curves in the lookup, braking on slopes, escaping a stuck
face. The single-pair workspace `ws` (conftest) comes from the independent static solver; the
two-pair data here too (`statics.equilibrium` with two pairs set), on (9,10,12) only."""

import numpy as np
import pytest

from tensegrity import locomotion as lo
from tensegrity.locomotion.brake import Brake, escape, hold
from tensegrity.locomotion.control import settle_controller
from tensegrity.locomotion.lockstep import lockstep
from tensegrity.physics import contact as ct
from tensegrity.physics import dynamics as d
from tensegrity.physics import frames, statics
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.physics.terrain import Terrain

EQUI = topo.face_number(topo.CONTACT_FACES["equilateral"])  # (9,10,12)
ISO = topo.face_number(topo.CONTACT_FACES["isosceles"])  # (10,11,12)
COMBOS = [(6, 10), (9, 10), (10, 11)]
DAMPED = Params(strut_damping=1.0)


def two_pair(levels):
    """The read_two_pair contract (combos, levels, cog (20,C,L,L,3), support (20,C,L,L,3,3)),
    both pairs at the same level from the static solve on (9,10,12); NaN elsewhere."""
    free = Params(gravity=0.0)
    C, L = len(COMBOS), len(levels)
    cog, sup = np.full((20, C, L, L, 3), np.nan), np.full((20, C, L, L, 3, 3), np.nan)
    for c, (a, b) in enumerate(COMBOS):
        nodes = None
        for i, lev in enumerate(levels):
            p = np.zeros(12)
            p[[a - 1, b - 1]] = lev
            nodes = statics.equilibrium(free, p, start=nodes)
            cog[EQUI - 1, c, i, i], sup[EQUI - 1, c, i, i] = statics.support_cog(nodes, EQUI)
    return np.array(COMBOS), np.array(levels, float), cog, sup


@pytest.fixture(scope="module")
def measured(levels):
    return two_pair(levels)


def standing(face, terrain=None, yaw=0.0):
    s = d.stand_on(Params(), face, terrain or Terrain.flat(), yaw_deg=yaw)
    return d.nodes(s.x, s.q, 0.5)[0]


def test_measured_two_pair_curves_replace_superposition(ws, measured, levels):
    """The lookup returns the static solve's two-pair CoG and triangle (not the sum of the
    single-pair shifts, which is 13 to 42 mm off at 4.8 MPa), whichever order the pairs come in,
    and predict's margins on flat ground are the static solve's margins."""
    both = ws.with_two_pair(*measured)
    k = np.arange(len(levels))
    for c, combo in enumerate(COMBOS):
        cog, sup = both.curve(EQUI, [combo, combo[::-1]])
        assert np.allclose(cog[:, 1:], measured[2][EQUI - 1, c, k, k], atol=1e-12)
        assert np.allclose(sup[:, 1:], measured[3][EQUI - 1, c, k, k], atol=1e-12)
        assert np.allclose(cog[:, 0], ws.rest_cog[EQUI - 1])
        summed, _ = ws.curve(EQUI, [combo])
        assert np.linalg.norm(summed[0, -1, :2] - cog[0, -1, :2]) > 0.01  # superposition is off
        pred = lo.predict(both, EQUI, standing(EQUI), [combo])
        truth = frames.margin_2d(measured[2][EQUI - 1, c, k, k, :2], measured[3][EQUI - 1, c, k, k, :, :2])
        assert np.allclose(pred.margin[0, 1:], truth, atol=1e-9)


def test_two_pair_fallback_and_interpolation(ws, measured):
    """Faces without data, and data that does not reach the workspace's highest level, fall back
    to superposition; coarser two-pair levels are interpolated linearly, from the unactuated
    robot (0 MPa) below their first level."""
    both = ws.with_two_pair(*measured)
    assert np.array_equal(both.curve(ISO, [(6, 10)])[0], ws.curve(ISO, [(6, 10)])[0])
    assert both.measured(EQUI, (6, 10)) == 0 and both.measured(ISO, (6, 10)) is None
    assert both.measured(EQUI, (1, 2)) is None
    short = ws.with_two_pair(measured[0], measured[1][:4], measured[2][:, :, :4, :4], measured[3][:, :, :4, :4])
    assert short.measured(EQUI, (6, 10)) is None  # no data above 3.2 MPa
    coarse = [0, 2, 4, 5]  # 0.8, 2.4, 4.0, 4.8 MPa
    sub = ws.with_two_pair(
        measured[0],
        measured[1][coarse],
        measured[2][:, :, coarse][:, :, :, coarse],
        measured[3][:, :, coarse][:, :, :, coarse],
    )
    mid = sub.curve(EQUI, [(6, 10)])[0][0, 2]  # 1.6 MPa, between 0.8 and 2.4
    lo_, hi = measured[2][EQUI - 1, 0, 0, 0], measured[2][EQUI - 1, 0, 2, 2]
    assert np.allclose(mid, 0.5 * (lo_ + hi), atol=1e-12)
    low = [1, 3, 5]  # 1.6, 3.2, 4.8 MPa: 0.8 MPa lies between the unactuated robot and 1.6
    sub = ws.with_two_pair(
        measured[0], measured[1][low], measured[2][:, :, low][:, :, :, low], measured[3][:, :, low][:, :, :, low]
    )
    first = sub.curve(EQUI, [(6, 10)])[0][0, 1]
    assert np.allclose(first, 0.5 * (ws.rest_cog[EQUI - 1] + measured[2][EQUI - 1, 0, 1, 1]), atol=1e-12)
    with pytest.raises(ValueError, match="two-pair cog must have shape"):
        ws.with_two_pair(measured[0], measured[1], measured[2][:, :2], measured[3])


# --------------------------------------------------------------------------------- braking


def _settled_face(brake, terrain, face, yaw):
    s = lo.RollSettings(settle_time=3.0, settle_speed=1e-9, brake=brake is not None)  # 3 s
    state = d.stand_on(DAMPED, face, terrain, yaw_deg=yaw)
    tri = topo.FACES[face - 1]
    start = d.nodes(state.x, state.q, 0.5)[0][tri]
    ctl = lambda b, o: settle_controller(s, o, brake)
    (res, _), st, _ = lockstep(DAMPED, terrain, state, ctl, s)[0]
    return res, float(np.max(np.linalg.norm(d.nodes(st.x, st.q, 0.5)[0][tri] - start, axis=-1)))


def test_brake_keeps_the_robot_on_its_face_on_a_slope(ws):
    """On a 20 deg slope the unactuated robot standing on (9,10,12) (the runs' start) tumbles
    off, although the workspace puts its CoG projection 10 mm inside (it sags under gravity);
    the brake chosen from the workspace (the single pair moving the projection furthest inside,
    raised at brake_rate) holds it on that face for 3 s; its support nodes move by the
    deformation only (< 7 cm), not by a roll (> 20 cm)."""
    slope = Terrain.slope(20.0)
    assert 0 < ct.judge(standing(EQUI, slope), EQUI).margin < 0.035
    face, moved = _settled_face(None, slope, EQUI, 0.0)
    assert face != EQUI and moved > 0.2
    p = hold(ws, EQUI, standing(EQUI, slope), 0.035)
    assert np.count_nonzero(p) == 1 and p.max() <= ws.max_pressure
    face, moved = _settled_face(Brake(ws, 0.035), slope, EQUI, 0.0)
    assert face == EQUI and moved < 0.07


def test_no_brake_where_the_robot_stands_anyway(ws):
    assert not hold(ws, EQUI, standing(EQUI), 0.035).any()  # flat: 88 mm inside


def test_landing_pose_puts_the_next_face_on_the_ground():
    slope = Terrain.slope(15.0)
    p = standing(EQUI, slope, 20.0)
    for k in range(3):
        edge = topo.edge_nodes(EQUI, k)
        q = ct.roll_over(p, EQUI, edge)[1]
        gap = ct.clearance(q, slope, 0.0)
        nxt = topo.FACES[topo.neighbour(EQUI, edge) - 1]
        on = ct.clearance(p, slope, 0.0)[topo.FACES[EQUI - 1]]  # the strut radius
        assert np.allclose(gap[nxt], on, atol=1e-9) and np.all(gap > on[0] - 1e-9)
        assert np.allclose(
            np.linalg.norm(q[:, None] - q[None], axis=-1), np.linalg.norm(p[:, None] - p[None], axis=-1), atol=1e-12
        )  # rigid


# ---------------------------------------------------------------------------------- escape


def test_escape_orders_actions_that_roll_first(ws):
    p = standing(EQUI)
    order = escape(ws, EQUI, p, {(10,)}, direction=(1.0, 0.0))
    assert (10,) not in order and len(order) == 12 - 1 + 66
    pred = lo.predict(ws, EQUI, p, order)
    rolls = [np.isfinite(frames.first_crossing(pred.pressure, m)[0]) for m in pred.margin]
    assert rolls[0] and sorted(rolls, reverse=True) == rolls  # predicted rolls come first


def test_escape_from_a_stuck_face(ws, levels):
    """With the workspace swept only to 1.6 MPa no single pair rolls the robot off (9,10,12)
    ("stuck", see test_stuck_when_the_workspace_cannot_roll_the_robot); tried in the world (lookahead
    0), the escape tries two
    pairs together as well and rolls it off."""
    low = lo.Workspace.from_arrays(levels[:2], ws.cog[:, :, :2], ws.support[:, :, :2])
    stuck = lo.roll_to(
        low,
        (2.0, 0.0),
        DAMPED,
        settings=lo.RollSettings(max_attempts=2, combine=False, max_rolls=1, escape_attempts=0, lookahead=0),
    )
    assert stuck.outcome == "stuck" and stuck.rolls == 0
    run = lo.roll_to(
        low,
        (2.0, 0.0),
        DAMPED,
        settings=lo.RollSettings(max_attempts=2, combine=False, max_rolls=1, escape_attempts=4, lookahead=0),
    )
    assert run.outcome == "step_limit" and run.rolls == 1
    assert len(run.steps[0].attempts) > 2 and len(run.steps[0].used.pairs) == 2
