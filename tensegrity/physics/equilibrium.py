"""Batched free-mode static equilibrium by Newton's method: many robots (designs x pairs x
levels) at once, compiled with numba, one robot per thread lane (docs/design.md §3, (S1)).

Each robot is six rigid struts, strut s given by its centre x_s (3,) m and unit axis c_s (3,),
nodes x_s +- (S/2) c_s (eq. 4). The cables are the linear springs (S1) of the law at rest,
tension k max(0, l - l*) (k N/m, l* m per cable, `actuator.spring`; exact for a = 1 at every
length, as l* >= Lmin). Newton minimises their energy U over the 30 coordinates (x_s, and two
rotation angles theta_s of c_s in its tangent plane, retraction c <- (c + E theta) / |c + E theta|)
with the analytic gradient and Hessian: the node Hessian of a taut cable is
k u u^T + (t / l)(I - u u^T), mapped through the strut Jacobian, plus the curvature term
-(S/2) sign (g_node . c) I of the retraction. The six rigid motions (a null space of U) are
removed by adding alpha R R^T (R: the rigid modes, alpha = trace H / 30), which leaves the
solution unchanged (the gradient is orthogonal to them). A step that raises U is halved.

Independent of `physics.statics` (BFGS on a different parametrisation), which tests use as the
oracle. Converged when the largest step is below `tol` (m, and rad); that step is taken: Newton
converges quadratically, leaving an error ~ 3 step^2 / m (measured on 60 designs x 12 pairs x 12
levels against tol = 1e-11: 3e-12 m at tol = 1e-6, 3e-16 m at the default 1e-8).
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numba as nb
import numpy as np

from . import topology as topo

_NS, _SG, _CAB = topo.NODE_STRUT, topo.NODE_SIGN, topo.CABLES
_NV = 30  # unknowns: per strut 3 centre coordinates and 2 angles


@nb.njit(cache=True)
def _basis(C, E):
    """E (6, 3, 2) <- per strut an orthonormal basis of the plane normal to its unit axis C[s]."""
    for s in range(6):
        c0, c1, c2 = C[s, 0], C[s, 1], C[s, 2]
        # e1 = c x a, a the coordinate axis least aligned with c
        if abs(c0) <= abs(c1) and abs(c0) <= abs(c2):
            e = (0.0, c2, -c1)
        elif abs(c1) <= abs(c2):
            e = (-c2, 0.0, c0)
        else:
            e = (c1, -c0, 0.0)
        n = np.sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2])
        a0, a1, a2 = e[0] / n, e[1] / n, e[2] / n
        E[s, 0, 0], E[s, 1, 0], E[s, 2, 0] = a0, a1, a2
        E[s, 0, 1], E[s, 1, 1], E[s, 2, 1] = c1 * a2 - c2 * a1, c2 * a0 - c0 * a2, c0 * a1 - c1 * a0


@nb.njit(cache=True)
def _nodes(X, C, h, NS, SG, p):
    for i in range(12):
        for d in range(3):
            p[i, d] = X[NS[i], d] + SG[i] * h * C[NS[i], d]


@nb.njit(cache=True)
def _energy(X, C, h, k, ls, NS, SG, CAB, p):
    """Cable energy U (J) of centres X (6, 3) m and unit axes C (6, 3); p (12, 3) work."""
    _nodes(X, C, h, NS, SG, p)
    U = 0.0
    for j in range(CAB.shape[0]):
        a, b = CAB[j, 0], CAB[j, 1]
        e0, e1, e2 = p[b, 0] - p[a, 0], p[b, 1] - p[a, 1], p[b, 2] - p[a, 2]
        s = np.sqrt(e0 * e0 + e1 * e1 + e2 * e2) - ls[j]
        if s > 0.0:
            U += 0.5 * k[j] * s * s
    return U


@nb.njit(cache=True)
def _assemble(X, C, E, h, k, ls, NS, SG, CAB, g, H, p, gp, J, KJ):
    """g (30,) <- dU/d(x, theta), H (30, 30) <- the Hessian (module docstring), at theta = 0;
    p, gp (12, 3), J (12, 3, 5), KJ (3, 5) work."""
    _nodes(X, C, h, NS, SG, p)
    for i in range(12):  # J[i] = d node i / d (x, theta) of its strut
        for r in range(3):
            for q in range(3):
                J[i, r, q] = 1.0 if r == q else 0.0
            J[i, r, 3] = SG[i] * h * E[NS[i], r, 0]
            J[i, r, 4] = SG[i] * h * E[NS[i], r, 1]
    gp[:] = 0.0
    H[:] = 0.0
    for j in range(CAB.shape[0]):
        a, b = CAB[j, 0], CAB[j, 1]
        e0, e1, e2 = p[b, 0] - p[a, 0], p[b, 1] - p[a, 1], p[b, 2] - p[a, 2]
        ln = np.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
        s = ln - ls[j]
        if s <= 0.0:
            continue  # slack: no force, no stiffness (cables never push)
        u = (e0 / ln, e1 / ln, e2 / ln)
        t = k[j] * s
        for d in range(3):
            gp[b, d] += t * u[d]
            gp[a, d] -= t * u[d]
        ka, kb = k[j] - t / ln, t / ln  # node stiffness Kc = ka u u^T + kb I
        for n2 in (a, b):
            for r in range(3):  # KJ = Kc J[n2]
                for q in range(5):
                    KJ[r, q] = kb * J[n2, r, q] + ka * u[r] * (
                        u[0] * J[n2, 0, q] + u[1] * J[n2, 1, q] + u[2] * J[n2, 2, q]
                    )
            o2 = 5 * NS[n2]
            for n1 in (a, b):
                sgn = 1.0 if n1 == n2 else -1.0
                o1 = 5 * NS[n1]
                for q1 in range(5):
                    for q2 in range(5):
                        H[o1 + q1, o2 + q2] += sgn * (
                            J[n1, 0, q1] * KJ[0, q2] + J[n1, 1, q1] * KJ[1, q2] + J[n1, 2, q1] * KJ[2, q2]
                        )
    g[:] = 0.0
    for i in range(12):
        o = 5 * NS[i]
        for q in range(5):
            g[o + q] += J[i, 0, q] * gp[i, 0] + J[i, 1, q] * gp[i, 1] + J[i, 2, q] * gp[i, 2]
        c = NS[i]
        curv = SG[i] * h * (gp[i, 0] * C[c, 0] + gp[i, 1] * C[c, 1] + gp[i, 2] * C[c, 2])
        H[o + 3, o + 3] -= curv
        H[o + 4, o + 4] -= curv


@nb.njit(cache=True)
def _gauge(X, C, E, H, r):
    """H += alpha R R^T: R the six rigid motions (unit columns), alpha = trace(H) / 30; r (30,) work."""
    alpha = 0.0
    for i in range(_NV):
        alpha += H[i, i] / _NV
    xc = np.zeros(3)
    for s in range(6):
        for d in range(3):
            xc[d] += X[s, d] / 6.0
    w, v = np.zeros(3), np.zeros(3)
    for m in range(6):  # translations along, then rotations about the centroid around, axis m % 3
        for s in range(6):
            o = 5 * s
            if m < 3:
                for d in range(3):
                    r[o + d] = 1.0 if d == m else 0.0
                r[o + 3] = r[o + 4] = 0.0
            else:  # e x (x - xc), and E^T (e x c), e the unit vector of axis m - 3
                d1, d2 = (m - 2) % 3, (m - 1) % 3
                for d in range(3):
                    w[d] = X[s, d] - xc[d]
                    r[o + d] = -w[d2] if d == d1 else (w[d1] if d == d2 else 0.0)
                    v[d] = -C[s, d2] if d == d1 else (C[s, d1] if d == d2 else 0.0)
                for q in range(2):
                    r[o + 3 + q] = E[s, 0, q] * v[0] + E[s, 1, q] * v[1] + E[s, 2, q] * v[2]
        nr = 0.0
        for i in range(_NV):
            nr += r[i] * r[i]
        nr = np.sqrt(nr)
        for i in range(_NV):
            for q in range(_NV):
                H[i, q] += alpha * r[i] * r[q] / (nr * nr)


@nb.njit(cache=True)
def _cholesky_solve(A, b, out):
    """out <- A^-1 b for a symmetric positive definite A (n, n), in place in A; False if A is not."""
    n = b.size
    for j in range(n):
        d = A[j, j]
        for q in range(j):
            d -= A[j, q] * A[j, q]
        if not d > 0.0:
            return False
        A[j, j] = np.sqrt(d)
        for i in range(j + 1, n):
            v = A[i, j]
            for q in range(j):
                v -= A[i, q] * A[j, q]
            A[i, j] = v / A[j, j]
    for i in range(n):
        v = b[i]
        for q in range(i):
            v -= A[i, q] * out[q]
        out[i] = v / A[i, i]
    for i in range(n - 1, -1, -1):
        v = out[i]
        for q in range(i + 1, n):
            v -= A[q, i] * out[q]
        out[i] = v / A[i, i]
    return True


@nb.njit(cache=True)
def _move(X, C, E, step, frac, Xn, Cn):
    """Xn, Cn <- the struts moved by frac * step (centres; axes by the retraction)."""
    for s in range(6):
        o = 5 * s
        nn = 0.0
        for d in range(3):
            Xn[s, d] = X[s, d] + frac * step[o + d]
            Cn[s, d] = C[s, d] + frac * (E[s, d, 0] * step[o + 3] + E[s, d, 1] * step[o + 4])
            nn += Cn[s, d] * Cn[s, d]
        nn = np.sqrt(nn)
        for d in range(3):
            Cn[s, d] /= nn


@nb.njit(cache=True)
def _one(X, C, h, k, ls, NS, SG, CAB, tol, maxit):
    """Newton on one robot, X and C updated in place; returns the iterations (-1: no convergence)."""
    E = np.empty((6, 3, 2))
    g, H, A, step, r = np.empty(_NV), np.empty((_NV, _NV)), np.empty((_NV, _NV)), np.empty(_NV), np.empty(_NV)
    Xn, Cn, p, gp = np.empty((6, 3)), np.empty((6, 3)), np.empty((12, 3)), np.empty((12, 3))
    J, KJ, mg = np.empty((12, 3, 5)), np.empty((3, 5)), np.empty(_NV)
    for it in range(maxit):
        _basis(C, E)
        _assemble(X, C, E, h, k, ls, NS, SG, CAB, g, H, p, gp, J, KJ)
        _gauge(X, C, E, H, r)
        tr = 0.0
        for i in range(_NV):
            mg[i] = -g[i]
            tr += H[i, i]
        shift = 0.0
        for _ in range(30):  # Levenberg shift where H is not positive definite
            for i in range(_NV):
                for q in range(_NV):
                    A[i, q] = H[i, q]
                A[i, i] += shift
            if _cholesky_solve(A, mg, step):
                break
            shift = 1e-6 * tr if shift == 0.0 else 10.0 * shift
        big = 0.0
        for i in range(_NV):
            big = max(big, abs(step[i]))
        frac = 1.0
        if big > 1e3 * tol:  # far from the solution: halve a step that raises U
            U0 = _energy(X, C, h, k, ls, NS, SG, CAB, p)
            for _ in range(40):
                _move(X, C, E, step, frac, Xn, Cn)
                if _energy(Xn, Cn, h, k, ls, NS, SG, CAB, p) <= U0:
                    break
                frac *= 0.5
        _move(X, C, E, step, frac, Xn, Cn)
        for s in range(6):
            for d in range(3):
                X[s, d], C[s, d] = Xn[s, d], Cn[s, d]
        if big < tol:  # the last step: Newton leaves an error ~ big^2 / (length scale)
            return it + 1
    return -1


@nb.njit(cache=True, nogil=True)
def _batch(X, C, h, k, ls, NS, SG, CAB, tol, maxit, iters):
    for b in range(X.shape[0]):
        iters[b] = _one(X[b], C[b], h[b], k[b], ls[b], NS, SG, CAB, tol, maxit)


def solve(
    centres: np.ndarray,
    axes: np.ndarray,
    strut_length: np.ndarray,
    k: np.ndarray,
    lstar: np.ndarray,
    tol: float = 1e-8,
    maxit: int = 60,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Equilibria of B robots from the start centres (B, 6, 3) m and axes (B, 6, 3) (normalised
    here), strut lengths (B,) m and cable laws k (B, 24) N/m, l* (B, 24) m (`actuator.spring`).
    Returns centres (B, 6, 3) m, unit axes (B, 6, 3) and the Newton iterations (B,) (-1: not
    converged to `tol` m and rad in `maxit`)."""
    X = np.array(centres, dtype=float, order="C")
    C = np.array(axes, dtype=float, order="C")
    C /= np.linalg.norm(C, axis=-1, keepdims=True)
    B = X.shape[0]
    h = np.array(np.broadcast_to(0.5 * np.asarray(strut_length, float), (B,)), order="C")
    k = np.array(np.broadcast_to(k, (B, topo.N_CABLES)), dtype=float, order="C")
    ls = np.array(np.broadcast_to(lstar, (B, topo.N_CABLES)), dtype=float, order="C")
    iters = np.empty(B, np.int64)
    # numba's threads: the compiled loop releases the GIL, so Python threads share out the batch
    cuts = np.linspace(0, B, min(nb.get_num_threads(), max(1, B // 64)) + 1).astype(int)

    def run(a: int, b: int) -> None:
        _batch(X[a:b], C[a:b], h[a:b], k[a:b], ls[a:b], _NS, _SG, _CAB, float(tol), int(maxit), iters[a:b])

    if cuts.size == 2:
        run(0, B)
    else:
        with ThreadPoolExecutor(cuts.size - 1) as pool:
            list(pool.map(run, cuts[:-1], cuts[1:]))
    return X, C, iters


def struts(nodes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Strut centres (..., 6, 3) m and unit axes (..., 6, 3) of node positions (..., 12, 3) m."""
    a, b = nodes[..., topo.STRUTS[:, 0], :], nodes[..., topo.STRUTS[:, 1], :]
    d = a - b
    return 0.5 * (a + b), d / np.linalg.norm(d, axis=-1, keepdims=True)


def nodes(centres: np.ndarray, axes: np.ndarray, strut_length: np.ndarray) -> np.ndarray:
    """Node positions (..., 12, 3) m of struts (centres, unit axes (..., 6, 3)) of length (...,) m (eq. 4)."""
    h = 0.5 * np.asarray(strut_length, float)[..., None, None]
    return centres[..., _NS, :] + _SG[:, None] * h * axes[..., _NS, :]
