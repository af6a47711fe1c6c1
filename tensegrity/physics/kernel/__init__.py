"""The compiled time loop (numba): cable forces (eq. 1-2), ground contact (C1)-(C4), gravity and
strut dynamics (eq. 3-4) integrated by semi-implicit Euler (design.md section 3).

One call advances every robot of a batch by `n_rec * every` steps of dt, writing the strut
centres and quaternions after each block of `every` steps. The time loop never returns to
Python; it is the one driver of `kernel.driver`, shared with the twisted-string actuator
(`kernel.motors`), which differs in the cable stage alone. Robots run in groups of LANES side by
side, one per SIMD lane (`kernel.stages`: a step is `node_states`, `cable_forces`,
`ground_forces`, `integrate`), the groups in parallel threads; batches under WIDE_FROM robots run
one robot per thread instead, in the layout of `kernel.robot` (its struts, nodes and cables side
by side). The working arrays live on the stack (`compiling.stack_array`). A batch that is not a
multiple of LANES fills the last group with copies of its last robot, whose results are dropped.
Status per robot (`dynamics.simulate` reads the codes 0-3): OK, NON_FINITE, TOO_FAST (node speed
above max_speed), OFF_TERRAIN (no triangle under a node). A robot that fails keeps the state and
step count of its failure; its group stops when all of its robots have failed. A robot's results
do not depend on its group: the same bits alone, in any lane, with any number of threads
(tests/physics/test_kernel_lanes).
"""

from __future__ import annotations

import numba as nb
import numpy as np

from . import stages as ks
from .compiling import callees_first, jit
from .driver import (
    _1C,
    _1P,
    _1T,
    _1U,
    LANES,
    NO_TERRAIN,
    NON_FINITE,
    OFF_TERRAIN,
    OK,
    ONE_LANE,
    TOO_FAST,
    WIDE_FROM,
    _1act,
    check_levels,
    constants,
    group_one,
    group_wide,
)

__all__ = ["LANES", "NO_TERRAIN", "NON_FINITE", "OFF_TERRAIN", "OK", "TOO_FAST", "WIDE_FROM", "advance", "tensions"]


@jit(parallel=True, nogil=True, **ks.JIT)
def _advance(x, v, q, w, anchor, stuck, prm, pres, kind, meta, hz, n_rec, every, dt,
             out_x, out_q, status, fail_step):
    """`advance`: the groups in parallel threads."""
    B = x.shape[0]
    if B < WIDE_FROM:
        for b in nb.prange(B):
            group_one(b, x, v, q, w, anchor, stuck, prm, pres, kind, meta, hz, n_rec, every, dt,
                      out_x, out_q, status, fail_step, None)
    else:
        for g in nb.prange((B + LANES - 1) // LANES):
            group_wide(g, x, v, q, w, anchor, stuck, prm, pres, kind, meta, hz, n_rec, every, dt,
                       out_x, out_q, status, fail_step, None)


def advance(x, v, q, w, anchor, stuck, prm, pres, kind, meta, hz, n_rec, every, dt,
            out_x, out_q, status, fail_step):
    """Advance all robots in place (module docstring). State x, v (B, 6, 3) m, m/s; q (B, 6, 4);
    w (B, 6, 3) rad/s body; anchor (B, 12, 3) m, stuck (B, 12) bool; prm (B, NP); pres (B, 24)
    MPa, one per cable (`topology.cable_levels` of a pair's; `check_levels`); terrain kind
    (NO_TERRAIN, PLANE, HEIGHTFIELD), meta (7,), hz (nx, ny) m (Terrain.packed); dt s;
    out_x (B, n_rec, 6, 3) m, out_q (B, n_rec, 6, 4); status, fail_step (B,) int64.
    The first call loads the group functions before `_advance` (`compiling.callees_first`)."""
    check_levels(pres, x.shape[0])
    args = (x, v, q, w, anchor, stuck, prm, pres, kind, meta, hz, n_rec, every, dt, out_x, out_q,
            status, fail_step)
    if not _advance.overloads:
        callees_first(_advance, (group_one, group_wide), args + (None,))
    _advance(*args)


@jit(**ks.JIT)
def tensions(P, U, prm, pres):
    """Cable tensions (B, 24) N and node forces (B, 12, 3) N from node positions P and
    velocities U (B, 12, 3), packed parameters prm (B, NP) and cable pressures pres (B, 24) MPa."""
    if pres.shape[1] != 24:
        raise ValueError("pres must hold one pressure per cable, (B, 24)")
    nbat = P.shape[0]
    T, F = np.zeros((nbat, 24)), np.zeros((nbat, 12, 3))
    Pl, Ul, Tl, C, act = _1P(), _1U(), _1T(), _1C(), _1act()
    for b in range(nbat):
        for n in range(12):
            for k in range(3):
                Pl[n, k, 0], Ul[n, k, 0] = P[b, n, k], U[b, n, k]
        linear = constants(prm, b, 1.0, C, act, pres, 0)
        ks.cable_forces(Pl, Ul, C, act, linear, Tl, ONE_LANE)
        for j in range(24):
            T[b, j] = Tl[j, 0, 0]
        for n in range(12):
            for k in range(3):
                F[b, n, k] = ks.cable_sum(Tl, n, k, 0)
    return T, F
