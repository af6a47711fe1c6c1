"""Per-design numbers of a study, many designs in one batched simulation.

`workspace`: the free-mode sweep of every (design, contact, pair) as one batch of robots, each with
its own parameters (`Params` fields as (B,) arrays), averaged per level as workspace.nominal does;
`static_workspace`: the same numbers as static equilibria (workspace.equilibria), with tipping
pressures found by root-finding (the study's `workspace.method: statics`).
`paper_statements`: the paper's statements (validation check 1) on each design's nominal CoG.
`roll_sequence`: the paper's roll sequence (9,10,12) -#10-> (10,11,12) -#11-> (6,10,11) in the
grounded mode for every design, driven by `locomotion.lockstep` as one batch.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, fields

import numpy as np

from .. import paper
from ..locomotion import control
from ..locomotion.lockstep import lockstep
from ..locomotion.settings import RollSettings
from ..physics import dynamics as d
from ..physics import frames
from ..physics import topology as topo
from ..physics.params import Params
from ..physics.schedule import Schedule
from ..physics.terrain import Terrain
from ..physics.topology import CONTACTS
from ..validation import paper as check1
from ..workspace import equilibria as eqw
from ..workspace import sweep as sw
from ..workspace.nominal import Nominal

STATEMENTS = ("1.1", "1.2", "1.3", "1.4", "1.5")  # the paper's statements (validation check 1)
STATEMENT_CODE = {"pass": 1, "fail": 0, "not evaluated": -1}

# The paper's experiment (IV.B; docs/design.md §1): (pairs driven, face it must land on).
PAPER_SEQUENCE = tuple(((pair,), face) for pair, _, face in paper.EXPERIMENT)


def batch_params(designs: Sequence[Params], repeat: int = 1) -> Params:
    """One `Params` whose fields are (n * repeat,) arrays: design i's values for robots
    i * repeat .. (i + 1) * repeat - 1; fields equal for every design stay scalars."""
    kw = {}
    for f in fields(Params):
        v = np.array([float(getattr(p, f.name)) for p in designs])
        kw[f.name] = float(v[0]) if np.all(v == v[0]) else np.repeat(v, repeat)
    return Params(**kw)


def _stand(designs: Sequence[Params], faces: Sequence[int], terrain: Terrain, per: int) -> d.State:
    """Design i standing on faces[j], `per` robots each, in the order (design, face, robot)."""
    parts = [d.stand_on(p, f, terrain, batch=per) for p in designs for f in faces]
    return d.State.concat(parts)


@dataclass(frozen=True)
class StudyWorkspace:
    """Nominal CoG of every design (D), contact case (C), pair (P) and level (L), in the support
    frame of the contact face: cog (D, C, P, L, 3) m, support (D, C, P, L, 3, 3) m (mean deformed
    triangle), margin (D, C, P, L) m (positive inside); faces (C,) 1..20."""

    faces: np.ndarray
    pairs: np.ndarray
    levels: np.ndarray
    cog: np.ndarray
    support: np.ndarray
    margin: np.ndarray


def _blocks(hold: float, dt: float, record_every: int, block_s: float = 0.1) -> list[float]:
    """`hold` s cut into blocks of about `block_s` s, each a whole number of recording intervals."""
    n = int(round(hold / (dt * record_every)))
    if n < 1 or abs(n * dt * record_every - hold) > 1e-9 * max(1.0, hold):
        raise ValueError(f"hold {hold} s is not a whole number of sampling intervals ({record_every} steps of {dt} s)")
    per = max(1, int(round(block_s / (dt * record_every))))
    return [k * dt * record_every for k in [per] * (n // per) + ([n % per] if n % per else [])]


def workspace(
    designs: Sequence[Params],
    contacts: Sequence[str],
    pairs: Sequence[int],
    setup: sw.SweepSetup,
    discard: float,
    progress: Callable[[float], None] | None = None,
) -> StudyWorkspace:
    """Free-mode staircase of `setup` (paper III.A; workspace.sweep in the free mode, its settle
    and mode not used) of every pair on every contact face for every design, as ONE batch of
    D * C * P robots; each level (MPa) is held setup.hold s and averaged after `discard` s as
    workspace.nominal.nominal does (the samples of the level's first `discard` s left out). A
    level is simulated in blocks of 0.1 s whose samples are summed, so that memory does not
    grow with the hold. progress(s) is called with the simulated seconds after each level."""
    levels, hold, dt, record_every = setup.levels, setup.hold, setup.dt, setup.record_every
    faces = np.array([topo.face_number(topo.CONTACT_FACES[c]) for c in contacts])
    pairs = np.array([topo.check_pair(p) for p in pairs])
    levels = np.asarray(levels, float)
    D, C, P, L = len(designs), len(faces), len(pairs), len(levels)
    prm, terrain = sw.setup(batch_params(designs, C * P), "free")
    state = _stand([p.replace(gravity=0.0) for p in designs], faces, terrain, P)
    col = np.tile(pairs - 1, D * C)
    cog, sup = np.zeros((D, C, P, L, 3)), np.zeros((D, C, P, L, 3, 3))
    for k, level in enumerate(levels):
        pres = np.zeros((D * C * P, topo.N_PAIRS))
        pres[np.arange(D * C * P), col] = level
        start, n = state.t, 0
        for dur in _blocks(hold, dt, record_every):
            state, tr = d.simulate(prm, state, Schedule.constant(pres, dur), terrain, dt, record_every)
            keep = tr.t > start + discard  # as workspace.nominal.nominal
            if not keep.any():
                continue
            nodes = tr.nodes(prm.strut_length)[:, keep].reshape(D, C, P, -1, topo.N_NODES, 3)
            for c, face in enumerate(faces):
                cg, st = frames.in_support_frame(nodes[:, c], int(face))
                cog[:, c, :, k] += cg.sum(axis=2)
                sup[:, c, :, k] += st.sum(axis=2)
            n += int(keep.sum())
        if n == 0:
            raise ValueError(f"discard = {discard} s leaves no samples of level {k} (hold {hold} s)")
        cog[:, :, :, k] /= n
        sup[:, :, :, k] /= n
        if progress:
            progress(hold)
    margin = frames.margin_2d(cog[..., :2], sup[..., :2])
    return StudyWorkspace(faces, pairs, levels, cog, sup, margin)


def static_workspace(
    designs: Sequence[Params], contacts: Sequence[str], pairs: Sequence[int], levels: Sequence[float]
) -> tuple[StudyWorkspace, np.ndarray]:
    """The workspace of `workspace` as static equilibria (`workspace.equilibria.free_workspace`:
    the support triangle is the equilibrium's, not a mean) and the tipping pressures (D, C, P)
    MPa, roots of the margin (NaN: never), for `paper_statements`."""
    faces = [topo.face_number(topo.CONTACT_FACES[c]) for c in contacts]
    s = eqw.free_workspace(designs, faces, pairs, levels)
    return StudyWorkspace(s.faces, s.pairs, s.levels, s.cog, s.support, s.margin), s.tip_pressure


def nominals(ws: StudyWorkspace, design: int, contacts: Sequence[str]) -> dict[str, Nominal]:
    """The free-mode nominal CoG of design number `design` (0-based, of `ws`) per contact case,
    `contacts` naming the contact cases of ws.faces in order."""
    return {
        c: Nominal.of_pairs(
            c,
            int(ws.faces[j]),
            "free",
            ws.levels,
            ws.pairs,
            ws.cog[design, j],
            ws.support[design, j],
            ws.margin[design, j],
        )
        for j, c in enumerate(contacts)
    }


def paper_statements(
    designs: Sequence[Params],
    ws: StudyWorkspace,
    contacts: Sequence[str],
    reference_pressure: float,
    tip_tolerance: float,
    tips: np.ndarray | None = None,
) -> dict[str, np.ndarray]:
    """The paper's statements per design (validation check 1, `validation.paper.check_paper`, on
    its nominal CoG `nominals` and its strut length; pairs ranked at `reference_pressure` MPa,
    #10's tip within `tip_tolerance` MPa): tip_pressure (D, C, N) MPa (NaN: never), tip_edge
    (D, C, N, 2) its nodes (0: none) and migration (D, C, N) m of the N pairs of `ws` on the C
    `contacts`, and status (D, 5), the codes (STATEMENT_CODE) of statements 1.1-1.5. `tips`
    (D, C, N) MPa, if given (`static_workspace`), replace the crossings interpolated in the levels."""
    D, C, N = ws.margin.shape[:3]
    out = {
        "tip_pressure": np.full((D, C, N), np.nan),
        "tip_edge": np.zeros((D, C, N, 2), np.int64),
        "migration": np.full((D, C, N), np.nan),
        "status": np.zeros((D, len(STATEMENTS)), np.int8),
    }
    for i, prm in enumerate(designs):
        given = None
        if tips is not None:
            given = np.full((len(CONTACTS), topo.N_PAIRS), np.nan)
            for j, c in enumerate(contacts):
                given[CONTACTS.index(c), ws.pairs - 1] = tips[i, j]
        r = check1.check_paper(
            nominals(ws, i, contacts), float(prm.strut_length), reference_pressure, tip_tolerance, tip_pressure=given
        )
        for j, c in enumerate(contacts):
            k = CONTACTS.index(c)
            out["tip_pressure"][i, j] = r.tip_pressure[k, ws.pairs - 1]
            out["tip_edge"][i, j] = r.tip_edge[k, ws.pairs - 1]
            out["migration"][i, j] = r.migration[k, ws.pairs - 1]
        out["status"][i] = [STATEMENT_CODE[r.status[s]] for s in STATEMENTS]
    return out


@dataclass(frozen=True)
class RollOutcome:
    """The roll sequence of one design: success (both rolls landed where the paper's did),
    tip_pressure (2,) MPa held when a support node lifted (NaN: no roll), face (2,) the face after
    each roll (0: none or not tried), error ('' or the simulation failure)."""

    success: bool
    tip_pressure: np.ndarray
    face: np.ndarray
    error: str = ""


def _sequence(prm: Params, s: RollSettings, obs, max_pressure: float, shared: dict):
    """Controller (locomotion.control generators): settle, then each roll of PAPER_SEQUENCE while
    the robot lands where the paper's did. A robot that is done holds zero pressure until every
    robot of the batch is, so that the batch (and its per-robot Params) never shrinks."""
    tips, faces, error = np.full(2, np.nan), np.zeros(2, np.int64), ""
    try:
        _, obs = yield from control.settle_controller(s, obs)
        for i, (pair, target) in enumerate(PAPER_SEQUENCE):
            if obs.face is None:
                break
            res, obs = yield from control.roll_controller(prm, s, obs, pair, max_pressure)
            tips[i], faces[i] = res.tip_pressure, res.face_after or 0
            if faces[i] != topo.face_number(target):
                break
    except d.SimulationError as e:
        error = str(e)
    ok = bool(not error and np.all(faces == [topo.face_number(t) for _, t in PAPER_SEQUENCE]))
    out = RollOutcome(ok, tips, faces, error)
    if error:
        return out
    shared["done"] += 1
    if shared["done"] == shared["n"]:
        shared["t_end"] = obs.t
    obs = yield np.zeros(topo.N_PAIRS)
    while shared["t_end"] is None or obs.t <= shared["t_end"]:
        obs = yield np.zeros(topo.N_PAIRS)
    return out


def roll_sequence(designs: Sequence[Params], settings: RollSettings, max_pressure: float) -> list[RollOutcome]:
    """The paper's roll sequence on flat ground for every design (one robot each, one lockstep
    batch with per-robot Params; rolls ramp to at most `max_pressure` MPa). If a simulation fails,
    the batch cannot go on with per-robot Params: the designs are then run one by one."""
    terrain = Terrain.flat()
    try:
        return _rolls(designs, settings, max_pressure, terrain)
    except (d.SimulationError, ValueError):
        return [_rolls([p], settings, max_pressure, terrain)[0] for p in designs]


def _rolls(designs, settings, max_pressure, terrain) -> list[RollOutcome]:
    prm = batch_params(designs)
    state = _stand(designs, [topo.face_number(paper.START_FACE)], terrain, 1)
    shared = {"done": 0, "n": len(designs), "t_end": None}
    out = lockstep(prm, terrain, state, lambda b, o: _sequence(designs[b], settings, o, max_pressure, shared), settings)
    return [r[0] for r in out]


def design_outputs(ws: StudyWorkspace, tip_pressure: np.ndarray, reference_pressure: float) -> dict[str, np.ndarray]:
    """Per design (D,): the margin (D, C, N) m at `reference_pressure` MPa (interpolated in the
    levels), its smallest value min_margin, the lowest tipping pressure of any pair and contact
    best_tip_pressure MPa (tip_pressure (D, C, N); NaN: none tips) and the objective: that
    pressure where every pair stands at the reference pressure (NaN: not standing)."""
    flat = ws.margin.reshape(-1, ws.margin.shape[-1])
    mref = np.array([np.interp(reference_pressure, ws.levels, m) for m in flat]).reshape(ws.margin.shape[:-1])
    D = mref.shape[0]
    tip = np.where(np.isfinite(tip_pressure), tip_pressure, np.inf)
    best = tip.reshape(D, -1).min(axis=1)
    best = np.where(np.isfinite(best), best, np.nan)
    min_margin = mref.reshape(D, -1).min(axis=1)
    return {
        "reference_margin": mref,
        "min_margin": min_margin,
        "best_tip_pressure": best,
        "objective": np.where(min_margin > 0, best, np.nan),
    }
