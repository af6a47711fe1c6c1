"""The cable stage of robots with twisted-string actuators (`actuator` (T1)-(T5), docs/design.md
§10), for both layouts of the one driver (`kernel.driver`): the tension of each cable by
`actuator.string_tension` from its node states and its motor's angle and speed, then the motor's
step (`actuator.motor_step`) under that tension. The struts, nodes, contact and integration are the
pneumatic kernel's own.

The motors' working arrays, `Motors` = (theta, omega, mprm, volts, TH, OM, VO, M): the batch's
angles theta and speeds omega (B, 24) rad, rad/s, constants mprm (B, NM) (`TwistedString.pack`)
and volts (B, 24) V, one per cable; the group's angles TH, speeds OM and volts VO (24, L), constants M (NM, L).
A lone robot (`kernel.robot`) holds its cable j in lane j: TH, OM, VO (1, 24), M (NM, 24).
"""

from __future__ import annotations

import math

from .. import actuator
from . import stages as ks
from .compiling import jit, stack_array

NM = len(actuator.MOTOR_ROWS)
SHAPES = ((24,), (24,), (24,), (NM,))  # TH, OM, VO, M before the lane axis
ALONE = tuple(stack_array(*s) for s in ((1, 24), (1, 24), (1, 24), (NM, 24)))  # a lone robot's
# The law (T1)-(T5), written once in `actuator`, compiled with the kernel's flags and inlined.
twist = jit(**ks.INLINE)(actuator.twist)
ratio = jit(**ks.INLINE)(actuator.ratio)
string_tension = jit(**ks.INLINE)(actuator.string_tension)
motor_torque = jit(**ks.INLINE)(actuator.motor_torque)
motor_step = jit(**ks.INLINE)(actuator.motor_step)


@jit(**ks.INLINE)
def string(dx, dy, dz, dux, duy, duz, TH, OM, VO, M, j, l):
    """Tension (N) (T3) of a cable from node 1 to node 2 = node 1 + d (m), node 2's velocity
    relative to node 1 du (m/s), whose motor is TH[j, l], OM[j, l] at the volts VO[j, l] with the
    constants M[:, l]; and its force (N) on node 1. Then steps the motor (T4)-(T5) under it.
    Two square roots (the cable's length, the strands' span p) and one division for both
    reciprocals: the divider bounds this stage with its arithmetic (docs/benchmarks.md)."""
    ln = math.sqrt(dx * dx + dy * dy + dz * dz)
    theta, omega = TH[j, l], OM[j, l]
    t, p = twist(theta, M, l)
    inv = 1.0 / (ln * p)
    il = p * inv
    ex, ey, ez = dx * il, dy * il, dz * il
    ldot = ex * dux + ey * duy + ez * duz
    h = ratio(t, ln * inv)
    f = string_tension(ln, ldot, p, h, omega, M, l)
    tau = motor_torque(VO[j, l], omega, M, l)
    TH[j, l], OM[j, l] = motor_step(theta, omega, tau, f, h, M, l)
    return f, f * ex, f * ey, f * ez


@jit(**ks.INLINE)
def cables(P, U, T, TH, OM, VO, M, lanes):
    """`ks.cable_forces` of twisted strings: T (24, 4, L) <- tension N and force on the first
    node of each cable (`string`), and each motor stepped."""
    for j in range(24):
        n1, n2 = ks.CABLE_NODES[j, 0], ks.CABLE_NODES[j, 1]
        for l in range(len(lanes)):
            T[j, 0, l], T[j, 1, l], T[j, 2, l], T[j, 3, l] = string(
                P[n2, 0, l] - P[n1, 0, l], P[n2, 1, l] - P[n1, 1, l], P[n2, 2, l] - P[n1, 2, l],
                U[n2, 0, l] - U[n1, 0, l], U[n2, 1, l] - U[n1, 1, l], U[n2, 2, l] - U[n1, 2, l],
                TH, OM, VO, M, j, l)


@jit(**ks.INLINE)
def motors_in(g, motors, lanes):
    """Loads the motors of group g (L = len(lanes) robots) into the lanes of `motors` (module
    docstring), each cable at its volts; lanes past the batch copy its last robot."""
    theta, omega, mprm, volts, TH, OM, VO, M = motors
    L, B = len(lanes), theta.shape[0]
    for l in range(L):
        b = min(g * L + l, B - 1)
        for r in range(NM):
            M[r, l] = mprm[b, r]
        for j in range(24):
            TH[j, l], OM[j, l], VO[j, l] = theta[b, j], omega[b, j], volts[b, j]


@jit(**ks.INLINE)
def motors_out(g, l, motors):
    """Writes the motors of lane l of group g back to the batch's theta, omega."""
    theta, omega, mprm, volts, TH, OM, VO, M = motors
    b = g * TH.shape[-1] + l
    for j in range(24):
        theta[b, j], omega[b, j] = TH[j, l], OM[j, l]


@jit(**ks.INLINE)
def alone_in(motors, A):
    """A (TH, OM, VO (1, 24), M (NM, 24)) <- the robot in lane 0 of `motors`, its constants in
    every lane (the layout of `kernel.robot`)."""
    TH1, OM1, VO1, M1 = motors[4:]
    TH, OM, VO, M = A
    for j in range(24):
        TH[0, j], OM[0, j], VO[0, j] = TH1[j, 0], OM1[j, 0], VO1[j, 0]
        for r in range(NM):
            M[r, j] = M1[r, 0]


@jit(**ks.INLINE)
def alone_out(A, motors):
    """The motors of the lone robot in A -> lane 0 of `motors` (the inverse of `alone_in`)."""
    TH1, OM1 = motors[4:6]
    for j in range(24):
        TH1[j, 0], OM1[j, 0] = A[0][0, j], A[1][0, j]
