"""The ground contact stage of the compiled kernel (`kernel/__init__.py`; the paper's contact
model C1-C4), laid out as `kernel.stages` (lane index last, branch-free lane loops):
`terrain_contact` and `_stick_force` are scalar per-robot rules, `ground_node` one node of one
lane, `ground_forces` every node of a group of lanes. `Terrain.height_and_normal` is the NumPy
twin of `terrain_contact` (tests/physics/test_twins.py).
"""
from __future__ import annotations

import math

from ..terrain import KINDS
from .compiling import jit
from .stages import CN, CT, EXACT, INLINE, KN, KT, MU, R

NO_TERRAIN, PLANE, HEIGHTFIELD = KINDS["none"], KINDS["plane"], KINDS["heightfield"]


@jit(**EXACT)
def terrain_contact(px, py, pz, kind, meta, hz):
    """Unit normal (nx, ny, nz), signed distance (m) of p to the triangle plane under it, ok flag
    (False off the edge of a HEIGHTFIELD, or if p is NaN; the other values are then meaningless).
    meta (7,) = normal, offset, x0, y0, spacing; hz (nx, ny) m. Branch-free for HEIGHTFIELD."""
    if kind == PLANE:
        return meta[0], meta[1], meta[2], meta[0] * px + meta[1] * py + meta[2] * pz - meta[3], True
    h = meta[6]
    u = (px - meta[4]) / h
    v = (py - meta[5]) / h
    ok = (u >= 0.0) & (u < hz.shape[0] - 1) & (v >= 0.0) & (v < hz.shape[1] - 1)
    i = int(math.floor(u if ok else 0.0))
    j = int(math.floor(v if ok else 0.0))
    up = (u - i) + (v - j) > 1.0  # the upper triangle of cell (i, j)
    c = 1 if up else 0
    z0, za, zb = hz[i + c, j + c], hz[i + 1, j], hz[i, j + 1]
    ax = h * (zb - z0) if up else -h * (za - z0)
    ay = h * (za - z0) if up else -h * (zb - z0)
    az = h * h
    x0, y0 = meta[4] + (i + c) * h, meta[5] + (j + c) * h
    nn = math.sqrt(ax * ax + ay * ay + az * az)
    ax, ay, az = ax / nn, ay / nn, az / nn
    return ax, ay, az, ax * (px - x0) + ay * (py - y0) + az * (pz - z0), ok


@jit(**EXACT)
def _stick_force(ddx, ddy, ddz, utx, uty, utz, kt, ct, cap):
    """(C4) friction force (N) of the stick spring k_t (N/m) and damper c_t (N s/m) from the
    tangential displacement dd (m) and velocity ut (m/s), scaled down to |f_t| = cap (N)."""
    ftx, fty, ftz = -kt * ddx - ct * utx, -kt * ddy - ct * uty, -kt * ddz - ct * utz
    fmag2 = ftx * ftx + fty * fty + ftz * ftz
    sc = cap / math.sqrt(fmag2) if fmag2 > cap * cap else 1.0
    return ftx * sc, fty * sc, ftz * sc


@jit(**EXACT)
def ground_node(n, l, P, U, G, AN, ST, C, on, kind, meta, hz):
    """`ground_forces` for node n of lane l."""
    px, py, pz = P[n, 0, l], P[n, 1, l], P[n, 2, l]
    nx, ny, nz, dist, ok = terrain_contact(px, py, pz, kind, meta, hz)
    okl = (on[l] != 0.0) & ok
    on[l] = 1.0 if okl else 0.0
    pen = C[R, l] - dist
    un = nx * U[n, 0, l] + ny * U[n, 1, l] + nz * U[n, 2, l]
    fn = C[KN, l] * pen - C[CN, l] * un
    touch = okl & (not pen <= 0.0) & (not fn <= 0.0)
    new = ST[n, l] == 0.0  # a contact begins: the anchor is the node
    ax = px if new else AN[n, 0, l]
    ay = py if new else AN[n, 1, l]
    az = pz if new else AN[n, 2, l]
    ddx, ddy, ddz = px - ax, py - ay, pz - az
    dn = nx * ddx + ny * ddy + nz * ddz
    ddx, ddy, ddz = ddx - dn * nx, ddy - dn * ny, ddz - dn * nz
    dmag = math.sqrt(ddx * ddx + ddy * ddy + ddz * ddz)
    kt, cap = C[KT, l], C[MU, l] * fn
    slide = kt * dmag > cap  # sliding: drag the anchor along
    sc = cap / (kt * dmag) if slide else 1.0
    ddx, ddy, ddz = ddx * sc, ddy * sc, ddz * sc
    ftx, fty, ftz = _stick_force(ddx, ddy, ddz, U[n, 0, l] - un * nx, U[n, 1, l] - un * ny,
                                 U[n, 2, l] - un * nz, kt, C[CT, l], cap)
    # the updates as selects, not branches: the lane loop vectorises
    AN[n, 0, l] = (px - ddx if slide else ax) if touch else AN[n, 0, l]
    AN[n, 1, l] = (py - ddy if slide else ay) if touch else AN[n, 1, l]
    AN[n, 2, l] = (pz - ddz if slide else az) if touch else AN[n, 2, l]
    G[n, 0, l] = fn * nx + ftx if touch else 0.0
    G[n, 1, l] = fn * ny + fty if touch else 0.0
    G[n, 2, l] = fn * nz + ftz if touch else 0.0
    ST[n, l] = (1.0 if touch else 0.0) if okl else ST[n, l]


@jit(**INLINE)
def _ground_at(n, P, U, G, AN, ST, C, on, kind, meta, hz, lanes):
    """`ground_forces` at node n, for the terrain kind (a constant: PLANE or HEIGHTFIELD). When
    the node is above the terrain in every lane (the usual case), only G and ST change."""
    clear = True
    for l in range(len(lanes)):
        dist, ok = terrain_contact(P[n, 0, l], P[n, 1, l], P[n, 2, l], kind, meta, hz)[3:]
        clear &= ok & (C[R, l] - dist <= 0.0)
    if clear:
        for l in range(len(lanes)):
            G[n, 0, l], G[n, 1, l], G[n, 2, l] = 0.0, 0.0, 0.0
            ST[n, l] = 0.0 if on[l] != 0.0 else ST[n, l]
    else:
        for l in range(len(lanes)):
            ground_node(n, l, P, U, G, AN, ST, C, on, kind, meta, hz)


@jit(**INLINE)
def ground_forces(P, U, G, AN, ST, C, on, kind, meta, hz, lanes):
    """The contact force G (12, 3, L) N, f_n n + f_t at a node touching the terrain, else 0:
    (C1) penetration of the end sphere, (C2) penalty normal force, (C3) stick displacement from
    the anchor AN (12, 3, L) m, set when a contact begins (ST (12, L) 0/1) and dragged along when
    sliding, (C4) by `_stick_force`. on (L,) is set to 0 in a lane with no terrain under a node;
    that lane's later nodes are then left unchanged."""
    for n in range(12):
        if kind == PLANE:  # the terrain kind is a constant inside each lane loop
            _ground_at(n, P, U, G, AN, ST, C, on, PLANE, meta, hz, lanes)
        else:
            _ground_at(n, P, U, G, AN, ST, C, on, HEIGHTFIELD, meta, hz, lanes)
