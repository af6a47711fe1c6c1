"""One robot alone, in SIMD lanes of its own: its struts, nodes and cables side by side (a batch
of one or two robots, `kernel.driver.alone`), its cables pneumatic muscles or twisted strings
(`kernel.strings`). The stages of `kernel.stages` are written for a group of
robots, one per lane; a lone robot would leave all lanes but one empty. Here the same per-item
functions (`ks.rotations`, `ks.node`, `ks.cable_force`, `kc.ground_node`, `ks.strut`) run with the
item as the lane: strut i in lane i of 8 (lanes 6, 7: padding), node STRUT_A[i] in lane i and
STRUT_B[i] in lane 8 + i of 16, cable j in lane j of 24. The only new code is the layout: the
cable ends and a node's four cables are picked from those lanes by whole-vector shuffles (`take`).
The pneumatic results are the same bits as in a group of lanes (tests/physics/test_kernel_lanes),
the twisted strings' the same to round-off (tests/physics/test_twisted).

The working arrays (SHAPES): struts X, V, W (1, 3, 8), Q (1, 4, 8), Rm (1, 3, 3, 8); nodes P, U,
G, AN (1, 3, 16), ST (1, 16), on (16,); cable ends E (4, 3, 16 -> 24: P1, P2, U1, U2), cable
forces TF (3, 24), the forces of a node's cables TN (4, 3, 16), their sums FN (3, 16); constants
C (NC, 24) (the robot's, in every lane), act (24,); end speeds (8,).
"""
from __future__ import annotations

import llvmlite.ir as llir
import numpy as np
from numba.core import types
from numba.extending import intrinsic

from . import contact as kc
from . import stages as ks
from . import strings as kst
from .compiling import jit
from .stages import DT_I, DT_M, GRAV, HL, INLINE, NC, R

SHAPES = ((1, 3, 8), (1, 3, 8), (1, 3, 8), (1, 4, 8), (1, 3, 3, 8), (1, 3, 16), (1, 3, 16),
          (1, 3, 16), (1, 3, 16), (1, 16), (16,), (4, 3, 24), (3, 24), (4, 3, 16), (3, 16),
          (NC, 24), (24,), (8,))

NODE_LANE = np.empty(12, np.int64)  # node -> its lane
NODE_LANE[ks.STRUT_A], NODE_LANE[ks.STRUT_B] = np.arange(6), 8 + np.arange(6)
STRUT_LANES = (0,) * 8  # the struts' lanes (kernel.stages' lane markers)
PAD = np.ones(16)  # 1.0 in the lanes that hold no node
PAD[NODE_LANE] = 0.0
END = NODE_LANE[ks.CABLE_NODES]  # (24, 2): the lanes of a cable's two nodes
SLOT = np.zeros((4, 16), np.int64)  # lane -> the node's four cables, in increasing order
SLOT_SIGN = np.zeros((4, 16))  # and the sign of their force on it (0 in the padding)
SLOT[:, NODE_LANE], SLOT_SIGN[:, NODE_LANE] = ks.NODE_CABLES.T, ks.NODE_CABLE_SIGN.T


def take(idx, n_src, rows):
    """A compiled function (dst, src): dst[r, j] = src[r, idx[j]] for r < rows, on C-contiguous
    float64 arrays with rows of n_src (src) and len(idx) (dst, a multiple of 8) values. One
    shuffle per register of 8 of dst (vpermt2pd), where a loop over j would gather element by
    element; LLVM splits a shuffle to a whole row of 16 or 24 into many small ones."""
    idx, m = [int(i) for i in idx], len(idx)
    assert m % 8 == 0, "whole registers of 8 float64"

    @intrinsic
    def shuffle(typingctx, dst, src):
        def codegen(context, builder, sig, args):
            f8 = llir.DoubleType()
            d = context.make_array(sig.args[0])(context, builder, args[0]).data
            s = context.make_array(sig.args[1])(context, builder, args[1]).data
            vs, v8 = llir.VectorType(f8, n_src), llir.VectorType(f8, 8)
            mask = {c: llir.Constant(llir.VectorType(llir.IntType(32), 8), idx[c:c + 8])
                    for c in range(0, m, 8)}
            at = lambda p, n: builder.gep(p, [context.get_constant(types.intp, n)])  # noqa: E731
            for r in range(rows):
                v = builder.load(builder.bitcast(at(s, r * n_src), vs.as_pointer()), align=8)
                for c in range(0, m, 8):
                    w = builder.shuffle_vector(v, llir.Constant(vs, llir.Undefined), mask[c])
                    builder.store(w, builder.bitcast(at(d, r * m + c), v8.as_pointer()), align=8)
            return context.get_dummy_value()
        return types.none(dst, src), codegen
    return shuffle


_END1, _END2 = take(END[:, 0], 16, 3), take(END[:, 1], 16, 3)
_SLOT0, _SLOT1, _SLOT2, _SLOT3 = (take(SLOT[c], 24, 3) for c in range(4))


@jit(**INLINE)
def _cable(j, E, C, act, TF, linear):
    TF[0, j], TF[1, j], TF[2, j] = ks.cable_force(
        E[1, 0, j] - E[0, 0, j], E[1, 1, j] - E[0, 1, j], E[1, 2, j] - E[0, 2, j],
        E[3, 0, j] - E[2, 0, j], E[3, 1, j] - E[2, 1, j], E[3, 2, j] - E[2, 2, j],
        C, j, act[j], linear)[1:]


@jit(**INLINE)
def _string(j, E, TF, A):
    """`_cable` of a twisted string (`kst.string`; its motor A: TH, OM, VO (1, 24), M (NM, 24))."""
    TF[0, j], TF[1, j], TF[2, j] = kst.string(
        E[1, 0, j] - E[0, 0, j], E[1, 1, j] - E[0, 1, j], E[1, 2, j] - E[0, 2, j],
        E[3, 0, j] - E[2, 0, j], E[3, 1, j] - E[2, 1, j], E[3, 2, j] - E[2, 2, j],
        A[0], A[1], A[2], A[3], 0, j)[1:]


@jit(**INLINE)
def _cables(P, U, E, C, act, linear, TF, TN, FN, strings):
    """FN (3, 16) <- the force (N) of each node's four cables, summed in cable order as
    `ks.cable_sum`: pneumatic muscles (`ks.cable_force`) if `strings` is None, else twisted
    strings (`kst.string`) with their motors `strings` (`kst.ALONE`)."""
    _END1(E[0], P[0])
    _END2(E[1], P[0])
    _END1(E[2], U[0])
    _END2(E[3], U[0])
    if strings is not None:
        for j in range(24):
            _string(j, E, TF, strings)
    elif linear:  # a constant inside each lane loop
        for j in range(24):
            _cable(j, E, C, act, TF, True)
    else:
        for j in range(24):
            _cable(j, E, C, act, TF, False)
    _SLOT0(TN[0], TF)
    _SLOT1(TN[1], TF)
    _SLOT2(TN[2], TF)
    _SLOT3(TN[3], TF)
    for k in range(3):
        for m in range(16):
            s = SLOT_SIGN[0, m] * TN[0, k, m]
            for c in range(1, 4):
                s += SLOT_SIGN[c, m] * TN[c, k, m]
            FN[k, m] = s


@jit(**INLINE)
def _ground(P, U, G, AN, ST, C, on, kind, meta, hz):
    """`kc.ground_forces` for the nodes of the robot, for the terrain kind (a constant). False
    if a node has no terrain under it: then, as there, the nodes after it (in node order) are
    left unchanged."""
    clear, ok_all = True, True
    for m in range(16):
        dist, ok = kc.terrain_contact(P[0, 0, m], P[0, 1, m], P[0, 2, m], kind, meta, hz)[3:]
        pad = PAD[m] != 0.0
        clear &= (ok & (C[R, m] - dist <= 0.0)) | pad
        ok_all &= ok | pad
    if clear:  # the usual case in the air: only G and ST change
        for m in range(16):
            G[0, 0, m], G[0, 1, m], G[0, 2, m], ST[0, m] = 0.0, 0.0, 0.0, 0.0
    elif ok_all:
        for m in range(16):
            on[m] = 1.0
            kc.ground_node(0, m, P, U, G, AN, ST, C, on, kind, meta, hz)
    else:  # rare: node by node, in node order
        prev = 1.0
        for n in range(12):
            on[NODE_LANE[n]] = prev
            kc.ground_node(0, NODE_LANE[n], P, U, G, AN, ST, C, on, kind, meta, hz)
            prev = on[NODE_LANE[n]]
    return ok_all


@jit(**INLINE)
def step(S, linear, kind, meta, hz, dt, strings):
    """One time step of dt s of the robot in S (the arrays of SHAPES), its cables pneumatic
    muscles or, unless `strings` is None, twisted strings with those motors (`_cables`). Returns
    the largest squared end speed of its struts (`ks.faster`), or -1.0 if a node has no terrain
    under it; the struts are then not moved."""
    X, V, W, Q, Rm, P, U, G, AN, ST, on, E, TF, TN, FN, C, act, fast = S
    ks.rotations(Q, Rm, STRUT_LANES)
    for i in range(8):
        ks.node(P, U, 0, i, X, V, W, Rm, 0, i, 1.0 * C[HL, i])
        ks.node(P, U, 0, 8 + i, X, V, W, Rm, 0, i, -1.0 * C[HL, i])
    _cables(P, U, E, C, act, linear, TF, TN, FN, strings)
    if kind == kc.PLANE:
        if not _ground(P, U, G, AN, ST, C, on, kc.PLANE, meta, hz):
            return -1.0
    elif kind == kc.HEIGHTFIELD:
        if not _ground(P, U, G, AN, ST, C, on, kc.HEIGHTFIELD, meta, hz):
            return -1.0
    for i in range(8):
        fast[i] = ks.strut(0, i, X, V, Q, W, Rm, C, dt, FN[0, i] + G[0, 0, i],
                           FN[1, i] + G[0, 1, i], FN[2, i] + G[0, 2, i], FN[0, 8 + i] + G[0, 0, 8 + i],
                           FN[1, 8 + i] + G[0, 1, 8 + i], FN[2, 8 + i] + G[0, 2, 8 + i])
    fastest = 0.0
    for i in range(6):
        fastest = ks.faster(fast[i], fastest)
    return fastest


@jit(**INLINE)
def load(S, X1, V1, W1, Q1, AN1, ST1, C1, act1):
    """S <- the robot in lane 0 of the group layout (kernel._run's arrays), its constants in
    every lane; G = 0. The padding struts (lanes 6, 7) rest at the origin, massless: forces and
    gravity do not move them."""
    X, V, W, Q, Rm, P, U, G, AN, ST, on, E, TF, TN, FN, C, act, fast = S
    for i in range(8):
        for k in range(3):
            X[0, k, i] = X1[i, k, 0] if i < 6 else 0.0
            V[0, k, i] = V1[i, k, 0] if i < 6 else 0.0
            W[0, k, i] = W1[i, k, 0] if i < 6 else 0.0
        for k in range(4):
            Q[0, k, i] = Q1[i, k, 0] if i < 6 else (1.0 if k == 0 else 0.0)
    for m in range(16):
        for k in range(3):
            AN[0, k, m], G[0, k, m] = 0.0, 0.0
        ST[0, m] = 0.0
    for n in range(12):
        for k in range(3):
            AN[0, k, NODE_LANE[n]] = AN1[n, k, 0]
        ST[0, NODE_LANE[n]] = ST1[n, 0]
    for r in range(NC):
        for j in range(24):
            C[r, j] = C1[r, 0]
    for j in range(6, 8):
        C[DT_M, j], C[DT_I, j], C[GRAV, j] = 0.0, 0.0, 0.0
    for j in range(24):
        act[j] = act1[j, 0]


@jit(**INLINE)
def store(S, X1, V1, W1, Q1, AN1, ST1):
    """The state of the robot in S -> lane 0 of the group layout (the inverse of `load`)."""
    X, V, W, Q, Rm, P, U, G, AN, ST, on, E, TF, TN, FN, C, act, fast = S
    for i in range(6):
        for k in range(3):
            X1[i, k, 0], V1[i, k, 0], W1[i, k, 0] = X[0, k, i], V[0, k, i], W[0, k, i]
        for k in range(4):
            Q1[i, k, 0] = Q[0, k, i]
    for n in range(12):
        for k in range(3):
            AN1[n, k, 0] = AN[0, k, NODE_LANE[n]]
        ST1[n, 0] = ST[0, NODE_LANE[n]]
