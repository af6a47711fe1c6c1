"""The one time loop of the compiled kernel, for both actuators (design.md sections 3 and 10): it
loads a group of robots, steps them, records after every block of `every` steps, retires a robot
at its failure and writes the live ones back at the end. The actuators differ in the cable stage
alone, and in the motors' state written back with the robot's: `motors` is None for pneumatic
muscles (`ks.cable_forces`), or the working arrays of twisted strings (`kernel.strings`); numba
compiles each kind on its own, the branches of the other pruned.

Two layouts: `run` steps a group of L robots side by side, one per SIMD lane (`kernel.stages`);
`alone` steps one robot in the layout of `kernel.robot` (its struts, nodes and cables side by
side), the faster for a batch under WIDE_FROM robots. Status per robot (`dynamics.simulate` reads
the codes 0-3): OK, NON_FINITE, TOO_FAST (node speed above max_speed), OFF_TERRAIN (no triangle
under a node; the struts keep their state from before that step). A robot that fails keeps the
state and step count of its failure; its group stops when all of its robots have failed.
"""

from __future__ import annotations

from numba.core import types
from numba.extending import overload

from .. import actuator
from ..params import IDX
from . import contact as kc
from . import robot as kr
from . import stages as ks
from . import strings as kst
from .compiling import jit, stack_array

OK, NON_FINITE, TOO_FAST, OFF_TERRAIN = 0, 1, 2, 3  # status codes (values fixed: see dynamics)
NO_TERRAIN = kc.NO_TERRAIN
LANES = 8  # robots per group: one AVX-512 register of float64
WIDE_FROM = 3  # smaller batches run one robot per group (and per thread): faster for 1 or 2

# Columns of the packed parameter array prm (B, NP) (params.NAMES); the actuator's from _LAW on.
_STRUT_LENGTH, _STRUT_RADIUS, _STRUT_MASS, _LAW, _GRAVITY = (IDX[k] for k in (
    "strut_length", "strut_radius", "strut_mass", actuator.NAMES[0], "gravity"))
(_GROUND_STIFFNESS, _GROUND_DAMPING, _FRICTION, _FRICTION_STIFFNESS, _FRICTION_DAMPING,
 _STRUT_DAMPING, _MAX_SPEED) = (IDX[k] for k in (
    "ground_stiffness", "ground_damping", "friction", "friction_stiffness", "friction_damping",
    "strut_damping", "max_speed"))

# The working arrays of a group of L lanes (shapes before the lane axis): state X, V, W, Q;
# anchors AN, stuck flags ST; nodes P, U, contact forces G; rotations Rm; cables T; constants
# C; muscles act; per lane (fastest squared speed, on terrain, alive). Each is made on the stack
# of the function that calls it (`compiling.stack_array`): _w* for LANES lanes, _1* for one;
# _r*: one robot alone (`kernel.robot`); _m*, _m1*, _a*: the motors (`kernel.strings`).
SHAPES = ((6, 3), (6, 3), (6, 3), (6, 4), (12, 3), (12,), (12, 3), (12, 3), (12, 3), (6, 3, 3),
          (24, 4), (ks.NC,), (24,), (3,))
(_wX, _wV, _wW, _wQ, _wAN, _wST, _wP, _wU, _wG, _wRm, _wT, _wC, _wact, _wlane) = [
    stack_array(*s, LANES) for s in SHAPES]
(_1X, _1V, _1W, _1Q, _1AN, _1ST, _1P, _1U, _1G, _1Rm, _1T, _1C, _1act, _1lane) = [
    stack_array(*s, 1) for s in SHAPES]
(_rX, _rV, _rW, _rQ, _rRm, _rP, _rU, _rG, _rAN, _rST, _ron, _rE, _rTF, _rTN, _rFN, _rC, _ract,
 _rfast) = [stack_array(*s) for s in kr.SHAPES]
_mTH, _mOM, _mVO, _mM = (stack_array(*s, LANES) for s in kst.SHAPES)
_m1TH, _m1OM, _m1VO, _m1M = (stack_array(*s, 1) for s in kst.SHAPES)
_aTH, _aOM, _aVO, _aM = kst.ALONE
WIDE_LANES, ONE_LANE = (0,) * LANES, (0,)  # lane markers (kernel.stages)


def check_levels(levels, batch):
    """Raises ValueError unless levels (pressures MPa or volts V) are (batch, 24), one per cable:
    the kernel reads levels[b, j] for cable j and does not check its bounds."""
    if levels.shape != (batch, 24):
        raise ValueError(f"the kernel takes one level per cable, ({batch}, 24); got {levels.shape}")


@jit(**ks.INLINE)
def constants(prm, b, dt, C, act, pres, l):
    """Lane l of C (NC, L) and the muscles act (24, L) N/m (eq. 1) for robot b, from its
    pressures pres[b] (24,) MPa, one per cable (`dynamics` lifts a pair's to both its cables)
    (kernel.stages names the rows; the actuator's by `actuator.pack` and `activation`). Returns
    True if its cable law is linear (`actuator.pack`)."""
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
        act[j, l] = ks.law_activation(prm, b, _LAW, pres[b, j])
    return linear


@jit(**ks.JIT)  # not inlined: rare, and it would crowd the step loop
def _retire(g, l, code, step, x, v, q, w, anchor, stuck, status, fail_step, X, V, Q, W, AN, ST,
            lane, motors):
    """Writes the state of lane l of group g (robot g*L + l) back, its motors unless None, with
    its status `code` and its number of completed steps; the lane is then no longer alive."""
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
    if motors is not None:
        kst.motors_out(g, l, motors)
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
def _load(g, x, v, q, w, anchor, stuck, prm, pres, dt, work, lanes, motors):
    """Loads the robots of group g into the lanes of `work` (and `motors`, unless None). Returns
    whether all their cable laws are linear and the number of live lanes. With motors the
    pneumatic muscles (act) are not used."""
    X, V, W, Q, AN, ST, P, U, G, Rm, T, C, act, lane = work
    L, B = len(lanes), x.shape[0]
    linear, n_alive = True, 0
    for l in range(L):
        b = min(g * L + l, B - 1)  # lanes past the batch copy its last robot
        linear &= constants(prm, b, dt, C, act, pres, l)
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
    if motors is not None:
        kst.motors_in(g, motors, lanes)
    return linear, n_alive


@jit(**ks.INLINE)
def _cables(P, U, C, act, linear, T, motors, lanes):
    """The cable stage: T (24, 4, L) by `ks.cable_forces`, or by `kst.cables` with motors."""
    if motors is None:
        ks.cable_forces(P, U, C, act, linear, T, lanes)
    else:
        kst.cables(P, U, T, motors[4], motors[5], motors[6], motors[7], lanes)


@jit(**ks.INLINE)
def run(g, x, v, q, w, anchor, stuck, prm, pres, kind, meta, hz, n_rec, every, dt, out_x, out_q,
        status, fail_step, work, lanes, motors):
    """Group g of `kernel.advance` (same arguments, then the tuple of working arrays of SHAPES,
    the lane markers and the motors): the module docstring."""
    X, V, W, Q, AN, ST, P, U, G, Rm, T, C, act, lane = work
    L = len(lanes)
    linear, n_alive = _load(g, x, v, q, w, anchor, stuck, prm, pres, dt, work, lanes, motors)
    step = 0
    for rec in range(n_rec):
        for _ in range(every):
            ks.node_states(X, V, Q, W, C, Rm, P, U, lanes)
            _cables(P, U, C, act, linear, T, motors, lanes)
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
                                    fail_step, X, V, Q, W, AN, ST, lane, motors)
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
                                lane, motors)
                        n_alive -= 1
            if n_alive == 0:
                break
        if n_alive == 0:
            break
        _record(g, rec, X, Q, lane, out_x, out_q, lanes)
    for l in range(L):
        if lane[2, l] != 0.0:
            _retire(g, l, OK, step, x, v, q, w, anchor, stuck, status, fail_step, X, V, Q, W, AN,
                    ST, lane, motors)


@jit(**ks.INLINE)
def alone(b, x, v, q, w, anchor, stuck, prm, pres, kind, meta, hz, n_rec, every, dt, out_x, out_q,
          status, fail_step, work, S, motors, strings):
    """`run` for robot b alone, stepped in the layout of `kernel.robot` (its arrays S, and for
    motors `strings`, `kst.ALONE`); a group of one lane (`work`, `motors`) loads, records and
    retires it."""
    X, V, W, Q, AN, ST, P, U, G, Rm, T, C, act, lane = work
    linear = _load(b, x, v, q, w, anchor, stuck, prm, pres, dt, work, ONE_LANE, motors)[0]
    kr.load(S, X, V, W, Q, AN, ST, C, act)
    if motors is not None:
        kst.alone_in(motors, strings)
    step, code = 0, OK
    for rec in range(n_rec):
        for _ in range(every):
            fastest = kr.step(S, linear, kind, meta, hz, dt, strings)
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
        _record(b, rec, X, Q, lane, out_x, out_q, ONE_LANE, False)
    kr.store(S, X, V, W, Q, AN, ST)
    if motors is not None:
        kst.alone_out(strings, motors)
    _retire(b, 0, code, step, x, v, q, w, anchor, stuck, status, fail_step, X, V, Q, W, AN, ST,
            lane, motors)


def _motors(batch, work):
    """The motors (`kernel.strings`): the batch's arrays `batch` followed by the working arrays
    `work`; None for pneumatic muscles (batch None). Compiled by its type (`_motors_typed`)."""
    return None if batch is None else batch + work


def _when(batch, value):
    """`value`, or None for pneumatic muscles (batch None). Compiled by its type."""
    return None if batch is None else value


@overload(_motors)
def _motors_typed(batch, work):
    if isinstance(batch, types.NoneType):
        return lambda batch, work: None
    return lambda batch, work: batch + work


@overload(_when)
def _when_typed(batch, value):
    if isinstance(batch, types.NoneType):
        return lambda batch, value: None
    return lambda batch, value: value


@jit(**ks.JIT)
def group_wide(g, x, v, q, w, anchor, stuck, prm, pres, kind, meta, hz, n_rec, every, dt, out_x,
               out_q, status, fail_step, batch_motors):
    """`run` for robots g*LANES ... g*LANES + LANES - 1: pneumatic if batch_motors is None, else
    twisted strings with the batch's motors (theta, omega, mprm, volts) (`kernel.strings`)."""
    work = (_wX(), _wV(), _wW(), _wQ(), _wAN(), _wST(), _wP(), _wU(), _wG(), _wRm(), _wT(), _wC(),
            _wact(), _wlane())
    motors = _motors(batch_motors, (_mTH(), _mOM(), _mVO(), _mM()))
    run(g, x, v, q, w, anchor, stuck, prm, pres, kind, meta, hz, n_rec, every, dt, out_x, out_q,
        status, fail_step, work, WIDE_LANES, motors)


@jit(**ks.JIT)
def group_one(b, x, v, q, w, anchor, stuck, prm, pres, kind, meta, hz, n_rec, every, dt, out_x,
              out_q, status, fail_step, batch_motors):
    """`alone` for robot b: as `group_wide`."""
    work = (_1X(), _1V(), _1W(), _1Q(), _1AN(), _1ST(), _1P(), _1U(), _1G(), _1Rm(), _1T(), _1C(),
            _1act(), _1lane())
    S = (_rX(), _rV(), _rW(), _rQ(), _rRm(), _rP(), _rU(), _rG(), _rAN(), _rST(), _ron(), _rE(),
         _rTF(), _rTN(), _rFN(), _rC(), _ract(), _rfast())
    motors = _motors(batch_motors, (_m1TH(), _m1OM(), _m1VO(), _m1M()))
    strings = _when(batch_motors, (_aTH(), _aOM(), _aVO(), _aM()))
    alone(b, x, v, q, w, anchor, stuck, prm, pres, kind, meta, hz, n_rec, every, dt, out_x, out_q,
          status, fail_step, work, S, motors, strings)
