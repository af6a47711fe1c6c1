"""Twins: a rule that the compiled kernel runs and its NumPy twin, pinned against each other on
random inputs (seeded). The actuator law, eq. 1-2 (physics/actuator.py): the scalar rule as the
kernel compiles it against `actuator.tensions`. The terrain query: `Terrain.height_and_normal`
against the kernel's `terrain_contact`, also exactly on cell edges, corners and diagonals."""

import numpy as np
import pytest

from tensegrity.physics import actuator, kernel
from tensegrity.physics import dynamics as d
from tensegrity.physics import topology as topo
from tensegrity.physics.kernel import contact as kc
from tensegrity.physics.kernel import stages as ks
from tensegrity.physics.params import IDX, NAMES, Params
from tensegrity.physics.schedule import MAX_PRESSURE, Schedule
from tensegrity.physics.terrain import Terrain

# The compiled rule may fuse a multiply-add where NumPy rounds twice: tensions agree to a few ulp
# of the largest term (K l or Kg P l, up to ~5e3 N, ulp ~1e-12 N).
ATOL, RTOL = 1e-11, 1e-14


def random_cables(rng, n, exponent=1.0):
    """n robots of 24 cables, every parameter drawn per robot: law parameters
    (len(actuator.NAMES), n, 1) in that order, lengths (n, 24) m from far below Lmin to taut, rates (n, 24) m/s and
    pair pressures (n, 12) MPa: a third 0, a third up to 3, a third high (up to MAX_PRESSURE)."""
    L = rng.uniform(0.2, 0.35, n)
    values = np.stack(
        [
            np.full(n, exponent) if np.isscalar(exponent) else exponent,
            rng.uniform(200.0, 3000.0, n),
            L,
            rng.uniform(0.0, 5.0, n),
            L * rng.uniform(0.3, 0.9, n),
            rng.uniform(100.0, 1000.0, n),
        ]
    )[..., None]
    ln = rng.uniform(0.02, 0.5, (n, 24))
    ldot = rng.normal(0.0, 0.5, (n, 24))
    third = rng.integers(0, 3, (n, 12))
    p = np.where(
        third == 0, 0.0, np.where(third == 1, rng.uniform(0.0, 3.0, (n, 12)), rng.uniform(3.0, MAX_PRESSURE, (n, 12)))
    )
    p[0] = MAX_PRESSURE
    return values, ln, ldot, p


def compiled(values, ln, ldot, p, linear=None):
    """The kernel's compiled rule, cable by cable: the constants by `ks.law_constants` from a
    packed parameter row, the muscle by `ks.law_activation`, the tension by `ks.cable_tension`
    (its fast path where the constants say linear, unless `linear` is given)."""
    prm = np.ascontiguousarray(values[..., 0].T)  # (n, 6): robot b's law from column 0
    C, out = np.zeros((len(actuator.ROWS), 1)), np.empty(ln.shape)
    for b in range(ln.shape[0]):
        lin = ks.law_constants(prm, b, 0, C, 0, 0)
        for j in range(24):
            act = ks.law_activation(prm, b, 0, p[b, topo.CABLE_PAIR[j]])
            out[b, j] = ks.cable_tension(ln[b, j], ldot[b, j], act, lin if linear is None else linear, C, 0, 0)
    return out


def twin(values, ln, ldot, p):
    """The NumPy twin of `compiled`."""
    act = actuator.activations(values[actuator.NAMES.index("muscle_gain")], p)
    return actuator.tensions(ln, ldot, act, actuator.constants(values))


@pytest.mark.parametrize("exponent", [1.0, 1.3, "random"])
def test_compiled_cable_law_equals_its_numpy_twin(exponent):
    rng = np.random.default_rng(7)
    n = 100
    values, ln, ldot, p = random_cables(rng, n, rng.uniform(0.5, 2.0, n) if exponent == "random" else exponent)
    f, f_np = compiled(values, ln, ldot, p), twin(values, ln, ldot, p)
    np.testing.assert_allclose(f, f_np, rtol=RTOL, atol=ATOL)
    # the draws reach every branch: slack, muscle off below Lmin, pressure 0 and high
    Lmin = values[actuator.NAMES.index("muscle_min_length")]
    act = actuator.activations(values[actuator.NAMES.index("muscle_gain")], p)
    assert 0.2 < np.mean(f_np == 0.0) < 0.8
    assert np.any((ln < Lmin) & (act > 0)) and np.any((act == 0) & (f_np > 0))
    assert p.max() == MAX_PRESSURE and np.mean(p > 3.0) > 0.2
    # the clamp: a slack cable pulls with exactly 0.0 (not -0.0) in both; never negative
    assert np.all(f[f_np == 0.0] == 0.0) and not np.signbit(f).any() and not np.signbit(f_np).any()
    # below Lmin the muscle adds nothing: the same tension at zero pressure
    below = ln <= Lmin
    np.testing.assert_array_equal(f_np[below], twin(values, ln, ldot, 0.0 * p)[below])
    np.testing.assert_array_equal(f[below], compiled(values, ln, ldot, 0.0 * p)[below])


def test_compiled_general_path_equals_the_fast_path_at_exponent_one():
    """A robot with a = 1 in a group with another a runs the power path: the same tensions."""
    values, ln, ldot, p = random_cables(np.random.default_rng(8), 20)
    np.testing.assert_allclose(
        compiled(values, ln, ldot, p, linear=False), compiled(values, ln, ldot, p), rtol=RTOL, atol=ATOL
    )


def test_nan_passes_both_twins():
    values, ln, ldot, p = random_cables(np.random.default_rng(9), 2)
    ln[0, 3] = ldot[1, 5] = np.nan
    for f in (compiled(values, ln, ldot, p), twin(values, ln, ldot, p)):
        assert np.isnan(f[0, 3]) and np.isnan(f[1, 5]) and np.isfinite(f).sum() == 2 * 24 - 2


@pytest.mark.parametrize("exponent", [1.0, 1.3])
def test_kernel_cable_stage_equals_the_numpy_law(exponent):
    """kernel.tensions (the compiled cable stage, parameters packed from Params) on random node
    positions and velocities, against the NumPy law at the lengths and rates computed here."""
    rng = np.random.default_rng(10)
    B = 12
    params = Params(
        cable_exponent=exponent,
        cable_stiffness=rng.uniform(500, 2000, B),
        muscle_gain=rng.uniform(200, 900, B),
        cable_damping=rng.uniform(0, 5, B),
    )
    P = topo.reference_nodes(params.strut_length) * rng.uniform(0.6, 1.4, (B, 1, 1))
    P = P + rng.normal(0, 0.02, P.shape)
    U = rng.normal(0, 0.3, P.shape)
    pres = rng.choice([0.0, 0.5, 2.0, MAX_PRESSURE], (B, 12))
    prm = params.pack(B)
    T = kernel.tensions(P, U, prm, topo.cable_levels(pres))[0]
    e = P[:, topo.CABLES[:, 1]] - P[:, topo.CABLES[:, 0]]
    ln = np.linalg.norm(e, axis=-1)
    ldot = np.sum(e * (U[:, topo.CABLES[:, 1]] - U[:, topo.CABLES[:, 0]]), -1) / ln
    c = IDX[actuator.NAMES[0]]
    values = prm[:, c : c + len(actuator.NAMES)].T[..., None]
    # lengths and rates are computed differently (one reciprocal there): a looser tolerance
    np.testing.assert_allclose(T, twin(values, ln, ldot, pres), rtol=1e-12, atol=1e-10)
    assert 0 < np.mean(T == 0.0) < 0.9


def test_the_actuator_packs_its_fields_side_by_side():
    c = IDX[actuator.NAMES[0]]
    assert NAMES[c : c + len(actuator.NAMES)] == actuator.NAMES
    values = np.array([[1.0, 1.3], [1000.0, 800.0], [0.28, 0.3], [2.0, 0.0], [0.2, 0.1], [589.0, 300.0]])
    C = np.zeros((len(actuator.ROWS), 2))
    prm = np.ascontiguousarray(values.T)
    assert [ks.law_constants(prm, b, 0, C, 0, b) for b in range(2)] == [True, False]
    np.testing.assert_allclose(C, actuator.constants(values), rtol=1e-15, atol=0)


def test_spring_is_the_law_at_rest_above_lmin():
    """(S1), what statics and dynamics.energy use: k max(0, l - l*) = eq. 1-2 at a = 1, dl/dt = 0
    and l > Lmin."""
    values, ln, _, p = random_cables(np.random.default_rng(11), 50)
    K, L, Lmin, Kg = (
        values[actuator.NAMES.index(k)]
        for k in ("cable_stiffness", "cable_rest_length", "muscle_min_length", "muscle_gain")
    )
    act = actuator.activations(Kg, p)
    k, lstar = actuator.spring(K, L, Lmin, act)
    above = ln > Lmin
    f = twin(values, ln, 0.0 * ln, p)
    np.testing.assert_allclose((k * np.maximum(0.0, ln - lstar))[above], f[above], rtol=1e-12, atol=1e-10)
    # l* is the mean of L and Lmin weighted by K and Kg P (to round-off)
    assert np.all(lstar >= np.minimum(L, Lmin) * (1 - 1e-15))
    assert np.all(lstar <= np.maximum(L, Lmin) * (1 + 1e-15))


# --------------------------------------------------------------- the terrain query
# Terrain.height_and_normal (NumPy) against kernel/contact.py terrain_contact (compiled), which
# returns the normal and the signed distance of p to the plane of the triangle under it.


def _fields():
    """Height fields: the spec's random field (0.25 m cells), a steep non-square field of 1/8 m
    cells, and one whose spacing and origin are not binary fractions."""
    rng = np.random.default_rng(12)
    return [
        Terrain.random(seed=3),
        Terrain(kind="heightfield", origin=(-0.75, 1.25), spacing=0.125, heights=rng.normal(0.0, 0.05, (9, 13))),
        Terrain(kind="heightfield", origin=(-1.1, 0.35), spacing=0.3, heights=rng.normal(0.0, 0.08, (12, 7))),
    ]


def field_points(rng, terrain, n=3000):
    """Points (x, y) m on a height field, by kind: drawn at random in the field, exactly on cell
    edges (either direction), on cell corners, on cell diagonals (s + t = 1), and off the field
    (on its far edge lines, or just outside)."""
    (x0, y0), h = terrain.origin, terrain.spacing
    nx, ny = terrain.heights.shape
    i, j = rng.integers(0, nx - 1, n), rng.integers(0, ny - 1, n)
    s = rng.integers(0, 1024, n) / 1024  # binary fractions: exact on a binary grid
    at = lambda u, v: (x0 + u * h, y0 + v * h)  # noqa: E731
    return {
        "random": at(rng.uniform(0, nx - 1, n), rng.uniform(0, ny - 1, n)),
        "edge": at(np.where(s < 0.5, i, i + s), np.where(s < 0.5, j + 2 * s, j)),
        "corner": at(i, j),
        "diagonal": at(i + s, j + 1 - s),
        "off": at(
            np.r_[np.full(n // 2, nx - 1.0), rng.uniform(-1.0, -1e-9, n // 2)], rng.uniform(0, ny - 1, 2 * (n // 2))
        ),
    }


def compiled_query(terrain, x, y, z):
    """kernel.contact.terrain_contact at the points (x, y, z) m: normals (n, 3), signed
    distances (n,) m, ok (n,)."""
    kind, meta, hz = terrain.packed()
    out = [kc.terrain_contact(a, b, c, kind, meta, hz) for a, b, c in zip(x, y, z)]
    return (np.array([o[:3] for o in out]), np.array([o[3] for o in out]), np.array([o[4] for o in out]))


@pytest.mark.parametrize("field", range(3))
def test_numpy_height_field_query_equals_the_kernels(field):
    terrain = _fields()[field]
    for kind, (x, y) in field_points(np.random.default_rng(13 + field), terrain).items():
        h, n = terrain.height_and_normal(x, y)
        nk, dist, ok = compiled_query(terrain, x, y, np.where(np.isfinite(h), h, 0.0))
        np.testing.assert_array_equal(ok, np.isfinite(h), err_msg=kind)
        assert np.all(np.isnan(n[~ok])), kind
        if kind == "off":
            assert not ok.any()
            continue
        # the NumPy height is on the kernel's triangle, and the normals are the same
        np.testing.assert_allclose(dist / nk[:, 2], 0.0, rtol=0, atol=1e-15, err_msg=kind)
        np.testing.assert_allclose(n, nk, rtol=0, atol=1e-12, err_msg=kind)
        np.testing.assert_array_equal(terrain.normal_at(x, y), n)
        np.testing.assert_array_equal(terrain.height(x, y), h)


def test_the_normal_is_the_triangles_on_both_sides_of_a_diagonal():
    """Just below a cell's diagonal and on it the lower triangle's normal (s + t <= 1), just
    above it the upper triangle's, each exact."""
    terrain = _fields()[1]
    (x0, y0), hs = terrain.origin, terrain.spacing
    z = terrain.heights
    low = np.array([-hs * (z[3, 4] - z[2, 4]), -hs * (z[2, 5] - z[2, 4]), hs * hs])
    up = np.array([hs * (z[2, 5] - z[3, 5]), hs * (z[3, 4] - z[3, 5]), hs * hs])
    x, y = x0 + hs * np.array([2.25, 2.25, 2.25]), y0 + hs * (4.75 + np.array([-1e-9, 0.0, 1e-9]))
    n = terrain.normal_at(x, y)
    np.testing.assert_allclose(n, [low / np.linalg.norm(low)] * 2 + [up / np.linalg.norm(up)], rtol=0, atol=1e-15)
    assert np.degrees(np.arccos(n[1] @ n[2])) > 1.0  # a real kink


@pytest.mark.parametrize(
    "terrain",
    [Terrain.flat(), Terrain.flat(0.2), Terrain.slope(12.0, 30.0), Terrain(normal=[0.1, -0.2, 1.0], offset=0.3)],
)
def test_numpy_plane_query_equals_the_kernels(terrain):
    rng = np.random.default_rng(14)
    x, y = rng.uniform(-3.0, 3.0, (2, 2000))
    x[:10], y[10:20] = 0.0, 0.0  # on the axes too
    h, n = terrain.height_and_normal(x, y)
    nk, dist, ok = compiled_query(terrain, x, y, h)
    assert ok.all()
    np.testing.assert_array_equal(n, nk)  # the plane's normal, both
    np.testing.assert_allclose(dist / nk[:, 2], 0.0, rtol=0, atol=1e-15)


def test_no_terrain_is_no_ground_in_both():
    """Terrain.none(): NumPy has no ground under any point (height -inf, normal up) and the
    kernel skips the contact stage: a robot falls freely through z = 0, its CoG with -g."""
    terrain = Terrain.none()
    x, y = np.random.default_rng(15).uniform(-5.0, 5.0, (2, 100))
    h, n = terrain.height_and_normal(x, y)
    assert np.all(h == -np.inf) and np.all(n == [0.0, 0.0, 1.0])
    assert terrain.packed()[0] == kernel.NO_TERRAIN
    params = Params()
    s = d.stand_on(params, 8, terrain)
    T = 0.5
    s1, _ = d.simulate(params, s, Schedule.constant(np.zeros(12), T), terrain)
    assert d.nodes(s1.x, s1.q, params.strut_length)[..., 2].max() < 0.0  # all of it under z = 0
    np.testing.assert_allclose(s1.v[..., 2].mean(), -params.gravity * T, rtol=1e-9)
