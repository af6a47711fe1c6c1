"""The compiled time loop (numba): cable forces (eq. 1-2), ground contact (C1)-(C4), gravity and
strut dynamics (eq. 3-4) integrated by semi-implicit Euler (design.md section 3).

One call advances every robot of a batch by `n_rec * every` steps of dt, writing the strut
centres and quaternions after each block of `every` steps. Robots run in parallel threads;
the time loop never returns to Python. A step runs the inlined stages `_node_states`,
`_cable_forces`, `_ground_forces`, `_integrate_strut` (per strut) and `_speed_status`; a block
ends with `_record`. Status per robot (`dynamics.simulate` reads the codes 0-3): OK, NON_FINITE,
TOO_FAST (node speed above max_speed), OFF_TERRAIN (no triangle under a node).
"""
from __future__ import annotations

import math

import numba as nb
import numpy as np

from . import topology as topo
from .params import IDX
from .terrain import KINDS

OK, NON_FINITE, TOO_FAST, OFF_TERRAIN = 0, 1, 2, 3  # status codes (values fixed: see dynamics)
NO_TERRAIN, PLANE, HEIGHTFIELD = KINDS["none"], KINDS["plane"], KINDS["heightfield"]

# Topology as kernel constants: node -> (strut, sign), cable -> nodes, cable -> pair,
# strut -> its two nodes (STRUT_A = centre + S/2 axis, STRUT_B = centre - S/2 axis).
NODE_STRUT = np.ascontiguousarray(topo.NODE_STRUT)
NODE_SIGN = np.ascontiguousarray(topo.NODE_SIGN)
CABLE_NODES = np.ascontiguousarray(topo.CABLES.astype(np.int64))
CABLE_PAIR = np.ascontiguousarray(topo.CABLE_PAIR.astype(np.int64))
STRUT_A = np.ascontiguousarray(topo.STRUTS[:, 0].astype(np.int64))
STRUT_B = np.ascontiguousarray(topo.STRUTS[:, 1].astype(np.int64))

# No division-by-zero checks (error_model="numpy"); fused multiply-add and reassociation are
# allowed, but not the flags that assume finite values: the blow-up checks must see NaN.
_JIT = dict(cache=True, error_model="numpy", fastmath={"contract", "reassoc", "nsz", "arcp"})
_INLINE = dict(inline="always", **_JIT)

# Columns of the packed parameter array prm (B, NP) (params.NAMES).
(_STRUT_LENGTH, _STRUT_RADIUS, _STRUT_MASS, _CABLE_EXPONENT, _CABLE_STIFFNESS, _CABLE_REST_LENGTH,
 _CABLE_DAMPING, _MUSCLE_MIN_LENGTH, _MUSCLE_GAIN, _GRAVITY) = (IDX[k] for k in (
    "strut_length", "strut_radius", "strut_mass", "cable_exponent", "cable_stiffness",
    "cable_rest_length", "cable_damping", "muscle_min_length", "muscle_gain", "gravity"))
(_GROUND_STIFFNESS, _GROUND_DAMPING, _FRICTION, _FRICTION_STIFFNESS, _FRICTION_DAMPING,
 _STRUT_DAMPING, _MAX_SPEED) = (IDX[k] for k in (
    "ground_stiffness", "ground_damping", "friction", "friction_stiffness", "friction_damping",
    "strut_damping", "max_speed"))


@nb.njit(**_INLINE)
def _node_states(X, V, Q, W, hl, Rm, P, U, F):
    """Rotation matrices Rm (6, 3, 3) (columns = body axes in world) of the quaternions Q (6, 4);
    node positions P (12, 3) m and velocities U (12, 3) m/s from the strut centres X, V (6, 3)
    and body angular velocities W (6, 3) rad/s, half strut length hl m; zeroes the forces F."""
    for i in range(6):
        qw, qx, qy, qz = Q[i, 0], Q[i, 1], Q[i, 2], Q[i, 3]
        Rm[i, 0, 0] = 1 - 2 * (qy * qy + qz * qz)
        Rm[i, 0, 1] = 2 * (qx * qy - qw * qz)
        Rm[i, 0, 2] = 2 * (qx * qz + qw * qy)
        Rm[i, 1, 0] = 2 * (qx * qy + qw * qz)
        Rm[i, 1, 1] = 1 - 2 * (qx * qx + qz * qz)
        Rm[i, 1, 2] = 2 * (qy * qz - qw * qx)
        Rm[i, 2, 0] = 2 * (qx * qz - qw * qy)
        Rm[i, 2, 1] = 2 * (qy * qz + qw * qx)
        Rm[i, 2, 2] = 1 - 2 * (qx * qx + qy * qy)
    for n in range(12):
        i = NODE_STRUT[n]
        sg = NODE_SIGN[n] * hl
        w0, w1 = W[i, 0], W[i, 1]
        for k in range(3):
            P[n, k] = X[i, k] + sg * Rm[i, k, 2]
            # d c / dt = R (w x e3) = R (w1, -w0, 0)
            U[n, k] = V[i, k] + sg * (Rm[i, k, 0] * w1 - Rm[i, k, 1] * w0)
            F[n, k] = 0.0


@nb.njit(**_INLINE)
def _cable_forces(P, U, K, Lr, a_exp, La, Bc, Lmin, act, F, T):
    """Cable tensions T (24,) N by eq. 2 with the muscle of eq. 1 (act = Kg*P per cable, N/m;
    La = Lr**a_exp), clamped at zero so that a cable never pushes; adds the node forces to F."""
    for j in range(24):
        n1, n2 = CABLE_NODES[j, 0], CABLE_NODES[j, 1]
        dx, dy, dz = P[n2, 0] - P[n1, 0], P[n2, 1] - P[n1, 1], P[n2, 2] - P[n1, 2]
        ln = math.sqrt(dx * dx + dy * dy + dz * dz)
        ex, ey, ez = dx / ln, dy / ln, dz / ln
        ldot = (ex * (U[n2, 0] - U[n1, 0]) + ey * (U[n2, 1] - U[n1, 1])
                + ez * (U[n2, 2] - U[n1, 2]))
        if a_exp == 1.0:
            f = K * (ln - Lr)
        else:
            f = K * (ln ** a_exp - La)
        f += Bc * ldot
        if act[j] > 0.0 and ln > Lmin:
            f += act[j] * (ln - Lmin)
        if f <= 0.0:
            T[j] = 0.0
            continue
        T[j] = f
        F[n1, 0] += f * ex
        F[n1, 1] += f * ey
        F[n1, 2] += f * ez
        F[n2, 0] -= f * ex
        F[n2, 1] -= f * ey
        F[n2, 2] -= f * ez


@nb.njit(**_INLINE)
def _terrain_contact(px, py, pz, kind, meta, hz):
    """Unit normal (nx, ny, nz), signed distance (m) of p to the triangle plane under it, ok flag
    (False off the edge of a HEIGHTFIELD). meta (7,) = normal, offset, x0, y0, spacing; hz (m)."""
    if kind == PLANE:
        return meta[0], meta[1], meta[2], meta[0] * px + meta[1] * py + meta[2] * pz - meta[3], True
    h = meta[6]
    u = (px - meta[4]) / h
    v = (py - meta[5]) / h
    i = int(math.floor(u))
    j = int(math.floor(v))
    if i < 0 or j < 0 or i >= hz.shape[0] - 1 or j >= hz.shape[1] - 1:
        return 0.0, 0.0, 1.0, 0.0, False
    s = u - i
    t = v - j
    if s + t <= 1.0:
        z0 = hz[i, j]
        ax, ay, az = -h * (hz[i + 1, j] - z0), -h * (hz[i, j + 1] - z0), h * h
        x0, y0 = meta[4] + i * h, meta[5] + j * h
    else:
        z0 = hz[i + 1, j + 1]
        ax, ay, az = h * (hz[i, j + 1] - z0), h * (hz[i + 1, j] - z0), h * h
        x0, y0 = meta[4] + (i + 1) * h, meta[5] + (j + 1) * h
    nn = math.sqrt(ax * ax + ay * ay + az * az)
    ax, ay, az = ax / nn, ay / nn, az / nn
    return ax, ay, az, ax * (px - x0) + ay * (py - y0) + az * (pz - z0), True


@nb.njit(**_INLINE)
def _stick_force(ddx, ddy, ddz, utx, uty, utz, kt, ct, cap):
    """(C4) friction force (N) of the stick spring k_t (N/m) and damper c_t (N s/m) from the
    tangential displacement dd (m) and velocity ut (m/s), scaled down to |f_t| = cap (N)."""
    ftx, fty, ftz = -kt * ddx - ct * utx, -kt * ddy - ct * uty, -kt * ddz - ct * utz
    fmag2 = ftx * ftx + fty * fty + ftz * ftz
    if fmag2 > cap * cap:
        sc = cap / math.sqrt(fmag2)
        ftx, fty, ftz = ftx * sc, fty * sc, ftz * sc
    return ftx, fty, ftz


@nb.njit(**_INLINE)
def _ground_forces(P, U, F, AN, ST, kind, meta, hz, contact):
    """Adds f_n n + f_t to F (12, 3) N at each node touching the terrain: (C1) penetration of
    the end sphere, (C2) penalty normal force, (C3) stick displacement from the anchor AN (12, 3)
    m, set when a contact begins (ST) and dragged along when sliding, (C4) by `_stick_force`.
    contact = (r m, k_n N/m, c_n N s/m, mu, k_t N/m, c_t N s/m). False if a node has no terrain
    under it (the later nodes are then skipped)."""
    r, kn, cn, mu, kt, ct = contact
    ok = True
    # No break or early return: with one exit, numba prunes the reference counting of the
    # inlined array arguments, which would otherwise cost atomic operations every step.
    for n in range(12):
        if not ok:
            continue
        nx, ny, nz, dist, ok = _terrain_contact(P[n, 0], P[n, 1], P[n, 2], kind, meta, hz)
        if not ok:
            continue
        pen = r - dist
        if pen <= 0.0:
            ST[n] = False  # no contact: forget the anchor
            continue
        un = nx * U[n, 0] + ny * U[n, 1] + nz * U[n, 2]
        fn = kn * pen - cn * un
        if fn <= 0.0:
            ST[n] = False
            continue
        if not ST[n]:
            for k in range(3):
                AN[n, k] = P[n, k]
            ST[n] = True
        ddx, ddy, ddz = P[n, 0] - AN[n, 0], P[n, 1] - AN[n, 1], P[n, 2] - AN[n, 2]
        dn = nx * ddx + ny * ddy + nz * ddz
        ddx, ddy, ddz = ddx - dn * nx, ddy - dn * ny, ddz - dn * nz
        dmag = math.sqrt(ddx * ddx + ddy * ddy + ddz * ddz)
        cap = mu * fn
        if kt * dmag > cap:  # sliding: drag the anchor along
            sc = cap / (kt * dmag)
            ddx, ddy, ddz = ddx * sc, ddy * sc, ddz * sc
            AN[n, 0], AN[n, 1], AN[n, 2] = P[n, 0] - ddx, P[n, 1] - ddy, P[n, 2] - ddz
        ftx, fty, ftz = _stick_force(ddx, ddy, ddz, U[n, 0] - un * nx, U[n, 1] - un * ny,
                                     U[n, 2] - un * nz, kt, ct, cap)
        F[n, 0] += fn * nx + ftx
        F[n, 1] += fn * ny + fty
        F[n, 2] += fn * nz + ftz
    return ok


@nb.njit(**_INLINE)
def _rotate(Q, i, w0, w1, w2, dt):
    """Q[i] <- Q[i] * exp(w dt / 2), the exponential by its Taylor series (|w| dt / 2 << 1). The
    factor is a unit quaternion, so |Q[i]| drifts by round-off only (see `_record`)."""
    h2 = 0.25 * dt * dt * (w0 * w0 + w1 * w1 + w2 * w2)
    c = 1.0 - h2 * (0.5 - h2 / 24.0)
    sn = 0.5 * dt * (1.0 - h2 * (1.0 / 6.0 - h2 / 120.0))
    ex, ey, ez = w0 * sn, w1 * sn, w2 * sn
    qw, qx, qy, qz = Q[i, 0], Q[i, 1], Q[i, 2], Q[i, 3]
    Q[i, 0] = qw * c - qx * ex - qy * ey - qz * ez
    Q[i, 1] = qw * ex + qx * c + qy * ez - qz * ey
    Q[i, 2] = qw * ey - qx * ez + qy * c + qz * ex
    Q[i, 3] = qw * ez + qx * ey - qy * ex + qz * c


@nb.njit(**_INLINE)
def _integrate_strut(i, X, V, Q, W, F, Rm, hl, motion):
    """Semi-implicit Euler step of strut i: V (m/s) from its node forces F, gravity and damping
    (eq. 3), then X (m); W (rad/s) by Euler's equations with the torque of eq. 4, then Q by
    `_rotate`. motion = (dt s, dt/m, dt/I_t, (I_a - I_t)/I_t, ds 1/s, g m/s^2). Returns the
    squared end speed bound |v|^2 + hl^2 (w0^2 + w1^2), m^2/s^2."""
    dt, dt_m, dt_I, gyro, ds, grav = motion
    na, nb_ = STRUT_A[i], STRUT_B[i]
    V[i, 0] += dt_m * (F[na, 0] + F[nb_, 0]) - dt * ds * V[i, 0]
    V[i, 1] += dt_m * (F[na, 1] + F[nb_, 1]) - dt * ds * V[i, 1]
    V[i, 2] += dt_m * (F[na, 2] + F[nb_, 2]) - dt * (grav + ds * V[i, 2])
    X[i, 0] += dt * V[i, 0]
    X[i, 1] += dt * V[i, 1]
    X[i, 2] += dt * V[i, 2]
    # body-frame torque (eq. 4): (0,0,L) x R^T f+ + (0,0,-L) x R^T f-
    gx, gy, gz = F[na, 0] - F[nb_, 0], F[na, 1] - F[nb_, 1], F[na, 2] - F[nb_, 2]
    d0 = Rm[i, 0, 0] * gx + Rm[i, 1, 0] * gy + Rm[i, 2, 0] * gz
    d1 = Rm[i, 0, 1] * gx + Rm[i, 1, 1] * gy + Rm[i, 2, 1] * gz
    w0, w1, w2 = W[i, 0], W[i, 1], W[i, 2]
    # Euler's equations, I = diag(It, It, Ia): w x I w = ((Ia-It) w1 w2, (It-Ia) w2 w0, 0)
    w0 += dt_I * (-hl * d1) - dt * (gyro * w1 * w2 + ds * w0)
    w1 += dt_I * (hl * d0) + dt * (gyro * w2 * w0 - ds * w1)
    w2 -= dt * ds * w2
    W[i, 0], W[i, 1], W[i, 2] = w0, w1, w2
    _rotate(Q, i, w0, w1, w2, dt)
    return V[i, 0] ** 2 + V[i, 1] ** 2 + V[i, 2] ** 2 + hl * hl * (w0 * w0 + w1 * w1)


@nb.njit(**_INLINE)
def _speed_status(fastest, vmax2):
    """The status after a step: OK if the largest squared end speed `fastest` (m^2/s^2) is
    within vmax2, else NON_FINITE (NaN) or TOO_FAST."""
    return OK if fastest <= vmax2 else (NON_FINITE if not fastest == fastest else TOO_FAST)


@nb.njit(**_INLINE)
def _record(b, rec, X, Q, out_x, out_q):
    """Renormalises the quaternions Q (6, 4) and writes X (6, 3) m, Q to out_x, out_q[b, rec]."""
    for i in range(6):
        iq = 1.0 / math.sqrt(Q[i, 0] ** 2 + Q[i, 1] ** 2 + Q[i, 2] ** 2 + Q[i, 3] ** 2)
        for k in range(4):
            Q[i, k] *= iq
            out_q[b, rec, i, k] = Q[i, k]
        for k in range(3):
            out_x[b, rec, i, k] = X[i, k]


@nb.njit(**_JIT)
def tensions(P, U, prm, pres):
    """Cable tensions (B, 24) N and node forces (B, 12, 3) N from node positions P and
    velocities U (B, 12, 3), packed parameters prm (B, NP) and pair pressures pres (B, 12) MPa."""
    nbat = P.shape[0]
    T = np.zeros((nbat, 24))
    F = np.zeros((nbat, 12, 3))
    act = np.empty(24)
    for b in range(nbat):
        a_exp = prm[b, _CABLE_EXPONENT]
        for j in range(24):
            act[j] = prm[b, _MUSCLE_GAIN] * pres[b, CABLE_PAIR[j]]
        _cable_forces(P[b], U[b], prm[b, _CABLE_STIFFNESS], prm[b, _CABLE_REST_LENGTH], a_exp,
                      prm[b, _CABLE_REST_LENGTH] ** a_exp, prm[b, _CABLE_DAMPING],
                      prm[b, _MUSCLE_MIN_LENGTH], act, F[b], T[b])
    return T, F


@nb.njit(**_JIT)
def _advance_one(b, x, v, q, w, anchor, stuck, prm, pres, kind, meta, hz, n_rec, every, dt,
                 out_x, out_q, status, fail_step):
    """Robot b of `advance` (same arguments): runs the stages on local copies of its state,
    records after every block, stops at the first failure and writes the state back, its status
    and the number of completed steps fail_step[b]."""
    S, r, m = prm[b, _STRUT_LENGTH], prm[b, _STRUT_RADIUS], prm[b, _STRUT_MASS]
    hl = 0.5 * S
    a_exp, Lmin = prm[b, _CABLE_EXPONENT], prm[b, _MUSCLE_MIN_LENGTH]
    K, Lr, Bc = prm[b, _CABLE_STIFFNESS], prm[b, _CABLE_REST_LENGTH], prm[b, _CABLE_DAMPING]
    La = Lr ** a_exp
    contact = (r, prm[b, _GROUND_STIFFNESS], prm[b, _GROUND_DAMPING], prm[b, _FRICTION],
               prm[b, _FRICTION_STIFFNESS], prm[b, _FRICTION_DAMPING])
    vmax2 = prm[b, _MAX_SPEED] ** 2
    It, Ia = m * (S * S / 12.0 + r * r / 4.0), m * r * r / 2.0  # thin tube inertia, kg m^2
    motion = (dt, dt / m, dt / It, (Ia - It) / It, prm[b, _STRUT_DAMPING], prm[b, _GRAVITY])
    # robot-local copies of the state: small contiguous arrays the loop works on
    X, V, Q, W = x[b].copy(), v[b].copy(), q[b].copy(), w[b].copy()
    AN, ST = anchor[b].copy(), stuck[b].copy()
    P, U, F = np.empty((12, 3)), np.empty((12, 3)), np.empty((12, 3))
    Rm, T, act = np.empty((6, 3, 3)), np.empty(24), np.empty(24)
    for j in range(24):
        act[j] = prm[b, _MUSCLE_GAIN] * pres[b, CABLE_PAIR[j]]
    step, code = 0, OK
    for rec in range(n_rec):
        for _ in range(every):
            _node_states(X, V, Q, W, hl, Rm, P, U, F)
            _cable_forces(P, U, K, Lr, a_exp, La, Bc, Lmin, act, F, T)
            if kind != NO_TERRAIN and not _ground_forces(P, U, F, AN, ST, kind, meta, hz, contact):
                code = OFF_TERRAIN
                break
            fastest = 0.0
            for i in range(6):
                sp = _integrate_strut(i, X, V, Q, W, F, Rm, hl, motion)
                if sp > fastest or not sp == sp:
                    fastest = sp
            step += 1
            code = _speed_status(fastest, vmax2)
            if code != OK:
                break
        if code != OK:
            break
        _record(b, rec, X, Q, out_x, out_q)
    status[b], fail_step[b] = code, step
    x[b], v[b], q[b], w[b] = X, V, Q, W
    anchor[b], stuck[b] = AN, ST


@nb.njit(parallel=True, **_JIT)
def advance(x, v, q, w, anchor, stuck, prm, pres, kind, meta, hz, n_rec, every, dt,
            out_x, out_q, status, fail_step):
    """Advance all robots in place (module docstring). State x, v (B, 6, 3) m, m/s; q (B, 6, 4);
    w (B, 6, 3) rad/s body; anchor (B, 12, 3) m, stuck (B, 12) bool; prm (B, NP); pres (B, 12)
    MPa; terrain kind (NO_TERRAIN, PLANE, HEIGHTFIELD), meta (7,), hz (nx, ny) m (Terrain.packed);
    dt s; out_x (B, n_rec, 6, 3) m, out_q (B, n_rec, 6, 4); status, fail_step (B,) int64."""
    for b in nb.prange(x.shape[0]):
        _advance_one(b, x, v, q, w, anchor, stuck, prm, pres, kind, meta, hz, n_rec, every, dt,
                     out_x, out_q, status, fail_step)
