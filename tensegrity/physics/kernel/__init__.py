"""The compiled time loop (numba): cable forces (eq. 1-2), ground contact (C1)-(C4), gravity and
strut dynamics (eq. 3-4) integrated by semi-implicit Euler (design.md section 3).

One call advances every robot of a batch by `n_rec * every` steps of dt, writing the strut
centres and quaternions after each block of `every` steps. The time loop never returns to
Python. Robots run in groups of LANES side by side, one per SIMD lane (`kernel.stages`: a step
is `node_states`, `cable_forces`, `ground_forces`, `integrate`), the groups in parallel threads;
batches under WIDE_FROM robots run one robot per thread instead, in the layout of `kernel.robot`
(its struts, nodes and cables side by side). The working arrays live on the stack
(`compiling.stack_array`). A batch that is not a multiple of LANES fills the last group with
copies of its last robot, whose results are dropped. Status per robot (`dynamics.simulate`
reads the codes 0-3): OK, NON_FINITE, TOO_FAST (node speed above max_speed), OFF_TERRAIN (no
triangle under a node). A robot that fails keeps the state and step count of its failure; its
group stops when all of its robots have failed. A robot's results do not depend on its group:
the same bits alone, in any lane, with any number of threads (tests/physics/test_kernel_lanes).
"""
from __future__ import annotations

import numba as nb
import numpy as np

from .. import actuator
from .. import topology as topo
from ..params import IDX
from . import contact as kc
from . import robot as kr
from . import stages as ks
from .compiling import callees_first, jit, stack_array

OK, NON_FINITE, TOO_FAST, OFF_TERRAIN = 0, 1, 2, 3  # status codes (values fixed: see dynamics)
NO_TERRAIN = kc.NO_TERRAIN
LANES = 8  # robots per group: one AVX-512 register of float64
WIDE_FROM = 3  # smaller batches run one robot per group (and per thread): faster for 1 or 2
CABLE_PAIR = np.ascontiguousarray(topo.CABLE_PAIR.astype(np.int64))

# Columns of the packed parameter array prm (B, NP) (params.NAMES); the actuator's from _LAW on.
_STRUT_LENGTH, _STRUT_RADIUS, _STRUT_MASS, _LAW, _GRAVITY = (IDX[k] for k in (
    "strut_length", "strut_radius", "strut_mass", actuator.NAMES[0], "gravity"))
(_GROUND_STIFFNESS, _GROUND_DAMPING, _FRICTION, _FRICTION_STIFFNESS, _FRICTION_DAMPING,
 _STRUT_DAMPING, _MAX_SPEED) = (IDX[k] for k in (
    "ground_stiffness", "ground_damping", "friction", "friction_stiffness", "friction_damping",
    "strut_damping", "max_speed"))


# The working arrays of a group of L lanes (shapes before the lane axis): state X, V, W, Q;
# anchors AN, stuck flags ST; nodes P, U, contact forces G; rotations Rm; cables T; constants
# C; muscles act; per lane (fastest squared speed, on terrain, alive).
_SHAPES = ((6, 3), (6, 3), (6, 3), (6, 4), (12, 3), (12,), (12, 3), (12, 3), (12, 3), (6, 3, 3),
           (24, 4), (ks.NC,), (24,), (3,))
_W = [stack_array(*s, LANES) for s in _SHAPES]
_1 = [stack_array(*s, 1) for s in _SHAPES]
_WIDE, _ONE = (0,) * LANES, (0,)  # lane markers (kernel.stages)
(_wX, _wV, _wW, _wQ, _wAN, _wST, _wP, _wU, _wG, _wRm, _wT, _wC, _wact, _wlane) = _W
(_1X, _1V, _1W, _1Q, _1AN, _1ST, _1P, _1U, _1G, _1Rm, _1T, _1C, _1act, _1lane) = _1
(_rX, _rV, _rW, _rQ, _rRm, _rP, _rU, _rG, _rAN, _rST, _ron, _rE, _rTF, _rTN, _rFN, _rC, _ract,
 _rfast) = [stack_array(*s) for s in kr.SHAPES]  # one robot alone (kernel.robot)


@jit(**ks.INLINE)
def _constants(prm, b, dt, C, act, pres, l):
    """Lane l of C (NC, L) and the muscles act (24, L) N/m (eq. 1) for robot b (kernel.stages
    names the rows; the actuator's by `actuator.pack` and `activation`). Returns True if its
    cable law is linear (`actuator.pack`)."""
    S, r, m = prm[b, _STRUT_LENGTH], prm[b, _STRUT_RADIUS], prm[b, _STRUT_MASS]
    It, Ia = m * (S * S / 12.0 + r * r / 4.0), m * r * r / 2.0  # thin tube inertia, kg m^2
    C[ks.HL, l] = 0.5 * S
    linear = ks.law_constants(prm, b, _LAW, C, ks.LAW, l)
    C[ks.R, l], C[ks.KN, l], C[ks.CN, l] = r, prm[b, _GROUND_STIFFNESS], prm[b, _GROUND_DAMPING]
    C[ks.MU, l], C[ks.KT, l], C[ks.CT, l] = (prm[b, _FRICTION], prm[b, _FRICTION_STIFFNESS],
                                             prm[b, _FRICTION_DAMPING])
    C[ks.DT_M, l], C[ks.DT_I, l], C[ks.GYRO, l] = dt / m, dt / It, (Ia - It) / It
    C[ks.DS, l], C[ks.GRAV, l] = prm[b, _STRUT_DAMPING], prm[b, _GRAVITY]
    C[ks.VMAX2, l] = prm[b, _MAX_SPEED] ** 2
    for j in range(24):
        act[j, l] = ks.law_activation(prm, b, _LAW, pres[b, CABLE_PAIR[j]])
    return linear


@jit(**ks.JIT)  # not inlined: rare, and it would crowd the step loop
def _retire(g, l, code, step, x, v, q, w, anchor, stuck, status, fail_step, X, V, Q, W, AN, ST,
            lane):
    """Writes the state of lane l of group g (robot g*L + l) back, with its status `code` and
    its number of completed steps; the lane is then no longer alive."""
    b = g * X.shape[-1] + l
    for i in range(6):
        for k in range(3):
            x[b, i, k], v[b, i, k], w[b, i, k] = X[i, k, l], V[i, k, l], W[i, k, l]
        for k in range(4):
            q[b, i, k] = Q[i, k, l]
    for n in range(12):
        for k in range(3):
            anchor[b, n, k] = AN[n, k, l]
        stuck[b, n] = ST[n, l] != 0.0
    status[b], fail_step[b] = code, step
    lane[2, l] = 0.0


@jit(**ks.INLINE)
def _record(g, rec, X, Q, lane, out_x, out_q, lanes, normalise=True):
    """Renormalises the quaternions Q (6, 4, L) (`ks.normalise`; unless told not to) and writes
    X (6, 3, L) m, Q of the live lanes to out_x, out_q[b, rec]."""
    L = len(lanes)
    if normalise:
        for i in range(6):
            for l in range(L):
                ks.normalise(Q, i, l)
    for l in range(L):
        if lane[2, l] != 0.0:
            for i in range(6):
                for k in range(4):
                    out_q[g * L + l, rec, i, k] = Q[i, k, l]
                for k in range(3):
                    out_x[g * L + l, rec, i, k] = X[i, k, l]


@jit(**ks.INLINE)
def _load(g, x, v, q, w, anchor, stuck, prm, pres, dt, work, lanes):
    """Loads the robots of group g into the lanes of `work` (`_run`). Returns whether all
    their cable laws are linear and the number of live lanes."""
    X, V, W, Q, AN, ST, P, U, G, Rm, T, C, act, lane = work
    L, B = len(lanes), x.shape[0]
    linear, n_alive = True, 0
    for l in range(L):
        b = min(g * L + l, B - 1)  # lanes past the batch copy its last robot
        linear &= _constants(prm, b, dt, C, act, pres, l)
        for i in range(6):
            for k in range(3):
                X[i, k, l], V[i, k, l], W[i, k, l] = x[b, i, k], v[b, i, k], w[b, i, k]
            for k in range(4):
                Q[i, k, l] = q[b, i, k]
        for n in range(12):
            for k in range(3):
                AN[n, k, l], G[n, k, l] = anchor[b, n, k], 0.0  # no terrain: G stays 0
            ST[n, l] = 1.0 if stuck[b, n] else 0.0
        lane[2, l] = 1.0 if g * L + l < B else 0.0
        n_alive += 1 if g * L + l < B else 0
    return linear, n_alive


@jit(**ks.INLINE)
def _run(g, x, v, q, w, anchor, stuck, prm, pres, kind, meta, hz, n_rec, every, dt, out_x, out_q,
         status, fail_step, work, lanes):
    """Group g of `advance` (same arguments, then the tuple of working arrays of _SHAPES): loads
    its robots into the lanes, steps them, records after every block, retires a lane at its
    failure and writes the live ones back at the end."""
    X, V, W, Q, AN, ST, P, U, G, Rm, T, C, act, lane = work
    L = len(lanes)
    linear, n_alive = _load(g, x, v, q, w, anchor, stuck, prm, pres, dt, work, lanes)
    step = 0
    for rec in range(n_rec):
        for _ in range(every):
            ks.node_states(X, V, Q, W, C, Rm, P, U, lanes)
            ks.cable_forces(P, U, C, act, linear, T, lanes)
            if kind != NO_TERRAIN:
                for l in range(L):
                    lane[1, l] = 1.0
                kc.ground_forces(P, U, G, AN, ST, C, lane[1], kind, meta, hz, lanes)
                off = False
                for l in range(L):
                    off |= (lane[1, l] == 0.0) & (lane[2, l] != 0.0)
                if off:  # before the step: the robot keeps its state
                    for l in range(L):
                        if lane[1, l] == 0.0 and lane[2, l] != 0.0:
                            _retire(g, l, OFF_TERRAIN, step, x, v, q, w, anchor, stuck, status,
                                    fail_step, X, V, Q, W, AN, ST, lane)
                            n_alive -= 1
            ks.integrate(X, V, Q, W, T, G, Rm, C, dt, lane[0], lanes)
            step += 1
            bad = False
            for l in range(L):
                bad |= (lane[2, l] != 0.0) & (not lane[0, l] <= C[ks.VMAX2, l])
            if bad:
                for l in range(L):
                    if lane[2, l] != 0.0 and not lane[0, l] <= C[ks.VMAX2, l]:
                        _retire(g, l, NON_FINITE if lane[0, l] != lane[0, l] else TOO_FAST, step,
                                x, v, q, w, anchor, stuck, status, fail_step, X, V, Q, W, AN, ST,
                                lane)
                        n_alive -= 1
            if n_alive == 0:
                break
        if n_alive == 0:
            break
        _record(g, rec, X, Q, lane, out_x, out_q, lanes)
    for l in range(L):
        if lane[2, l] != 0.0:
            _retire(g, l, OK, step, x, v, q, w, anchor, stuck, status, fail_step, X, V, Q, W, AN,
                    ST, lane)


@jit(**ks.JIT)
def _group_wide(g, x, v, q, w, anchor, stuck, prm, pres, kind, meta, hz, n_rec, every, dt, out_x,
                out_q, status, fail_step):
    """`_run` for robots g*LANES ... g*LANES + LANES - 1."""
    _run(g, x, v, q, w, anchor, stuck, prm, pres, kind, meta, hz, n_rec, every, dt, out_x, out_q,
         status, fail_step, (_wX(), _wV(), _wW(), _wQ(), _wAN(), _wST(), _wP(), _wU(), _wG(),
                             _wRm(), _wT(), _wC(), _wact(), _wlane()), _WIDE)


@jit(**ks.JIT)
def _group_one(b, x, v, q, w, anchor, stuck, prm, pres, kind, meta, hz, n_rec, every, dt, out_x,
               out_q, status, fail_step):
    """`_run` for robot b alone, stepped in the layout of `kernel.robot` (the group layout of
    one lane loads, records and retires it)."""
    work = (_1X(), _1V(), _1W(), _1Q(), _1AN(), _1ST(), _1P(), _1U(), _1G(), _1Rm(), _1T(),
            _1C(), _1act(), _1lane())
    X, V, W, Q, AN, ST, P, U, G, Rm, T, C, act, lane = work
    S = (_rX(), _rV(), _rW(), _rQ(), _rRm(), _rP(), _rU(), _rG(), _rAN(), _rST(), _ron(), _rE(),
         _rTF(), _rTN(), _rFN(), _rC(), _ract(), _rfast())
    linear = _load(b, x, v, q, w, anchor, stuck, prm, pres, dt, work, _ONE)[0]
    kr.load(S, X, V, W, Q, AN, ST, C, act)
    step, code = 0, OK
    for rec in range(n_rec):
        for _ in range(every):
            fastest = kr.step(S, linear, kind, meta, hz, dt)
            if fastest < 0.0:  # before the step: the robot keeps its state
                code = OFF_TERRAIN
                break
            step += 1
            if not fastest <= C[ks.VMAX2, 0]:
                code = NON_FINITE if fastest != fastest else TOO_FAST
                break
        if code != OK:
            break
        for i in range(6):  # by struts side by side: the same bits as in a group
            ks.normalise(S[3], 0, i)
        kr.store(S, X, V, W, Q, AN, ST)
        _record(b, rec, X, Q, lane, out_x, out_q, _ONE, False)
    kr.store(S, X, V, W, Q, AN, ST)
    _retire(b, 0, code, step, x, v, q, w, anchor, stuck, status, fail_step, X, V, Q, W, AN, ST,
            lane)


@jit(parallel=True, nogil=True, **ks.JIT)
def _advance(x, v, q, w, anchor, stuck, prm, pres, kind, meta, hz, n_rec, every, dt,
             out_x, out_q, status, fail_step):
    """`advance`: the groups in parallel threads."""
    B = x.shape[0]
    if B < WIDE_FROM:
        for b in nb.prange(B):
            _group_one(b, x, v, q, w, anchor, stuck, prm, pres, kind, meta, hz, n_rec, every, dt,
                       out_x, out_q, status, fail_step)
    else:
        for g in nb.prange((B + LANES - 1) // LANES):
            _group_wide(g, x, v, q, w, anchor, stuck, prm, pres, kind, meta, hz, n_rec, every, dt,
                        out_x, out_q, status, fail_step)


def advance(x, v, q, w, anchor, stuck, prm, pres, kind, meta, hz, n_rec, every, dt,
            out_x, out_q, status, fail_step):
    """Advance all robots in place (module docstring). State x, v (B, 6, 3) m, m/s; q (B, 6, 4);
    w (B, 6, 3) rad/s body; anchor (B, 12, 3) m, stuck (B, 12) bool; prm (B, NP); pres (B, 12)
    MPa; terrain kind (NO_TERRAIN, PLANE, HEIGHTFIELD), meta (7,), hz (nx, ny) m (Terrain.packed);
    dt s; out_x (B, n_rec, 6, 3) m, out_q (B, n_rec, 6, 4); status, fail_step (B,) int64.
    The first call loads the group functions before `_advance` (`compiling.callees_first`)."""
    args = (x, v, q, w, anchor, stuck, prm, pres, kind, meta, hz, n_rec, every, dt, out_x, out_q,
            status, fail_step)
    if not _advance.overloads:
        callees_first(_advance, (_group_one, _group_wide), args)
    _advance(*args)


@jit(**ks.JIT)
def tensions(P, U, prm, pres):
    """Cable tensions (B, 24) N and node forces (B, 12, 3) N from node positions P and
    velocities U (B, 12, 3), packed parameters prm (B, NP) and pair pressures pres (B, 12) MPa."""
    nbat = P.shape[0]
    T, F = np.zeros((nbat, 24)), np.zeros((nbat, 12, 3))
    Pl, Ul, Tl, C, act = _1P(), _1U(), _1T(), _1C(), _1act()
    for b in range(nbat):
        for n in range(12):
            for k in range(3):
                Pl[n, k, 0], Ul[n, k, 0] = P[b, n, k], U[b, n, k]
        linear = _constants(prm, b, 1.0, C, act, pres, 0)
        ks.cable_forces(Pl, Ul, C, act, linear, Tl, _ONE)
        for j in range(24):
            T[b, j] = Tl[j, 0, 0]
        for n in range(12):
            for k in range(3):
                F[b, n, k] = ks.cable_sum(Tl, n, k, 0)
    return T, F
