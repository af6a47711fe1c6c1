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

from . import geometry as g
from .params import IDX

# Topology as kernel constants: node -> (strut, sign), cable -> nodes, cable -> pair.
NODE_STRUT = np.empty(g.N_NODES, np.int64)
NODE_SIGN = np.empty(g.N_NODES, np.float64)
for _s, (_a, _b) in enumerate(g.STRUTS):
    NODE_STRUT[_a], NODE_SIGN[_a] = _s, 1.0
    NODE_STRUT[_b], NODE_SIGN[_b] = _s, -1.0
CABLE_NODES = np.ascontiguousarray(g.CABLES.astype(np.int64))
CABLE_PAIR = np.ascontiguousarray(g.CABLE_PAIR.astype(np.int64))
g_STRUT_A = np.ascontiguousarray(g.STRUTS[:, 0].astype(np.int64))
g_STRUT_B = np.ascontiguousarray(g.STRUTS[:, 1].astype(np.int64))

_S, _R, _M, _A, _K, _L, _B, _LMIN, _KG, _G = (IDX[k] for k in (
    "strut_length", "strut_radius", "strut_mass", "cable_exponent", "cable_stiffness",
    "cable_rest_length", "cable_damping", "muscle_min_length", "muscle_gain", "gravity"))
_KN, _CN, _MU, _KT, _CT, _DS, _VMAX = (IDX[k] for k in (
    "ground_stiffness", "ground_damping", "friction", "friction_stiffness", "friction_damping",
    "strut_damping", "max_speed"))


@nb.njit(cache=True, inline="always")
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


@nb.njit(cache=True)
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


@nb.njit(cache=True)
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


@nb.njit(cache=True)
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
    P = np.empty((12, 3))
    U = np.empty((12, 3))
    F = np.empty((12, 3))
    Rm = np.empty((6, 3, 3))
    T = np.empty(24)
    act = np.empty(24)
    for j in range(24):
        act[j] = Kg * pres[b, CABLE_PAIR[j]]
    step = 0
    for rec in range(n_rec):
        for _ in range(every):
            # kinematics: rotation matrices (columns = body axes in world), node states
            for i in range(6):
                qw, qx, qy, qz = q[b, i, 0], q[b, i, 1], q[b, i, 2], q[b, i, 3]
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
                w0, w1 = w[b, i, 0], w[b, i, 1]
                for k in range(3):
                    P[n, k] = x[b, i, k] + sg * Rm[i, k, 2]
                    # d c / dt = R (w x e3) = R (w1, -w0, 0)
                    U[n, k] = v[b, i, k] + sg * (Rm[i, k, 0] * w1 - Rm[i, k, 1] * w0)
                    F[n, k] = 0.0
            _cable_forces(P, U, K, Lr, a_exp, La, Bc, Lmin, act, F, T)
            # ground: penalty normal force, stick spring capped by mu N (no creep)
            if kind > 0:
                for n in range(12):
                    nx, ny, nz, dist, ok = _terrain_contact(P[n, 0], P[n, 1], P[n, 2], kind, meta, hz)
                    if not ok:
                        status[b] = 3
                        fail_step[b] = step
                        return
                    pen = r - dist
                    if pen <= 0.0:
                        stuck[b, n] = False
                        continue
                    un = nx * U[n, 0] + ny * U[n, 1] + nz * U[n, 2]
                    fn = kn * pen - cn * un
                    if fn <= 0.0:
                        stuck[b, n] = False
                        continue
                    if not stuck[b, n]:
                        for k in range(3):
                            anchor[b, n, k] = P[n, k]
                        stuck[b, n] = True
                    ddx = P[n, 0] - anchor[b, n, 0]
                    ddy = P[n, 1] - anchor[b, n, 1]
                    ddz = P[n, 2] - anchor[b, n, 2]
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
                        anchor[b, n, 0] = P[n, 0] - ddx
                        anchor[b, n, 1] = P[n, 1] - ddy
                        anchor[b, n, 2] = P[n, 2] - ddz
                    utx, uty, utz = U[n, 0] - un * nx, U[n, 1] - un * ny, U[n, 2] - un * nz
                    ftx = -kt * ddx - ct * utx
                    fty = -kt * ddy - ct * uty
                    ftz = -kt * ddz - ct * utz
                    fmag = math.sqrt(ftx * ftx + fty * fty + ftz * ftz)
                    if fmag > cap:
                        sc = cap / fmag
                        ftx *= sc
                        fty *= sc
                        ftz *= sc
                    F[n, 0] += fn * nx + ftx
                    F[n, 1] += fn * ny + fty
                    F[n, 2] += fn * nz + ftz
            # semi-implicit Euler: velocities from forces (eq. 3, Euler's equations with eq. 4)
            fastest = 0.0
            for i in range(6):
                na, nb_ = g_STRUT_A[i], g_STRUT_B[i]
                fx = F[na, 0] + F[nb_, 0]
                fy = F[na, 1] + F[nb_, 1]
                fz = F[na, 2] + F[nb_, 2] - m * grav
                v[b, i, 0] += dt * (fx / m - ds * v[b, i, 0])
                v[b, i, 1] += dt * (fy / m - ds * v[b, i, 1])
                v[b, i, 2] += dt * (fz / m - ds * v[b, i, 2])
                for k in range(3):
                    x[b, i, k] += dt * v[b, i, k]
                # body-frame torque: (0,0,L) x R^T f+ + (0,0,-L) x R^T f-
                gx = F[na, 0] - F[nb_, 0]
                gy = F[na, 1] - F[nb_, 1]
                gz = F[na, 2] - F[nb_, 2]
                d0 = Rm[i, 0, 0] * gx + Rm[i, 1, 0] * gy + Rm[i, 2, 0] * gz
                d1 = Rm[i, 0, 1] * gx + Rm[i, 1, 1] * gy + Rm[i, 2, 1] * gz
                t0, t1 = -hl * d1, hl * d0
                w0, w1, w2 = w[b, i, 0], w[b, i, 1], w[b, i, 2]
                w[b, i, 0] = w0 + dt * ((t0 - w1 * w2 * (Ia - It)) / It - ds * w0)
                w[b, i, 1] = w1 + dt * ((t1 - w2 * w0 * (It - Ia)) / It - ds * w1)
                w[b, i, 2] = w2 - dt * ds * w2
                # q <- q * exp(w dt / 2), then renormalise
                w0, w1, w2 = w[b, i, 0], w[b, i, 1], w[b, i, 2]
                wn = math.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
                if wn > 0.0:
                    half = 0.5 * wn * dt
                    c = math.cos(half)
                    sn = math.sin(half) / wn
                    ex, ey, ez = w0 * sn, w1 * sn, w2 * sn
                    qw, qx, qy, qz = q[b, i, 0], q[b, i, 1], q[b, i, 2], q[b, i, 3]
                    nw = qw * c - qx * ex - qy * ey - qz * ez
                    nx_ = qw * ex + qx * c + qy * ez - qz * ey
                    ny_ = qw * ey - qx * ez + qy * c + qz * ex
                    nz_ = qw * ez + qx * ey - qy * ex + qz * c
                    qn = math.sqrt(nw * nw + nx_ * nx_ + ny_ * ny_ + nz_ * nz_)
                    q[b, i, 0] = nw / qn
                    q[b, i, 1] = nx_ / qn
                    q[b, i, 2] = ny_ / qn
                    q[b, i, 3] = nz_ / qn
                sp = (v[b, i, 0] ** 2 + v[b, i, 1] ** 2 + v[b, i, 2] ** 2
                      + hl * hl * (w0 * w0 + w1 * w1))
                if sp > fastest or not sp == sp:
                    fastest = sp
            step += 1
            if not (fastest <= vmax2):
                status[b] = 1 if not fastest == fastest else 2
                fail_step[b] = step
                return
        for i in range(6):
            for k in range(3):
                out_x[b, rec, i, k] = x[b, i, k]
            for k in range(4):
                out_q[b, rec, i, k] = q[b, i, k]



@nb.njit(cache=True, parallel=True)
def advance(x, v, q, w, anchor, stuck, prm, pres, kind, meta, hz, n_rec, every, dt,
            out_x, out_q, status, fail_step):
    """Advance all robots in place; see the module docstring. Arrays have a leading batch axis."""
    for b in nb.prange(x.shape[0]):
        _advance_one(b, x, v, q, w, anchor, stuck, prm, pres, kind, meta, hz, n_rec, every, dt,
                     out_x, out_q, status, fail_step)
