"""The compiled time loop (numba): forces (eq. 2-4), contact, and semi-implicit Euler.

One call advances every robot of a batch by `n_rec * every` steps of dt, writing the strut
centres and quaternions after each block of `every` steps. Robots run in parallel threads;
the time loop never returns to Python. Status codes per robot: 0 ok, 1 non-finite, 2 too fast
(node speed above max_speed), 3 off the terrain (no triangle under a node).
"""
from __future__ import annotations

import math

import numba as nb
import numpy as np

from . import topology as topo
from .params import IDX

# Topology as kernel constants: node -> (strut, sign), cable -> nodes, cable -> pair.
NODE_STRUT = np.ascontiguousarray(topo.NODE_STRUT)
NODE_SIGN = np.ascontiguousarray(topo.NODE_SIGN)
CABLE_NODES = np.ascontiguousarray(topo.CABLES.astype(np.int64))
CABLE_PAIR = np.ascontiguousarray(topo.CABLE_PAIR.astype(np.int64))
g_STRUT_A = np.ascontiguousarray(topo.STRUTS[:, 0].astype(np.int64))
g_STRUT_B = np.ascontiguousarray(topo.STRUTS[:, 1].astype(np.int64))

# No division-by-zero checks (error_model="numpy"); fused multiply-add and reassociation are
# allowed, but not the flags that assume finite values: the blow-up checks must see NaN.
_JIT = dict(cache=True, error_model="numpy", fastmath={"contract", "reassoc", "nsz", "arcp"})

_S, _R, _M, _A, _K, _L, _B, _LMIN, _KG, _G = (IDX[k] for k in (
    "strut_length", "strut_radius", "strut_mass", "cable_exponent", "cable_stiffness",
    "cable_rest_length", "cable_damping", "muscle_min_length", "muscle_gain", "gravity"))
_KN, _CN, _MU, _KT, _CT, _DS, _VMAX = (IDX[k] for k in (
    "ground_stiffness", "ground_damping", "friction", "friction_stiffness", "friction_damping",
    "strut_damping", "max_speed"))


@nb.njit(inline="always", **_JIT)
def _terrain_contact(px, py, pz, kind, meta, hz):
    """Unit normal (nx, ny, nz), signed distance of p to the triangle plane under it, ok flag."""
    if kind == 1:
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
    ax /= nn
    ay /= nn
    az /= nn
    return ax, ay, az, ax * (px - x0) + ay * (py - y0) + az * (pz - z0), True


@nb.njit(**_JIT)
def _cable_forces(P, U, K, Lr, a_exp, La, Bc, Lmin, act, F, T):
    """Cable tensions T (24,) N by eq. 2 with the muscle of eq. 1 (act = Kg*P per cable),
    clamped at zero so that a cable never pushes; adds the node forces to F (12, 3)."""
    for j in range(24):
        n1, n2 = CABLE_NODES[j, 0], CABLE_NODES[j, 1]
        dx = P[n2, 0] - P[n1, 0]
        dy = P[n2, 1] - P[n1, 1]
        dz = P[n2, 2] - P[n1, 2]
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


@nb.njit(**_JIT)
def tensions(P, U, prm, pres):
    """Cable tensions (B, 24) N and node forces (B, 12, 3) N from node positions P and
    velocities U (B, 12, 3), packed parameters prm (B, NP) and pair pressures pres (B, 12) MPa."""
    nbat = P.shape[0]
    T = np.zeros((nbat, 24))
    F = np.zeros((nbat, 12, 3))
    act = np.empty(24)
    for b in range(nbat):
        a_exp = prm[b, _A]
        for j in range(24):
            act[j] = prm[b, _KG] * pres[b, CABLE_PAIR[j]]
        _cable_forces(P[b], U[b], prm[b, _K], prm[b, _L], a_exp, prm[b, _L] ** a_exp,
                      prm[b, _B], prm[b, _LMIN], act, F[b], T[b])
    return T, F


@nb.njit(**_JIT)
def _advance_one(b, x, v, q, w, anchor, stuck, prm, pres, kind, meta, hz, n_rec, every, dt,
                 out_x, out_q, status, fail_step):
    S = prm[b, _S]
    hl = 0.5 * S
    r = prm[b, _R]
    m = prm[b, _M]
    a_exp = prm[b, _A]
    K = prm[b, _K]
    Lr = prm[b, _L]
    La = Lr ** a_exp
    Bc = prm[b, _B]
    Lmin = prm[b, _LMIN]
    Kg = prm[b, _KG]
    grav = prm[b, _G]
    kn, cn, mu, kt, ct = prm[b, _KN], prm[b, _CN], prm[b, _MU], prm[b, _KT], prm[b, _CT]
    ds = prm[b, _DS]
    vmax2 = prm[b, _VMAX] ** 2
    It = m * (S * S / 12.0 + r * r / 4.0)
    Ia = m * r * r / 2.0
    dt_m = dt / m
    gyro = (Ia - It) / It
    dt_I = dt / It
    # robot-local copies of the state: small contiguous arrays the loop works on
    X = x[b].copy()
    V = v[b].copy()
    Q = q[b].copy()
    W = w[b].copy()
    AN = anchor[b].copy()
    ST = stuck[b].copy()
    P = np.empty((12, 3))
    U = np.empty((12, 3))
    F = np.empty((12, 3))
    Rm = np.empty((6, 3, 3))
    T = np.empty(24)
    act = np.empty(24)
    for j in range(24):
        act[j] = Kg * pres[b, CABLE_PAIR[j]]
    step = 0
    code = 0
    for rec in range(n_rec):
        for _ in range(every):
            # kinematics: rotation matrices (columns = body axes in world), node states
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
            _cable_forces(P, U, K, Lr, a_exp, La, Bc, Lmin, act, F, T)
            # ground: penalty normal force, stick spring capped by mu N (no creep)
            if kind > 0:
                for n in range(12):
                    nx, ny, nz, dist, ok = _terrain_contact(P[n, 0], P[n, 1], P[n, 2], kind, meta, hz)
                    if not ok:
                        code = 3
                        break
                    pen = r - dist
                    if pen <= 0.0:
                        ST[n] = False
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
                    ddx = P[n, 0] - AN[n, 0]
                    ddy = P[n, 1] - AN[n, 1]
                    ddz = P[n, 2] - AN[n, 2]
                    dn = nx * ddx + ny * ddy + nz * ddz
                    ddx -= dn * nx
                    ddy -= dn * ny
                    ddz -= dn * nz
                    dmag = math.sqrt(ddx * ddx + ddy * ddy + ddz * ddz)
                    cap = mu * fn
                    if kt * dmag > cap:  # sliding: drag the anchor along
                        sc = cap / (kt * dmag)
                        ddx *= sc
                        ddy *= sc
                        ddz *= sc
                        AN[n, 0] = P[n, 0] - ddx
                        AN[n, 1] = P[n, 1] - ddy
                        AN[n, 2] = P[n, 2] - ddz
                    utx, uty, utz = U[n, 0] - un * nx, U[n, 1] - un * ny, U[n, 2] - un * nz
                    ftx = -kt * ddx - ct * utx
                    fty = -kt * ddy - ct * uty
                    ftz = -kt * ddz - ct * utz
                    fmag2 = ftx * ftx + fty * fty + ftz * ftz
                    if fmag2 > cap * cap:
                        sc = cap / math.sqrt(fmag2)
                        ftx *= sc
                        fty *= sc
                        ftz *= sc
                    F[n, 0] += fn * nx + ftx
                    F[n, 1] += fn * ny + fty
                    F[n, 2] += fn * nz + ftz
                if code:
                    break
            # semi-implicit Euler: velocities from forces (eq. 3, Euler's equations with eq. 4)
            fastest = 0.0
            for i in range(6):
                na, nb_ = g_STRUT_A[i], g_STRUT_B[i]
                V[i, 0] += dt_m * (F[na, 0] + F[nb_, 0]) - dt * ds * V[i, 0]
                V[i, 1] += dt_m * (F[na, 1] + F[nb_, 1]) - dt * ds * V[i, 1]
                V[i, 2] += dt_m * (F[na, 2] + F[nb_, 2]) - dt * (grav + ds * V[i, 2])
                X[i, 0] += dt * V[i, 0]
                X[i, 1] += dt * V[i, 1]
                X[i, 2] += dt * V[i, 2]
                # body-frame torque: (0,0,L) x R^T f+ + (0,0,-L) x R^T f-
                gx = F[na, 0] - F[nb_, 0]
                gy = F[na, 1] - F[nb_, 1]
                gz = F[na, 2] - F[nb_, 2]
                d0 = Rm[i, 0, 0] * gx + Rm[i, 1, 0] * gy + Rm[i, 2, 0] * gz
                d1 = Rm[i, 0, 1] * gx + Rm[i, 1, 1] * gy + Rm[i, 2, 1] * gz
                w0, w1, w2 = W[i, 0], W[i, 1], W[i, 2]
                # Euler's equations, I = diag(It, It, Ia): w x I w = ((Ia-It) w1 w2, (It-Ia) w2 w0, 0)
                w0 += dt_I * (-hl * d1) - dt * (gyro * w1 * w2 + ds * w0)
                w1 += dt_I * (hl * d0) + dt * (gyro * w2 * w0 - ds * w1)
                w2 -= dt * ds * w2
                W[i, 0], W[i, 1], W[i, 2] = w0, w1, w2
                # q <- q * exp(w dt / 2) by its Taylor series (|w| dt / 2 << 1), renormalised
                h2 = 0.25 * dt * dt * (w0 * w0 + w1 * w1 + w2 * w2)
                c = 1.0 - h2 * (0.5 - h2 / 24.0)
                sn = 0.5 * dt * (1.0 - h2 * (1.0 / 6.0 - h2 / 120.0))
                ex, ey, ez = w0 * sn, w1 * sn, w2 * sn
                qw, qx, qy, qz = Q[i, 0], Q[i, 1], Q[i, 2], Q[i, 3]
                nw = qw * c - qx * ex - qy * ey - qz * ez
                nx_ = qw * ex + qx * c + qy * ez - qz * ey
                ny_ = qw * ey - qx * ez + qy * c + qz * ex
                nz_ = qw * ez + qx * ey - qy * ex + qz * c
                # exp(w dt/2) is a unit quaternion: |q| drifts by round-off only, so it is
                # renormalised once per recorded block (below), not every step
                Q[i, 0] = nw
                Q[i, 1] = nx_
                Q[i, 2] = ny_
                Q[i, 3] = nz_
                sp = V[i, 0] ** 2 + V[i, 1] ** 2 + V[i, 2] ** 2 + hl * hl * (w0 * w0 + w1 * w1)
                if sp > fastest or not sp == sp:
                    fastest = sp
            if code:
                break
            step += 1
            if not (fastest <= vmax2):
                code = 1 if not fastest == fastest else 2
                break
        if code:
            break
        for i in range(6):
            iq = 1.0 / math.sqrt(Q[i, 0] ** 2 + Q[i, 1] ** 2 + Q[i, 2] ** 2 + Q[i, 3] ** 2)
            for k in range(4):
                Q[i, k] *= iq
            for k in range(3):
                out_x[b, rec, i, k] = X[i, k]
            for k in range(4):
                out_q[b, rec, i, k] = Q[i, k]
    status[b] = code
    fail_step[b] = step
    x[b] = X
    v[b] = V
    q[b] = Q
    w[b] = W
    anchor[b] = AN
    stuck[b] = ST


@nb.njit(parallel=True, **_JIT)
def advance(x, v, q, w, anchor, stuck, prm, pres, kind, meta, hz, n_rec, every, dt,
            out_x, out_q, status, fail_step):
    """Advance all robots in place; see the module docstring. Arrays have a leading batch axis."""
    for b in nb.prange(x.shape[0]):
        _advance_one(b, x, v, q, w, anchor, stuck, prm, pres, kind, meta, hz, n_rec, every, dt,
                     out_x, out_q, status, fail_step)
