"""The compiled time loop of robots with twisted-string actuators (`actuator` (T1)-(T5),
docs/design.md §10): `kernel.advance`'s one driver (`kernel.driver`), in the same layouts (groups
of LANES robots side by side; a batch under WIDE_FROM robots one robot per thread, its struts,
nodes and cables side by side), with the cable stage of `kernel.strings`: the tension of each cable
from its node states and its motor's angle and speed, then the motor's step under that tension.
"""

from __future__ import annotations

import numba as nb

from . import stages as ks
from .compiling import callees_first, jit
from .driver import LANES, WIDE_FROM, check_levels, group_one, group_wide
from .strings import NM

__all__ = ["NM", "advance"]


@jit(parallel=True, nogil=True, **ks.JIT)
def _advance(x, v, q, w, anchor, stuck, theta, omega, prm, mprm, volts, kind, meta, hz, n_rec,
             every, dt, out_x, out_q, status, fail_step):
    """`advance`: the groups in parallel threads."""
    B = x.shape[0]
    motors = (theta, omega, mprm, volts)
    if B < WIDE_FROM:
        for b in nb.prange(B):
            group_one(b, x, v, q, w, anchor, stuck, prm, volts, kind, meta, hz, n_rec, every, dt,
                      out_x, out_q, status, fail_step, motors)
    else:
        for g in nb.prange((B + LANES - 1) // LANES):
            group_wide(g, x, v, q, w, anchor, stuck, prm, volts, kind, meta, hz, n_rec, every, dt,
                       out_x, out_q, status, fail_step, motors)


def advance(x, v, q, w, anchor, stuck, theta, omega, prm, mprm, volts, kind, meta, hz, n_rec,
            every, dt, out_x, out_q, status, fail_step):
    """Advance all robots and their motors in place: as `kernel.advance`, with the motor angles
    theta and speeds omega (B, 24) rad, rad/s, their constants mprm (B, NM)
    (`TwistedString.pack`, at this dt) and the voltages volts (B, 24) V, one per cable. A read-only mprm
    (`pack` of one robot is a view) is copied: one compiled signature for every batch."""
    check_levels(volts, x.shape[0])
    if not mprm.flags.writeable:
        mprm = mprm.copy()
    args = (x, v, q, w, anchor, stuck, theta, omega, prm, mprm, volts, kind, meta, hz, n_rec,
            every, dt, out_x, out_q, status, fail_step)
    if not _advance.overloads:
        callees_first(_advance, (group_one, group_wide),
                      (x, v, q, w, anchor, stuck, prm, volts, *args[11:], (theta, omega, mprm, volts)))
    _advance(*args)
