"""Physics of the simulator (docs/design.md §3), tested as physics."""

from dataclasses import replace

import numpy as np
import pytest

from tensegrity.physics import dynamics as d
from tensegrity.physics import kernel, statics
from tensegrity.physics import symmetry as sym
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.physics.schedule import Schedule
from tensegrity.physics.terrain import Terrain

EQUI = topo.face_number(topo.CONTACT_FACES["equilateral"])  # (9,10,12)

DT = 1e-4


def strut_loads(params, state, pressure):
    """Net cable force (B, 6, 3) and torque about the centre (B, 6, 3) on each strut."""
    T = d.tensions(params, state, pressure)
    P = d.nodes(state.x, state.q, params.strut_length)
    e = P[:, topo.CABLES[:, 1]] - P[:, topo.CABLES[:, 0]]
    e /= np.linalg.norm(e, axis=-1, keepdims=True)
    F = np.zeros_like(P)
    np.add.at(F, (slice(None), topo.CABLES[:, 0]), T[..., None] * e)
    np.add.at(F, (slice(None), topo.CABLES[:, 1]), -T[..., None] * e)
    a, b = topo.STRUTS[:, 0], topo.STRUTS[:, 1]
    force = F[:, a] + F[:, b]
    torque = np.cross(P[:, a] - state.x, F[:, a]) + np.cross(P[:, b] - state.x, F[:, b])
    return force, torque


def test_symmetric_structure_is_in_equilibrium_and_stays(free):
    s = d.stand_on(free, EQUI, Terrain.none())
    T = d.tensions(free, s, np.zeros(12))
    np.testing.assert_allclose(T, free.cable_pretension, rtol=1e-12)
    force, torque = strut_loads(free, s, np.zeros(12))
    assert np.abs(force).max() < 1e-12 * free.cable_pretension * 24
    assert np.abs(torque).max() < 1e-12 * free.cable_pretension * 24
    s1, tr = d.simulate(free, s, Schedule.constant(np.zeros(12), 1.0), Terrain.none(), DT)
    assert np.abs(tr.x - s.x[:, None]).max() < 1e-9  # metres, after 1 s


def test_slack_cable_carries_exactly_zero_tension(free):
    loose = free.replace(cable_rest_length=0.32)  # longer than every cable (0.306 m)
    s = d.stand_on(loose, EQUI, Terrain.none())
    assert np.all(d.tensions(loose, s, np.zeros(12)) == 0.0)
    # a muscle (eq. 1) pulls, but below l* = (K L + Kg P Lmin) / (K + Kg P) the sum is negative
    assert np.all(d.tensions(loose, s, np.full(12, 0.1)) == 0.0)
    assert np.all(d.tensions(loose, s, np.full(12, 0.5)) > 0.0)
    # taut cables shortening so fast that the damping term B dl/dt outweighs K (l - L)
    P = topo.reference_nodes(free.strut_length)[None]
    rate = 2 * free.cable_pretension / (free.cable_damping * 0.306)  # 1/s, twice what cancels T0
    prm, pres = free.pack(1), np.zeros((1, 24))
    T, F = kernel.tensions(P, -rate * P, prm, pres)  # every node moving inward
    assert np.all(T == 0.0) and np.all(F == 0.0)
    T, F = kernel.tensions(P, rate * P, prm, pres)
    assert np.all(T > free.cable_pretension)


def test_energy_and_momentum_conserved_without_damping_gravity_or_ground():
    """Semi-implicit (symplectic) Euler: energy error bounded and O(dt); at dt = 1e-4 s the
    measured relative error is 1.3e-3 over 5 s, so the bound is 3e-3 and it must halve with dt."""
    params = Params(gravity=0.0, cable_damping=0.0)
    s = d.stand_on(params, EQUI, Terrain.none())
    rng = np.random.default_rng(1)
    s = replace(s, v=rng.normal(0, 0.05, s.v.shape), w=rng.normal(0, 0.5, s.w.shape))
    pres = np.zeros(12)
    pres[9] = 2.0
    errs = []
    for dt in (DT, DT / 2):
        e0 = d.energy(params, s, pres)[0]
        m = params.strut_mass
        p0 = m * s.v.sum(1)[0]
        It, Ia = m * (params.strut_length**2 / 12 + params.strut_radius**2 / 4), m * params.strut_radius**2 / 2

        def ang(st, It=It, Ia=Ia, m=m):
            spin = np.einsum("bsij,bsj->bi", d.axes(st.q), st.w * [It, It, Ia])
            return (np.cross(st.x, m * st.v).sum(1) + spin)[0]

        l0 = ang(s)
        cur, err = s, 0.0
        for _ in range(50):
            cur, _ = d.simulate(params, cur, Schedule.constant(pres, 0.1), Terrain.none(), dt, 100)
            err = max(err, abs(d.energy(params, cur, pres)[0] - e0) / e0)
            np.testing.assert_allclose(m * cur.v.sum(1)[0], p0, atol=1e-12)  # N s
            np.testing.assert_allclose(ang(cur), l0, atol=1e-3 * np.abs(l0).max())
        errs.append(err)
    assert errs[0] < 3e-3
    assert 0.35 < errs[1] / errs[0] < 0.65  # first order in dt, as symplectic Euler must be


def test_free_fall_matches_g():
    params = Params()
    s = d.stand_on(params, EQUI, Terrain.none())
    s = replace(s, x=s.x + [0, 0, 5.0])
    _, tr = d.simulate(params, s, Schedule.constant(np.zeros(12), 0.5), Terrain.none(), DT, 1)
    z = tr.cog()[0, :, 2]
    acc = np.diff(z, 2) / DT**2
    np.testing.assert_allclose(acc, -params.gravity, rtol=1e-6)
    np.testing.assert_allclose(z[-1] - z[0], -0.5 * params.gravity * (tr.t[-1] ** 2 - tr.t[0] ** 2), rtol=1e-3)


@pytest.mark.parametrize("slope", [0.0, 10.0])
def test_standing_robot_does_not_creep(slope):
    """No creep: over 10 s the feet do not slide and the mean CoG does not drift along the
    ground (1 mm). The body itself keeps breathing vertically by a few mm at about 1 Hz: the
    soft mechanism mode, loaded by gravity from the symmetric start and barely damped by the
    cables (docs/design.md §3), so positions are compared as 1 s means."""
    params = Params()
    terrain = Terrain.slope(slope, azimuth_deg=30.0) if slope else Terrain.flat()
    s = d.stand_on(params, EQUI, terrain)
    _, tr = d.simulate(params, s, Schedule.constant(np.zeros(12), 11.0), terrain, DT, 100)
    P = tr.nodes(params.strut_length)[0]
    feet = topo.FACES[EQUI - 1]
    n = terrain.normal
    along = lambda v: v - (v @ n)[..., None] * n  # component along the ground
    first, last = (tr.t > 1) & (tr.t <= 2), tr.t > 10
    slide = np.linalg.norm(along(P[:, feet] - P[first][0, feet]), axis=-1)
    assert slide[tr.t > 1].max() < 1e-3  # m
    c = tr.cog()[0]
    assert np.linalg.norm(along(c[last].mean(0) - c[first].mean(0))) < 1e-3  # m
    h = terrain.height(P[-1, :, 0], P[-1, :, 1])
    assert np.array_equal(np.flatnonzero(P[-1, :, 2] - h < 1.5 * params.strut_radius), np.sort(feet))


def test_mean_cog_agrees_with_static_equilibrium(free, free_sweep):
    pairs, levels = [10, 4, 1], [1.2, 2.4]
    t, c, _ = free_sweep(free, EQUI, pairs, levels)
    for b, pair in enumerate(pairs):
        for k, p in enumerate(levels):
            sel = (t > k + 0.2) & (t <= k + 1)  # the level after its 0.2 s rise
            pres = np.zeros(12)
            pres[pair - 1] = p
            ref, _ = statics.support_cog(statics.equilibrium(free, pres), EQUI)
            assert np.linalg.norm(c[b, sel].mean(0) - ref) < 1e-4  # m


def test_three_fold_orbit_moves_the_cog_equally_120_degrees_apart(free, free_sweep):
    """Pairs of a 3-fold orbit on (9,10,12) move the CoG by equal amounts, and each in the
    same direction relative to the corner its rotation carries the reference vertex to, i.e.
    in directions 120 degrees apart around the triangle. (In the frame of the one deformed
    reference vertex the angles are not exactly 120 degrees: the triangle deforms.)"""
    orbits = ([9, 10, 12], [4, 6, 7])
    pairs = orbits[0] + orbits[1]
    t, c, tri = free_sweep(free, EQUI, pairs, [2.4], hold=1.0)
    sel = t > 0.2
    face = topo.FACES[EQUI - 1]
    stab = [s for s in sym.group() if s.faces[EQUI - 1] == EQUI - 1]
    for orbit in orbits:
        rel = []
        for pair in orbit:
            s = next(s for s in stab if s.pairs[orbit[0] - 1] == pair - 1)
            corner = list(face).index(s.nodes[face[0]])  # image of the reference vertex
            b = pairs.index(pair)
            cog, v = c[b, sel].mean(0)[:2], tri[b, sel].mean(0)[corner, :2]
            ang = np.arctan2(v[0], v[1])  # rotate the frame so that y points to that corner
            rot = np.array([[np.cos(ang), -np.sin(ang)], [np.sin(ang), np.cos(ang)]])
            rel.append(rot @ cog)
        rel = np.array(rel)
        assert np.linalg.norm(rel[0]) > 5e-3  # the orbit does move the CoG
        assert np.ptp(np.linalg.norm(rel, axis=1)) < 1e-4
        assert np.abs(rel - rel[0]).max() < 1e-4


def test_transformed_robot_simulates_to_the_transformed_motion(free):
    G = sym.group()
    p0 = d.nodes(
        *(a[0] for a in (d.stand_on(free, EQUI, Terrain.none()).x, d.stand_on(free, EQUI, Terrain.none()).q)),
        free.strut_length,
    )
    pres = np.zeros(12)
    pres[[9, 3]] = [2.0, 1.0]
    nodes0 = np.stack([np.empty((12, 3)) for _ in G])
    pres_b = np.zeros((len(G), 12))
    for k, s in enumerate(G):
        nodes0[k][s.nodes] = p0 @ s.matrix.T
        pres_b[k][s.pairs] = pres
    start = d.from_nodes(nodes0)
    _, tr = d.simulate(free, start, Schedule.constant(pres_b, 0.3), Terrain.none(), DT, 500)
    P = tr.nodes(free.strut_length)
    ident = next(k for k, s in enumerate(G) if np.allclose(s.matrix, np.eye(3)))
    for k, s in enumerate(G):
        expect = P[ident] @ s.matrix.T
        np.testing.assert_allclose(P[k][:, s.nodes], expect, atol=1e-9)
    assert np.abs(P[ident, -1] - P[ident, 0]).max() > 1e-3  # the robot did move


def test_halving_dt_moves_the_nominal_cog_less_than_0_05_mm(free, free_sweep):
    levels = [2.4]
    t1, c1, _ = free_sweep(free, EQUI, [10], levels, dt=DT)
    t2, c2, _ = free_sweep(free, EQUI, [10], levels, dt=DT / 2)
    assert np.linalg.norm(c1[0].mean(0) - c2[0].mean(0)) < 5e-5


def test_batch_equals_single_runs_with_different_parameters_and_actuation():
    params = Params(gravity=0.0, cable_stiffness=np.array([1000.0, 800.0]), strut_mass=np.array([0.2, 0.25]))
    s = d.stand_on(params, EQUI, Terrain.none(), batch=2)
    sched = Schedule.staircase([10, 4], [1.0, 2.0], 0.1)
    _, tr = d.simulate(params, s, sched, Terrain.none(), DT)
    for b in range(2):
        pb = Params(
            gravity=0.0, cable_stiffness=float(params.cable_stiffness[b]), strut_mass=float(params.strut_mass[b])
        )
        _, trb = d.simulate(pb, s.take([b]), Schedule(sched.durations, sched.pressure[[b]]), Terrain.none(), DT)
        assert np.array_equal(trb.x[0], tr.x[b])
    assert not np.allclose(tr.x[0], tr.x[1])


def test_same_input_same_output(free):
    s = d.stand_on(Params(), EQUI, Terrain.slope(10), batch=3)
    sched = Schedule.staircase([10, 11, 4], [2.0, 4.0], 0.2)
    a = d.simulate(Params(), s, sched, Terrain.slope(10))[1]
    b = d.simulate(Params(), s, sched, Terrain.slope(10))[1]
    assert np.array_equal(a.x, b.x) and np.array_equal(a.q, b.q)


def test_optional_strut_damping_does_not_move_the_equilibrium(free, free_sweep):
    """strut_damping (1/s, off by default; locomotion uses it to settle faster) damps strut
    motion but exerts no force at rest, so the nominal CoG stays where it is (statics)."""
    pres = np.zeros(12)
    pres[9] = 2.4
    ref, _ = statics.support_cog(statics.equilibrium(free, pres), EQUI)
    damped = free.replace(strut_damping=1.0)
    t, c, _ = free_sweep(damped, EQUI, [10], [2.4], hold=2.0)
    assert np.linalg.norm(c[0, t > 1.0].mean(0) - ref) < 2e-5  # m
    t0, c0, _ = free_sweep(free, EQUI, [10], [2.4], hold=2.0)
    assert c[0, t > 1.5].std(axis=0).max() < 0.5 * c0[0, t0 > 1.5].std(axis=0).max()  # it damps
