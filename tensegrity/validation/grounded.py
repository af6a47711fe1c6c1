"""Check 4: the paper's assumption (III.A-B) measured. The pipeline's sweep is repeated in the
grounded mode (gravity, ground, friction) and compared with the free-mode nominal CoG: how far
gravity and contact move the CoG while the robot stands, and whether it rolls where the free
workspace says it should. Numbers and statuses only; `validation.summary` words them."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..physics import frames
from ..physics import topology as topo
from ..physics.params import Params
from ..physics.topology import CONTACTS
from ..physics.twisted import TwistedString
from ..workspace.nominal import Nominal
from ..workspace.sweep import SweepSetup
from .common import N_CONTACTS, SKIP, CheckSettings, Result, status
from .nominals import common_levels, simulate_nominal


@dataclass(frozen=True)
class GroundedComparison:
    """A grounded sweep against the free one, per pair (n,) and level (P,): shift (n, P, 3) m
    grounded minus free nominal CoG and margin_change (n, P) m, NaN from the first rolled level
    on; rolled (n, P) bool; roll_pressure / free_roll_pressure (n,) MPa (first rolled level;
    first level with a negative free margin; NaN: none); roll_face / free_roll_face (n,) (the
    face reached; the face across the crossed edge; 0: none); in_plane_max m, the largest
    in-plane shift (NaN: rolled at every level); agree (n,) bool, same roll level and face (or
    no roll in both); the verdicts shift_ok (None if the robot rolled at every level), roll_ok."""

    shift: np.ndarray
    margin_change: np.ndarray
    rolled: np.ndarray
    roll_pressure: np.ndarray
    free_roll_pressure: np.ndarray
    roll_face: np.ndarray
    free_roll_face: np.ndarray
    in_plane_max: float
    agree: np.ndarray
    shift_ok: bool | None
    roll_ok: bool


def compare_grounded(
    levels: ArrayLike,
    face: int,
    free_cog: np.ndarray,
    free_support: np.ndarray,
    free_margin: np.ndarray,
    grounded_cog: np.ndarray,
    grounded_margin: np.ndarray,
    end_face: np.ndarray,
    tolerance: float = CheckSettings.grounded_tolerance,
) -> GroundedComparison:
    """Compare a grounded sweep with the free one, per pair (n) and level (P), on `face` (1..20).

    levels (P,) MPa; free_* and grounded_*: nominal cog (n, P, 3) m, free support (n, P, 3, 3) m,
    margins (n, P) m, in the support frame of `face`; end_face (n, P) the grounded robot's face
    at the end of each level (0: none). A level counts as rolled from the first level whose end
    face is not `face` on (the robot stands elsewhere: its CoG in this face's frame means
    nothing, so its shift is NaN). `tolerance` m bounds the in-plane shift."""
    levels = np.asarray(levels, float)
    n, P = np.shape(free_margin)
    rolled = np.maximum.accumulate(np.asarray(end_face) != face, axis=1)
    shift = np.where(rolled[..., None], np.nan, grounded_cog - free_cog)
    margin_change = np.where(rolled, np.nan, grounded_margin - free_margin)
    roll_p, free_p = np.full(n, np.nan), np.full(n, np.nan)
    roll_f, free_f = np.zeros(n, np.int64), np.zeros(n, np.int64)
    agree = np.zeros(n, bool)
    for b in range(n):
        r = np.flatnonzero(rolled[b])
        if r.size:
            roll_p[b], roll_f[b] = levels[r[0]], end_face[b, r[0]]
        _, _, edge = frames.crossing(levels, free_margin[b], free_cog[b], free_support[b], face)
        out = np.flatnonzero(free_margin[b] < 0)
        if out.size:
            free_p[b], free_f[b] = levels[out[0]], topo.neighbour(face, edge)
        agree[b] = (r.size == 0 and out.size == 0) or (
            r.size > 0 and out.size > 0 and r[0] == out[0] and roll_f[b] == free_f[b]
        )
    in_plane = np.linalg.norm(shift[..., :2], axis=-1)
    in_plane_max = float(np.nanmax(in_plane)) if np.isfinite(in_plane).any() else float("nan")
    return GroundedComparison(
        shift,
        margin_change,
        rolled,
        roll_p,
        free_p,
        roll_f,
        free_f,
        in_plane_max,
        agree,
        bool(in_plane_max <= tolerance) if np.isfinite(in_plane_max) else None,
        bool(agree.all()),
    )


@dataclass(frozen=True)
class GroundedResult(Result):
    """Numbers of check 4 on the contact cases C = CONTACTS, all N_PAIRS pairs and the P `levels`
    MPa: faces (contact -> face 1..20 of the cases run), modes (the sorted modes of the nominal
    files compared with), settle s, tolerance m; swept (C, N_PAIRS) bool, the pair was run; cog
    (C, N_PAIRS, P, 3) m grounded nominal CoG, shift (C, N_PAIRS, P, 3) m and margin_change
    (C, N_PAIRS, P) m (all NaN once the robot rolled); rolled (C, N_PAIRS, P) bool; end_face
    (C, N_PAIRS, P) the face at the end of each level (0: none); roll_pressure,
    free_roll_pressure (C, N_PAIRS) MPa and roll_face, free_roll_face (C, N_PAIRS) as in
    `GroundedComparison`; agree (C, N_PAIRS) bool; status of verdicts 4.1 and 4.2."""

    levels: np.ndarray
    faces: dict[str, int]
    modes: tuple[str, ...]
    settle: float
    tolerance: float
    swept: np.ndarray
    cog: np.ndarray
    shift: np.ndarray
    margin_change: np.ndarray
    rolled: np.ndarray
    end_face: np.ndarray
    roll_pressure: np.ndarray
    roll_face: np.ndarray
    free_roll_pressure: np.ndarray
    free_roll_face: np.ndarray
    agree: np.ndarray


def check_grounded(
    params: Params,
    nominals: Mapping[str, Nominal],
    setup: SweepSetup,
    discard: float,
    settle: float = CheckSettings.grounded_settle,
    tolerance: float = CheckSettings.grounded_tolerance,
    motors: TwistedString | None = None,
) -> GroundedResult:
    """The paper's assumption (III.A-B: cable forces dominate, gravity does not change the
    shape, the robot rolls when the CoG projection leaves the triangle), measured: the pipeline's
    sweep repeated in the grounded mode (gravity, ground, friction; `settle` s on the ground
    first) against the pipeline's nominal CoG (free mode by default).

    4.1 where the robot stays on its face, gravity and contact shift the nominal CoG in the
        support plane by less than `tolerance` m;
    4.2 the grounded robot first rolls at the level where the free CoG projection first leaves
        the triangle, onto the face across the edge it crosses.
    With `motors` (`twisted.TwistedString`) the levels are motor voltages, V.
    """
    levels = common_levels(nominals)
    shape = (N_CONTACTS, topo.N_PAIRS, levels.size)
    gcog, shift = np.full((*shape, 3), np.nan), np.full((*shape, 3), np.nan)
    dmargin = np.full(shape, np.nan)
    rolled = np.zeros(shape, bool)
    endf = np.zeros(shape, np.int64)
    rp, frp = np.full(shape[:2], np.nan), np.full(shape[:2], np.nan)
    rf, frf = np.zeros(shape[:2], np.int64), np.zeros(shape[:2], np.int64)
    swept, agree = np.zeros(shape[:2], bool), np.zeros(shape[:2], bool)
    faces, shift_ok, roll_ok = {}, [], []
    for c, contact in enumerate(CONTACTS):
        n = nominals.get(contact)
        if n is None:
            continue
        face = n.face
        fc, fs, fm = n.cog, n.support, n.margin
        swept[c] = np.isfinite(fm).all(axis=1)
        idx = np.flatnonzero(swept[c])
        if idx.size == 0:
            continue
        faces[contact] = face
        run = simulate_nominal(params, face, idx + 1, setup, discard, motors, mode="grounded", settle=settle)
        cmp_ = compare_grounded(levels, face, fc[idx], fs[idx], fm[idx], run.cog, run.margin, run.end_face, tolerance)
        gcog[c, idx] = np.where(cmp_.rolled[..., None], np.nan, run.cog)
        shift[c, idx], dmargin[c, idx] = cmp_.shift, cmp_.margin_change
        rolled[c, idx], endf[c, idx] = cmp_.rolled, run.end_face
        rp[c, idx], frp[c, idx] = cmp_.roll_pressure, cmp_.free_roll_pressure
        rf[c, idx], frf[c, idx] = cmp_.roll_face, cmp_.free_roll_face
        agree[c, idx] = cmp_.agree
        if cmp_.shift_ok is not None:
            shift_ok.append(cmp_.shift_ok)
        roll_ok.append(cmp_.roll_ok)
    modes = tuple(sorted({n.mode for n in nominals.values()}))
    st = {"4.1": status(all(shift_ok)) if shift_ok else SKIP, "4.2": status(all(roll_ok)) if roll_ok else SKIP}
    return GroundedResult(
        status=st,
        levels=levels,
        faces=faces,
        modes=modes,
        settle=settle,
        tolerance=tolerance,
        swept=swept,
        cog=gcog,
        shift=shift,
        margin_change=dmargin,
        rolled=rolled,
        end_face=endf,
        roll_pressure=rp,
        roll_face=rf,
        free_roll_pressure=frp,
        free_roll_face=frf,
        agree=agree,
    )
