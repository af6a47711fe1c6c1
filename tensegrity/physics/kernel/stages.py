"""The stages of one time step of the compiled kernel (`kernel/__init__.py`), each on a group of L
robots side by side: every array has the lane (robot) index as its last, contiguous axis, e.g. strut
centres X (6, 3, L). Each stage loops over struts, nodes or cables outside and over lanes inside;
the lane loops have no branches (selects instead of `if`), so that LLVM turns them into SIMD
instructions, one robot per lane. The per-robot rules (`cable_tension`, the actuator's law;
`_rotate`) are scalar functions called inside the lane loops. The ground contact stage is in
`kernel.contact`.

Per-lane constants are the rows of C (NC, L) named below. Booleans are stored as 0.0 / 1.0.
The last argument of a stage, `lanes`, is a tuple of L zeros: its length is a compile-time
constant, so that LLVM vectorises each lane loop exactly once and for its true length.
"""
from __future__ import annotations

import math

import numpy as np

from .. import actuator
from .. import topology as topo
from .compiling import jit

# No division-by-zero checks (error_model="numpy"); fused multiply-add and reciprocals are
# allowed, but not reassociation (with it, a robot's bits would depend on the lane count) nor
# the flags that assume finite values: the blow-up checks must see NaN.
JIT = dict(cache=True, error_model="numpy", fastmath={"contract", "nsz", "arcp"})
INLINE = dict(forceinline=True, **JIT)
# The contact rules and `normalise` without fused multiply-add: there LLVM's choice of which
# product of a*b - c*d to fuse depends on the code around, and a robot alone (kernel.robot) would
# differ from the same robot in a group in the last bit. Elsewhere the choice has been the same in both layouts
# (tests/physics/test_kernel_lanes); the flags travel with the instructions into the caller.
EXACT = dict(INLINE, fastmath={"nsz", "arcp"})

# Topology as kernel constants: node -> (strut, sign), cable -> nodes, strut -> its two nodes
# (STRUT_A = centre + S/2 axis, STRUT_B = centre - S/2 axis), node -> its four cables in
# increasing order and the sign (+1 first node, -1 second) of their force on it.
NODE_STRUT = np.ascontiguousarray(topo.NODE_STRUT)
NODE_SIGN = np.ascontiguousarray(topo.NODE_SIGN)
CABLE_NODES = np.ascontiguousarray(topo.CABLES.astype(np.int64))
STRUT_A = np.ascontiguousarray(topo.STRUTS[:, 0].astype(np.int64))
STRUT_B = np.ascontiguousarray(topo.STRUTS[:, 1].astype(np.int64))
NODE_CABLES = np.array([np.flatnonzero((topo.CABLES == n).any(1)) for n in range(12)], np.int64)
NODE_CABLE_SIGN = np.where(topo.CABLES[NODE_CABLES, 0] == np.arange(12)[:, None], 1.0, -1.0)

# Rows of the per-lane constants C (NC, L): half strut length m; from row LAW on, the actuator's
# (actuator.ROWS: cable K N/m, L m, exponent a, L**a, B N s/m, Lmin m, eq. 1-2); contact r m,
# k_n N/m, c_n N s/m, mu, k_t N/m, c_t N s/m (C1-C4); dt/m, dt/I_t, (I_a - I_t)/I_t, strut
# damping 1/s, g m/s^2 (eq. 3-4); max speed^2.
HL, LAW = 0, 1
_AFTER_LAW = LAW + len(actuator.ROWS)
(R, KN, CN, MU, KT, CT, DT_M, DT_I, GYRO, DS, GRAV, VMAX2) = range(_AFTER_LAW, _AFTER_LAW + 12)
NC = VMAX2 + 1

# The actuator's law (eq. 1-2), written once in `actuator`, compiled here with the kernel's flags
# and inlined where it is called: its constants, a cable's muscle, and the cable tension.
law_constants = jit(**INLINE)(actuator.pack)
law_activation = jit(**INLINE)(actuator.activation)
cable_tension = jit(**INLINE)(actuator.tension)


@jit(**INLINE)
def rotations(Q, Rm, lanes):
    """Rm (S, 3, 3, L) <- the rotation matrices (columns = body axes in world) of the
    quaternions Q (S, 4, L)."""
    for i in range(Q.shape[0]):
        for l in range(len(lanes)):
            qw, qx, qy, qz = Q[i, 0, l], Q[i, 1, l], Q[i, 2, l], Q[i, 3, l]
            Rm[i, 0, 0, l] = 1 - 2 * (qy * qy + qz * qz)
            Rm[i, 0, 1, l] = 2 * (qx * qy - qw * qz)
            Rm[i, 0, 2, l] = 2 * (qx * qz + qw * qy)
            Rm[i, 1, 0, l] = 2 * (qx * qy + qw * qz)
            Rm[i, 1, 1, l] = 1 - 2 * (qx * qx + qz * qz)
            Rm[i, 1, 2, l] = 2 * (qy * qz - qw * qx)
            Rm[i, 2, 0, l] = 2 * (qx * qz - qw * qy)
            Rm[i, 2, 1, l] = 2 * (qy * qz + qw * qx)
            Rm[i, 2, 2, l] = 1 - 2 * (qx * qx + qy * qy)


@jit(**INLINE)
def node(P, U, n, m, X, V, W, Rm, i, l, sg):
    """P[n, :, m], U[n, :, m] <- position m and velocity m/s of the strut end at sg m (+-half
    the length) along the axis of strut X[i, :, l], V, W, Rm."""
    w0, w1 = W[i, 0, l], W[i, 1, l]
    for k in range(3):
        P[n, k, m] = X[i, k, l] + sg * Rm[i, k, 2, l]
        # d c / dt = R (w x e3) = R (w1, -w0, 0)
        U[n, k, m] = V[i, k, l] + sg * (Rm[i, k, 0, l] * w1 - Rm[i, k, 1, l] * w0)


@jit(**INLINE)
def node_states(X, V, Q, W, C, Rm, P, U, lanes):
    """Rotation matrices Rm (6, 3, 3, L) of the quaternions Q (6, 4, L) (`rotations`); node
    positions P (12, 3, L) m and velocities U (12, 3, L) m/s (`node`) from the strut centres
    X, V (6, 3, L) and body angular velocities W (6, 3, L) rad/s."""
    rotations(Q, Rm, lanes)
    for n in range(12):
        i = NODE_STRUT[n]
        for l in range(len(lanes)):
            node(P, U, n, l, X, V, W, Rm, i, l, NODE_SIGN[n] * C[HL, l])


@jit(**INLINE)
def cable_force(dx, dy, dz, dux, duy, duz, C, l, a, linear):
    """Tension (N) by `cable_tension` of a cable from node 1 to node 2 = node 1 + d (m), the
    velocity of node 2 relative to node 1 du (m/s), and its force (N) on node 1, with the
    constants of lane l of C and the muscle a (N/m)."""
    ln = math.sqrt(dx * dx + dy * dy + dz * dz)
    il = 1.0 / ln  # one division, not three: the divider is the stage's bottleneck
    ex, ey, ez = dx * il, dy * il, dz * il
    ldot = ex * dux + ey * duy + ez * duz
    f = cable_tension(ln, ldot, a, linear, C, LAW, l)
    return f, f * ex, f * ey, f * ez


@jit(**INLINE)
def _cable(j, l, P, U, C, act, T, linear):
    """`cable_forces` for cable j of lane l."""
    n1, n2 = CABLE_NODES[j, 0], CABLE_NODES[j, 1]
    T[j, 0, l], T[j, 1, l], T[j, 2, l], T[j, 3, l] = cable_force(
        P[n2, 0, l] - P[n1, 0, l], P[n2, 1, l] - P[n1, 1, l], P[n2, 2, l] - P[n1, 2, l],
        U[n2, 0, l] - U[n1, 0, l], U[n2, 1, l] - U[n1, 1, l], U[n2, 2, l] - U[n1, 2, l],
        C, l, act[j, l], linear)


@jit(**INLINE)
def cable_forces(P, U, C, act, linear, T, lanes):
    """Cable tensions and forces T (24, 4, L) by `cable_tension` (act (24, L) N/m; `linear` if
    `law_constants` returned True in every lane): T[:, 0] tension N, T[:, 1:] its force on the
    cable's first node."""
    for j in range(24):
        if linear:  # a constant inside each lane loop
            for l in range(len(lanes)):
                _cable(j, l, P, U, C, act, T, True)
        else:
            for l in range(len(lanes)):
                _cable(j, l, P, U, C, act, T, False)


@jit(**INLINE)
def cable_sum(T, n, k, l):
    """Component k (N) of the force of node n's four cables (T of `cable_forces`) in lane l,
    summed in cable order."""
    s = NODE_CABLE_SIGN[n, 0] * T[NODE_CABLES[n, 0], k + 1, l]
    for c in range(1, 4):
        s += NODE_CABLE_SIGN[n, c] * T[NODE_CABLES[n, c], k + 1, l]
    return s


@jit(**INLINE)
def _rotate(Q, i, l, w0, w1, w2, dt):
    """Q[i, :, l] <- Q[i, :, l] * exp(w dt / 2), the exponential by its Taylor series
    (|w| dt / 2 << 1). The factor is a unit quaternion, so |Q| drifts by round-off only."""
    h2 = 0.25 * dt * dt * (w0 * w0 + w1 * w1 + w2 * w2)
    c = 1.0 - h2 * (0.5 - h2 / 24.0)
    sn = 0.5 * dt * (1.0 - h2 * (1.0 / 6.0 - h2 / 120.0))
    ex, ey, ez = w0 * sn, w1 * sn, w2 * sn
    qw, qx, qy, qz = Q[i, 0, l], Q[i, 1, l], Q[i, 2, l], Q[i, 3, l]
    Q[i, 0, l] = qw * c - qx * ex - qy * ey - qz * ez
    Q[i, 1, l] = qw * ex + qx * c + qy * ez - qz * ey
    Q[i, 2, l] = qw * ey - qx * ez + qy * c + qz * ex
    Q[i, 3, l] = qw * ez + qx * ey - qy * ex + qz * c


@jit(**EXACT)
def normalise(Q, i, l):
    """Q[i, :, l] <- the unit quaternion Q[i, :, l] / |Q[i, :, l]| (`_rotate` keeps |Q| = 1 up
    to round-off only)."""
    iq = 1.0 / math.sqrt(Q[i, 0, l] ** 2 + Q[i, 1, l] ** 2 + Q[i, 2, l] ** 2 + Q[i, 3, l] ** 2)
    for k in range(4):
        Q[i, k, l] *= iq


@jit(**INLINE)
def _node_force(T, G, n, k, l):
    """Component k of the force (N) on node n in lane l: its cables (`cable_sum`) + contact G."""
    return cable_sum(T, n, k, l) + G[n, k, l]


@jit(**INLINE)
def strut(i, l, X, V, Q, W, Rm, C, dt, fax, fay, faz, fbx, fby, fbz):
    """Semi-implicit Euler step of strut X[i, :, l], V, Q, W (rotation Rm) with the forces fa
    on its first and fb on its second node (N): V (m/s) from the forces, gravity and damping
    (eq. 3), then X (m); W (rad/s) by Euler's equations with the torque of eq. 4, then Q by
    `_rotate`. Returns the squared end speed bound |v|^2 + hl^2 (w0^2 + w1^2), m^2/s^2."""
    dt_m, ds, hl = C[DT_M, l], C[DS, l], C[HL, l]
    V[i, 0, l] += dt_m * (fax + fbx) - dt * ds * V[i, 0, l]
    V[i, 1, l] += dt_m * (fay + fby) - dt * ds * V[i, 1, l]
    V[i, 2, l] += dt_m * (faz + fbz) - dt * (C[GRAV, l] + ds * V[i, 2, l])
    X[i, 0, l] += dt * V[i, 0, l]
    X[i, 1, l] += dt * V[i, 1, l]
    X[i, 2, l] += dt * V[i, 2, l]
    # body-frame torque (eq. 4): (0,0,L) x R^T f+ + (0,0,-L) x R^T f-
    gx, gy, gz = fax - fbx, fay - fby, faz - fbz
    d0 = Rm[i, 0, 0, l] * gx + Rm[i, 1, 0, l] * gy + Rm[i, 2, 0, l] * gz
    d1 = Rm[i, 0, 1, l] * gx + Rm[i, 1, 1, l] * gy + Rm[i, 2, 1, l] * gz
    w0, w1, w2 = W[i, 0, l], W[i, 1, l], W[i, 2, l]
    # Euler's equations, I = diag(It, It, Ia): w x I w = ((Ia-It) w1 w2, (It-Ia) w2 w0, 0)
    dt_I, gyro = C[DT_I, l], C[GYRO, l]
    w0 += dt_I * (-hl * d1) - dt * (gyro * w1 * w2 + ds * w0)
    w1 += dt_I * (hl * d0) + dt * (gyro * w2 * w0 - ds * w1)
    w2 -= dt * ds * w2
    W[i, 0, l], W[i, 1, l], W[i, 2, l] = w0, w1, w2
    _rotate(Q, i, l, w0, w1, w2, dt)
    return V[i, 0, l] ** 2 + V[i, 1, l] ** 2 + V[i, 2, l] ** 2 + hl * hl * (w0 * w0 + w1 * w1)


@jit(**INLINE)
def faster(sp, fastest):
    """The larger of two squared speeds, NaN if sp is NaN."""
    return sp if (sp > fastest) | (sp != sp) else fastest


@jit(**INLINE)
def integrate(X, V, Q, W, T, G, Rm, C, dt, fastest, lanes):
    """`strut` for every strut, with its node forces: cables T and contact G. fastest (L,) <-
    the largest squared end speed over the struts of a lane (`faster`)."""
    for l in range(len(lanes)):
        fastest[l] = 0.0
    for i in range(6):
        na, nb_ = STRUT_A[i], STRUT_B[i]
        for l in range(len(lanes)):
            sp = strut(i, l, X, V, Q, W, Rm, C, dt, _node_force(T, G, na, 0, l),
                       _node_force(T, G, na, 1, l), _node_force(T, G, na, 2, l),
                       _node_force(T, G, nb_, 0, l), _node_force(T, G, nb_, 1, l),
                       _node_force(T, G, nb_, 2, l))
            fastest[l] = faster(sp, fastest[l])
