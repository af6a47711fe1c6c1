"""The kernel runs robots side by side in SIMD lanes (kernel.LANES per group; one per group for
small batches): a robot's trajectory must not depend on its neighbours, its place in the batch,
the batch size or the number of threads, also when a neighbour fails."""

from dataclasses import replace

import numba
import numpy as np
import pytest

from tensegrity.physics import dynamics as d
from tensegrity.physics import kernel
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.physics.terrain import Terrain

EQUI = (9, 10, 12)
PER_ROBOT = ("friction", "cable_stiffness", "cable_rest_length")


def run(params, state, pres, terrain, n_rec, every=10, dt=1e-4):
    """kernel.advance on a copy of the state: final state, records, status and fail step."""
    B = state.batch
    kind, meta, hz = terrain.packed()
    s = state.copy()
    status, fail = np.zeros(B, np.int64), np.zeros(B, np.int64)
    out_x, out_q = np.full((B, n_rec, 6, 3), np.nan), np.full((B, n_rec, 6, 4), np.nan)
    kernel.advance(
        s.x,
        s.v,
        s.q,
        s.w,
        s.anchor,
        s.stuck,
        params.pack(B),
        np.ascontiguousarray(topo.cable_levels(pres)),
        kind,
        meta,
        hz,
        n_rec,
        every,
        dt,
        out_x,
        out_q,
        status,
        fail,
    )
    return dict(
        x=s.x, v=s.v, q=s.q, w=s.w, anchor=s.anchor, stuck=s.stuck, out_x=out_x, out_q=out_q, status=status, fail=fail
    )


def robots(B, terrain, position=(0.3, -0.2), seed=1):
    """B different robots (parameters, kicks, pressures) standing on the terrain."""
    rng = np.random.default_rng(seed)
    params = Params(friction=np.linspace(0.5, 1.0, B), cable_stiffness=np.linspace(900, 1300, B))
    s = d.stand_on(params, EQUI, terrain, batch=B, position=position)
    s = replace(s, v=s.v + rng.normal(0, 0.3, (B, 1, 3)))
    return params, s, rng.uniform(0, 2.5, (B, 12))


def robot(params, b):
    return replace(params, **{k: np.asarray(getattr(params, k))[[b]] for k in PER_ROBOT})


def assert_same(a, b, idx):
    for k in a:
        np.testing.assert_array_equal(a[k], b[k][idx], err_msg=k)


@pytest.mark.parametrize("terrain", [Terrain.random(seed=3), Terrain.slope(10.0)], ids=["heightfield", "slope"])
def test_a_robot_in_a_batch_equals_the_robot_alone(terrain):
    B = kernel.LANES + 3  # the last group is padded
    params, s, pres = robots(B, terrain)
    together = run(params, s, pres, terrain, 100)
    assert not together["status"].any()
    for b in (0, kernel.LANES - 1, B - 1):
        alone = run(robot(params, b), s.take([b]), pres[[b]], terrain, 100)
        assert_same(alone, together, [b])


def test_robots_do_not_depend_on_their_place_in_the_batch():
    terrain = Terrain.flat()
    B = 2 * kernel.LANES + 1
    params, s, pres = robots(B, terrain, position=(0.0, 0.0))
    perm = np.random.default_rng(5).permutation(B)
    base = run(params, s, pres, terrain, 50)
    shuffled = replace(params, **{k: np.asarray(getattr(params, k))[perm] for k in PER_ROBOT})
    assert_same(run(shuffled, s.take(perm), pres[perm], terrain, 50), base, perm)


def test_a_failing_robot_stops_alone_with_its_own_status():
    """In a 1 m field: robot 1 blows up (TOO_FAST or NON_FINITE), robot 2 is thrown off the
    edge (OFF_TERRAIN); the others run on, as they would alone."""
    terrain = Terrain.random(seed=1, size=1.0)
    B = kernel.LANES + 1
    params = Params(cable_stiffness=np.where(np.arange(B) == 1, 1e8, 1000.0))
    s = d.stand_on(params, EQUI, terrain, batch=B, position=(0.2, 0.0))
    v = s.v.copy()
    v[2] += [5.0, 0.0, 0.0]
    s = replace(s, v=v)
    pres = np.zeros((B, 12))
    pres[:, 9] = 2.0
    together = run(params, s, pres, terrain, 40, dt=5e-4)
    assert together["status"][1] in (kernel.TOO_FAST, kernel.NON_FINITE)
    assert together["status"][2] == kernel.OFF_TERRAIN
    assert together["fail"][1] < together["fail"][2] < 400
    for b in range(B):
        one = replace(
            params, cable_stiffness=params.cable_stiffness[[b]], cable_rest_length=params.cable_rest_length[[b]]
        )
        assert_same(run(one, s.take([b]), pres[[b]], terrain, 40, dt=5e-4), together, [b])


def test_same_bytes_whatever_the_number_of_threads():
    terrain = Terrain.random(seed=3)
    params, s, pres = robots(3 * kernel.LANES - 2, terrain)
    threads = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        one = run(params, s, pres, terrain, 50)
    finally:
        numba.set_num_threads(threads)
    many = run(params, s, pres, terrain, 50)
    for k in one:
        assert one[k].tobytes() == many[k].tobytes(), k
