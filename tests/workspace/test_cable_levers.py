"""Per-cable levers of the sensitivity model (issue 30: "the 24 cables one by one"): a pair
pressure is that pressure on both its cables, so the per-cable model reproduces the per-pair one
bit for bit there, its sensitivity summed over each pair's two cables is the pair's (the lever
map is linear, up to the forward difference's curvature), and a set of pairs being a set of
cables, the cables' least-pressure programme is never above the pairs'."""

import numpy as np
import pytest

from tensegrity.physics import dynamics as d
from tensegrity.physics import statics
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.workspace import cable_actions as ca
from tensegrity.workspace import gravity as gv
from tensegrity.workspace import sensitivity as sv
from tensegrity.workspace import slope_limit as sl
from tensegrity.workspace.slopes import place, slope_field

SETUP = gv.GravitySetup()
PARAMS = SETUP.rolling(Params())
FACE = topo.face_number((9, 10, 12))
NODES = sl.pose(PARAMS, FACE, 12.0, 0.0)


def test_cable_law_of_lifted_pair_pressures_is_the_pair_law():
    p = np.linspace(0.0, 4.4, topo.N_PAIRS)
    for a, b in zip(sv.cable_law(PARAMS, topo.cable_levels(p)), statics.cable_law(PARAMS, p)):
        np.testing.assert_array_equal(a, b)
    with pytest.raises(ValueError):
        sv.Model(PARAMS, FACE, np.array([0.0, 0.0, -1.0]), levers=13)


def test_lifted_pressures_give_the_same_distances():
    m12, m24 = sv.grounded(PARAMS, FACE, NODES), sv.grounded(PARAMS, FACE, NODES, topo.N_CABLES)
    np.testing.assert_array_equal(m12.offset, m24.offset)
    p = np.array([np.zeros(12), np.eye(12)[9] * 3.0, np.linspace(0, 2, 12)])
    np.testing.assert_array_equal(m12.d(p), m24.d(topo.cable_levels(p)))


@pytest.mark.parametrize("step, tol", [(sv.STEP, 0.05), (0.01, 0.005)])
def test_pair_sensitivity_is_the_sum_over_its_cables(monkeypatch, step, tol):
    """At 0 and at 2 MPa on pairs 7 and 9: D_pair = D_cable1 + D_cable2 (the derivatives; the
    forward differences of a step h on one cable or on both differ by the curvature, O(h): under
    5 % of the largest entry at STEP, under 0.5 % at 0.01 MPa)."""
    monkeypatch.setattr(sv, "STEP", step)
    m12, m24 = sv.grounded(PARAMS, FACE, NODES), sv.grounded(PARAMS, FACE, NODES, topo.N_CABLES)
    for base in (np.zeros(12), 2.0 * (np.eye(12)[6] + np.eye(12)[8])):
        d12, D12 = sv.sensitivity(m12, base)
        d24, D24 = sv.sensitivity(m24, topo.cable_levels(base))
        np.testing.assert_array_equal(d12, d24)
        summed = np.zeros((3, topo.N_PAIRS))
        np.add.at(summed.T, topo.CABLE_PAIR, D24.T)
        assert np.abs(summed - D12).max() < tol * np.abs(D12).max(), (summed, D12)


def test_cables_least_pressure_programme_is_not_above_the_pairs():
    """The first programme of edge_action (linearised at 0) for each edge: the pairs' optimum
    lifted to the cables is feasible for the cables' (with the pair sensitivity split by the
    cable sensitivities, exact in the linear programme's own model), so the cables' least total
    is at most the pairs' lifted total (twice the pairs' sum)."""
    from scipy.optimize import linprog

    d0, D24 = sv.sensitivity(sv.grounded(PARAMS, FACE, NODES, topo.N_CABLES), np.zeros(24))
    D12 = np.zeros((3, topo.N_PAIRS))
    np.add.at(D12.T, topo.CABLE_PAIR, D24.T)  # the pair model the cables' linearisation implies
    for k in range(3):
        others = [j for j in range(3) if j != k]
        out = []
        for D, n in ((D12, 12), (D24, 24)):
            rows = np.vstack([D[k], -D[others]])
            rhs = np.concatenate([[-d0[k]], d0[others] - 0.005])
            res = linprog(np.ones(n), A_ub=rows, b_ub=rhs, bounds=[(0, SETUP.max_pressure)] * n, method="highs")
            out.append(res.fun if res.status == 0 else np.inf)
        pairs, cables = out
        assert cables <= 2 * pairs + 1e-9, (k, pairs, cables)


def test_cables_climb_wherever_pairs_do():
    """On 12 deg at heading 0 of the equilateral face the pairs roll it uphill (the statics), so do
    the cables (24 weights); edge_action with the default levers answers in pairs."""
    v = ca.verdict(PARAMS, FACE, 12.0, 0.0, SETUP.max_pressure, 0.005)
    assert v.stands and v.ok["pairs_least"] and v.ok["pairs"] and v.ok["cables"]
    assert v.actions["cables"].weights.shape == (topo.N_CABLES,)
    k = [topo.edge_nodes(FACE, i) for i in range(3)].index(v.actions["pairs_least"].edge)
    a = sv.edge_action(sv.grounded(PARAMS, FACE, NODES), k, SETUP.max_pressure, 0.005)
    assert a is not None and a.weights.shape == (topo.N_PAIRS,)
    np.testing.assert_array_equal(a.weights, v.actions["pairs_least"].weights)


def test_cable_action_rolls_the_isosceles_face_uphill_where_its_pairs_do_not():
    """The case the statics said 24 cables add (docs/planner_evaluation.md, "Would 24 cable
    actuators extend the uphill limit?"): the isosceles face (10,11,12) on 23 deg with uphill at
    heading 270, across its gap edge 11-12, above the pairs' statics limit (19.7 deg). The
    statics' cable action drives one cable only of pairs #6 and #9; ramped in the simulator (one
    pressure per cable) it rolls the robot uphill over 11-12, and the same pairs on both their
    cables (each at its larger cable's weight) do not tip it."""
    face = topo.face_number((10, 11, 12))
    c = ca.verdict(PARAMS, face, 23.0, 270.0, SETUP.max_pressure, 0.005).actions["cables"]
    w = c.weights[topo.PAIR_CABLES]  # (12, 2)
    assert c.edge == (11, 12) and sorted(np.flatnonzero((w > 0).sum(1) == 1) + 1) == [6, 9]
    W = np.stack([c.weights, topo.cable_levels(w.max(1))])
    terrain, centres = slope_field([23.0, 23.0])
    state = d.State.concat([place(PARAMS, face, terrain, x, 270.0) for x in centres])
    level, n_settle = SETUP.levels()
    rec, gone = gv.ramp(PARAMS, terrain, face, state, W, level, n_settle, SETUP)
    cable, pairs = (gv.tip(rec, b, face, n_settle, gone[b]) for b in range(2))
    assert cable[2] == (11, 12) and cable[0] < SETUP.max_pressure, cable
    assert pairs[2] is None, pairs
