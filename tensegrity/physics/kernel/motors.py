"""The compiled time loop of robots with twisted-string actuators (`actuator` (T1)-(T5),
docs/design.md §10): as `kernel.advance`, and each step also moves the 24 motors of every robot.

Robots run in groups of LANES side by side (the layout of `kernel.stages`), a batch under
WIDE_FROM robots in groups of one lane each (not the struts-side-by-side layout of `kernel.robot`):
the strut, node, contact and integration stages are the pneumatic kernel's own; only the cable
stage differs (`_cables`): the tension of each cable by `actuator.string_tension` from the node
states and its motor's angle and speed, then the motor's step (`actuator.motor_step`) under that
tension. The pneumatic kernel is not touched by this module: its results stay bit for bit.
"""
from __future__ import annotations

import math

import numba as nb
import numpy as np

from .. import actuator
from . import (
    _1AN,
    _1C,
    _1G,
    _1P,
    _1Q,
    _1ST,
    _1T,
    _1U,
    _1V,
    _1W,
    _1X,
    _ONE,
    _WIDE,
    LANES,
    NO_TERRAIN,
    NON_FINITE,
    OFF_TERRAIN,
    OK,
    TOO_FAST,
    WIDE_FROM,
    _1act,
    _1lane,
    _1Rm,
    _load,
    _record,
    _retire,
    _wact,
    _wAN,
    _wC,
    _wG,
    _wlane,
    _wP,
    _wQ,
    _wRm,
    _wST,
    _wT,
    _wU,
    _wV,
    _wW,
    _wX,
)
from . import contact as kc
from . import stages as ks
from .compiling import callees_first, jit, stack_array

NM = len(actuator.MOTOR_ROWS)
_L0, _RS = actuator.MOTOR_ROWS.index("L0"), actuator.MOTOR_ROWS.index("RS")
_CABLE_PAIR = np.ascontiguousarray(actuator.topo.CABLE_PAIR.astype(np.int64))
_TH, _OM, _VO, _M = (stack_array(*s, LANES) for s in ((24,), (24,), (24,), (NM,)))
_TH1, _OM1, _VO1, _M1 = (stack_array(*s, 1) for s in ((24,), (24,), (24,), (NM,)))
# The law (T1)-(T5), written once in `actuator`, compiled with the kernel's flags and inlined.
twist = jit(**ks.INLINE)(actuator.twist)
string_tension = jit(**ks.INLINE)(actuator.string_tension)
motor_torque = jit(**ks.INLINE)(actuator.motor_torque)
motor_step = jit(**ks.INLINE)(actuator.motor_step)


@jit(**ks.INLINE)
def _cables(P, U, T, TH, OM, VO, M, lanes):
    """T (24, 4, L) <- tension N and force on the first node of each cable (T3); then each
    motor's step (T5) under its cable's tension: TH, OM (24, L) rad, rad/s at the volts VO."""
    for j in range(24):
        n1, n2 = ks.CABLE_NODES[j, 0], ks.CABLE_NODES[j, 1]
        for l in range(len(lanes)):
            dx, dy, dz = P[n2, 0, l] - P[n1, 0, l], P[n2, 1, l] - P[n1, 1, l], P[n2, 2, l] - P[n1, 2, l]
            ln = math.sqrt(dx * dx + dy * dy + dz * dz)
            il = 1.0 / ln
            ex, ey, ez = dx * il, dy * il, dz * il
            ldot = (ex * (U[n2, 0, l] - U[n1, 0, l]) + ey * (U[n2, 1, l] - U[n1, 1, l])
                    + ez * (U[n2, 2, l] - U[n1, 2, l]))
            c, h = twist(TH[j, l], M[_L0, l], M[_RS, l])
            f = string_tension(ln, ldot, c, h, OM[j, l], M, l)
            T[j, 0, l], T[j, 1, l], T[j, 2, l], T[j, 3, l] = f, f * ex, f * ey, f * ez
            tau = motor_torque(VO[j, l], OM[j, l], M, l)
            TH[j, l], OM[j, l] = motor_step(TH[j, l], OM[j, l], tau, f, h, M, l)


@jit(**ks.INLINE)
def _motors_in(g, theta, omega, mprm, volts, TH, OM, VO, M, lanes):
    """Loads the motors of group g into the lanes: angles TH, speeds OM, volts VO (24, L) by
    their pair, constants M (NM, L); lanes past the batch copy its last robot."""
    L, B = len(lanes), theta.shape[0]
    for l in range(L):
        b = min(g * L + l, B - 1)
        for r in range(NM):
            M[r, l] = mprm[b, r]
        for j in range(24):
            TH[j, l], OM[j, l], VO[j, l] = theta[b, j], omega[b, j], volts[b, _CABLE_PAIR[j]]


@jit(**ks.INLINE)
def _motors_out(g, l, theta, omega, TH, OM):
    """Writes the motors of lane l of group g back (with `kernel._retire`)."""
    b = g * TH.shape[-1] + l
    for j in range(24):
        theta[b, j], omega[b, j] = TH[j, l], OM[j, l]


@jit(**ks.INLINE)
def _run(g, x, v, q, w, anchor, stuck, theta, omega, prm, mprm, volts, kind, meta, hz, n_rec,
         every, dt, out_x, out_q, status, fail_step, work, motors, lanes):
    """`kernel._run` for the robots of group g (L = len(lanes) of them), with the motors
    (`_cables`; their working arrays `motors`: TH, OM, VO, M)."""
    X, V, W, Q, AN, ST, P, U, G, Rm, T, C, act, lane = work
    TH, OM, VO, M = motors
    L = len(lanes)
    # the pneumatic constants' muscles (act) are not used: the volts stand in for pressures
    n_alive = _load(g, x, v, q, w, anchor, stuck, prm, volts, dt, work, lanes)[1]
    _motors_in(g, theta, omega, mprm, volts, TH, OM, VO, M, lanes)
    step = 0
    for rec in range(n_rec):
        for _ in range(every):
            ks.node_states(X, V, Q, W, C, Rm, P, U, lanes)
            _cables(P, U, T, TH, OM, VO, M, lanes)
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
                            _motors_out(g, l, theta, omega, TH, OM)
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
                        _motors_out(g, l, theta, omega, TH, OM)
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
            _motors_out(g, l, theta, omega, TH, OM)
            _retire(g, l, OK, step, x, v, q, w, anchor, stuck, status, fail_step, X, V, Q, W, AN,
                    ST, lane)


@jit(**ks.JIT)
def _group_wide(g, x, v, q, w, anchor, stuck, theta, omega, prm, mprm, volts, kind, meta, hz,
                n_rec, every, dt, out_x, out_q, status, fail_step):
    """`_run` for robots g*LANES ... g*LANES + LANES - 1, side by side in SIMD lanes."""
    _run(g, x, v, q, w, anchor, stuck, theta, omega, prm, mprm, volts, kind, meta, hz, n_rec,
         every, dt, out_x, out_q, status, fail_step,
         (_wX(), _wV(), _wW(), _wQ(), _wAN(), _wST(), _wP(), _wU(), _wG(), _wRm(), _wT(), _wC(),
          _wact(), _wlane()), (_TH(), _OM(), _VO(), _M()), _WIDE)


@jit(**ks.JIT)
def _group_one(b, x, v, q, w, anchor, stuck, theta, omega, prm, mprm, volts, kind, meta, hz,
               n_rec, every, dt, out_x, out_q, status, fail_step):
    """`_run` for robot b alone, in a group of one lane (a batch under WIDE_FROM robots)."""
    _run(b, x, v, q, w, anchor, stuck, theta, omega, prm, mprm, volts, kind, meta, hz, n_rec,
         every, dt, out_x, out_q, status, fail_step,
         (_1X(), _1V(), _1W(), _1Q(), _1AN(), _1ST(), _1P(), _1U(), _1G(), _1Rm(), _1T(), _1C(),
          _1act(), _1lane()), (_TH1(), _OM1(), _VO1(), _M1()), _ONE)


@jit(parallel=True, nogil=True, **ks.JIT)
def _advance(x, v, q, w, anchor, stuck, theta, omega, prm, mprm, volts, kind, meta, hz, n_rec,
             every, dt, out_x, out_q, status, fail_step):
    B = x.shape[0]
    if B < WIDE_FROM:
        for b in nb.prange(B):
            _group_one(b, x, v, q, w, anchor, stuck, theta, omega, prm, mprm, volts, kind, meta,
                       hz, n_rec, every, dt, out_x, out_q, status, fail_step)
    else:
        for g in nb.prange((B + LANES - 1) // LANES):
            _group_wide(g, x, v, q, w, anchor, stuck, theta, omega, prm, mprm, volts, kind, meta,
                        hz, n_rec, every, dt, out_x, out_q, status, fail_step)


def advance(x, v, q, w, anchor, stuck, theta, omega, prm, mprm, volts, kind, meta, hz, n_rec,
            every, dt, out_x, out_q, status, fail_step):
    """Advance all robots and their motors in place: as `kernel.advance`, with the motor angles
    theta and speeds omega (B, 24) rad, rad/s, their constants mprm (B, NM)
    (`TwistedString.pack`, at this dt) and the pair voltages volts (B, 12) V."""
    args = (x, v, q, w, anchor, stuck, theta, omega, prm, mprm, volts, kind, meta, hz, n_rec,
            every, dt, out_x, out_q, status, fail_step)
    if not _advance.overloads:
        callees_first(_advance, (_group_one, _group_wide), args)
    _advance(*args)
