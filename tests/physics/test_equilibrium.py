"""Batched Newton statics (tensegrity.physics.equilibrium) against the independent energy
minimisation of physics.statics (BFGS on another parametrisation): the same equilibria, the same
gradient with slack cables, and the clamped law's force balance."""

import numpy as np
import pytest

from tensegrity.physics import actuator, frames, statics
from tensegrity.physics import equilibrium as eq
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params

BASE = Params()
CASES = [  # design, pair pressures (pair: MPa)
    (BASE, {10: 2.4}),
    (BASE.replace(cable_stiffness=700.0, cable_pretension=12.0), {11: 4.0, 3: 1.5, 7: 0.8}),
    (BASE.replace(strut_length=0.6, muscle_gain=450.0, cable_pretension=30.0), {4: 4.8}),
]


def _law(prm: Params, pressure: np.ndarray):
    act = actuator.activations(prm.muscle_gain, pressure)
    return actuator.spring(prm.cable_stiffness, prm.cable_rest_length, prm.muscle_min_length, act)


def _solve(cases):
    """Equilibrium nodes (B, 12, 3) m of the cases, one batch, from the symmetric state."""
    S = np.array([prm.strut_length for prm, _ in cases])
    pres = np.zeros((len(cases), topo.N_PAIRS))
    for b, (_, pairs) in enumerate(cases):
        for pair, v in pairs.items():
            pres[b, pair - 1] = v
    k, ls = map(np.stack, zip(*[_law(prm, p) for (prm, _), p in zip(cases, pres)]))
    X, C = eq.struts(topo.reference_nodes(1.0)[None] * S[:, None, None])
    X, C, it = eq.solve(X, C, S, k, ls)
    assert np.all((it >= 0) & (it < 12)), it  # Newton with the exact Hessian: a few steps
    return eq.nodes(X, C, S), pres, k, ls


def test_agrees_with_the_independent_statics():
    nodes, pres, _, _ = _solve(CASES)
    for b, (prm, _) in enumerate(CASES):
        ref = statics.equilibrium(prm, pres[b])
        # frame-free comparisons: the CoG in two support frames and every cable length. The
        # oracle converges to ~1e-11 m; 1e-9 m = 1e-6 mm is the agreement the issue asks for.
        for face in (8, 20):
            a, b_ = frames.in_support_frame(nodes[b], face)[0], frames.in_support_frame(ref, face)[0]
            np.testing.assert_allclose(a, b_, rtol=0, atol=1e-9)
        ln = lambda n: np.linalg.norm(n[topo.CABLES[:, 1]] - n[topo.CABLES[:, 0]], axis=1)  # noqa: E731
        np.testing.assert_allclose(ln(nodes[b]), ln(ref), rtol=0, atol=1e-9)
        struts = np.linalg.norm(nodes[b, topo.STRUTS[:, 0]] - nodes[b, topo.STRUTS[:, 1]], axis=1)
        np.testing.assert_allclose(struts, prm.strut_length, rtol=0, atol=1e-12)


def test_cables_pull_and_balance_every_strut():
    """At each equilibrium the law's NumPy twin (clamped: never pushes) balances every strut."""
    nodes, pres, _, _ = _solve(CASES)
    for b, (prm, _) in enumerate(CASES):
        n = nodes[b]
        e = n[topo.CABLES[:, 1]] - n[topo.CABLES[:, 0]]
        ln = np.linalg.norm(e, axis=1)
        rows = actuator.constants([getattr(prm, f) for f in actuator.NAMES])[:, None]
        t = actuator.tensions(ln, 0.0, actuator.activations(prm.muscle_gain, pres[b]), rows)
        assert t.min() > 0.5  # taut: the structure is prestressed
        f = np.zeros((topo.N_NODES, 3))
        np.add.at(f, topo.CABLES[:, 0], (t / ln)[:, None] * e)
        np.add.at(f, topo.CABLES[:, 1], -(t / ln)[:, None] * e)
        a, c = topo.STRUTS.T
        centre = 0.5 * (n[a] + n[c])
        net = f[a] + f[c]
        torque = np.cross(n[a] - centre, f[a]) + np.cross(n[c] - centre, f[c])
        # tensions ~10-100 N; a 1e-10 m shape error leaves ~K * 1e-10 m = 1e-7 N
        assert np.abs(net).max() < 1e-7 and np.abs(torque).max() < 1e-7


def test_gradient_with_slack_cables_is_the_independent_one():
    """Away from equilibrium, with some cables slack (l < l*), the solver's gradient equals
    statics.cable_energy's: slack cables neither push nor pull."""
    rng = np.random.default_rng(3)
    X, C = eq.struts(topo.reference_nodes(0.5))
    X = X + 0.01 * rng.standard_normal((6, 3))
    C = C + 0.05 * rng.standard_normal((6, 3))
    C /= np.linalg.norm(C, axis=1, keepdims=True)
    n = eq.nodes(X, C, 0.5)
    ln = np.linalg.norm(n[topo.CABLES[:, 1]] - n[topo.CABLES[:, 0]], axis=1)
    k, ls = _law(BASE, np.zeros(topo.N_PAIRS))
    ls = ls.copy()
    ls[:5] = ln[:5] + 0.01  # five cables slack
    E, g, H = np.empty((6, 3, 2)), np.empty(30), np.empty((30, 30))
    work = (np.empty((12, 3)), np.empty((12, 3)), np.empty((12, 3, 5)), np.empty((3, 5)))
    eq._basis(C, E)
    eq._assemble(X, C, E, 0.25, k, ls, eq._NS, eq._SG, eq._CAB, g, H, *work)
    U, gx, gd = statics.cable_energy(X, C, 0.5, k, ls)
    g = g.reshape(6, 5)
    np.testing.assert_allclose(g[:, :3], gx, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(g[:, 3:], np.einsum("sdq,sd->sq", E, gd), rtol=1e-12, atol=1e-12)
    assert U == pytest.approx(eq._energy(X, C, 0.25, k, ls, eq._NS, eq._SG, eq._CAB, np.empty((12, 3))), rel=1e-13)
    np.testing.assert_allclose(H, H.T, atol=1e-9)  # the Hessian of an energy is symmetric
