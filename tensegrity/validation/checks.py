"""Validation of the kinematic workspace (issue 5): the workflow checks its own results.

Seven checks, each a function returning a result dataclass of numbers and statuses (PASS, FAIL,
SKIP), never words or files:

1. `paper.check_paper`         the paper's statements (III.A, III.C, IV.B) against the nominal CoG;
2. `check_statics`             the nominal CoG against a static equilibrium (energy minimisation);
3. `check_mapping`             the workspace mapped by symmetry against direct simulations on
                               other faces (a workspace made by statics: against statics);
4. `grounded.check_grounded`   the paper's assumption: the same sweep with gravity, ground and
                               friction;
5. `check_timestep`            the nominal CoG at the time step against half of it;
6. `runs.check_runs`           the workflow's demonstration runs arrived (results/locomotion/);
7. `averaging.check_averaging` every level's estimated averaging error under a tolerance.

A check never raises because a comparison failed: a failure is a status next to its numbers.
Checks 3-5 run their own (batched) simulations. `run_checks` runs all seven; `validation.report`
turns the results into summary.md/html and validation.nc.
"""

from __future__ import annotations

import traceback
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ..physics import statics
from ..physics import topology as topo
from ..physics.params import Params
from ..physics.topology import CONTACTS
from ..physics.twisted import TwistedString
from ..workspace.lookup import Workspace
from ..workspace.nominal import Nominal
from ..workspace.sweep import SweepSetup
from . import averaging, common, grounded, paper
from . import runs as demo_runs
from .common import FAIL, LEVEL_TOL, N_CONTACTS, SKIP, CheckError, CheckSettings, MappingResult, Result, status
from .nominals import common_levels, simulate_nominal
from .statics_mapping import check_mapping_statics

# ----------------------------------------------------------------------- 2. statics


@dataclass(frozen=True)
class StaticsResult(Result):
    """Numbers of check 2 on the contact cases C = CONTACTS, all N_PAIRS pairs and the S
    `pressures` MPa: faces (contact -> face 1..20 of the cases given), tolerance m, modes (the
    sorted sweep modes of the nominal files), missing (the pressures not among the swept levels),
    cog (C, N_PAIRS, S, 3) m of the static equilibrium and difference (C, N_PAIRS, S) m from the
    nominal CoG, both in the support frame, NaN where not computed; status of verdict 2."""

    pressures: np.ndarray
    tolerance: float
    faces: dict[str, int]
    modes: tuple[str, ...]
    missing: tuple[float, ...]
    cog: np.ndarray
    difference: np.ndarray


def check_statics(
    params: Params,
    nominals: Mapping[str, Nominal],
    pressures: Sequence[float] = CheckSettings.statics_pressures,
    tolerance: float = CheckSettings.statics_tolerance,
) -> StaticsResult:
    """For every swept pair at `pressures` (MPa, among the swept levels), the nominal CoG against
    the free-mode static equilibrium solved by energy minimisation (physics.statics), both in
    the support frame of each contact face; goal: largest distance under `tolerance` m. Not
    evaluated for sweeps in the grounded mode or pressures off the levels."""
    levels = common_levels(nominals)
    pressures = np.asarray(pressures, float)
    S = len(pressures)
    scog = np.full((N_CONTACTS, topo.N_PAIRS, S, 3), np.nan)
    diff = np.full((N_CONTACTS, topo.N_PAIRS, S), np.nan)
    near = [np.flatnonzero(np.isclose(levels, p, rtol=0, atol=LEVEL_TOL)) for p in pressures]
    at = [int(k[0]) if k.size else -1 for k in near]
    modes = tuple(sorted({n.mode for n in nominals.values()}))
    missing = tuple(float(p) for p, k in zip(pressures, at) if k < 0)
    faces = {c: nominals[c].face for c in CONTACTS if c in nominals}
    result = lambda st: StaticsResult(
        status={"2": st},
        pressures=pressures,
        tolerance=tolerance,
        faces=faces,
        modes=modes,
        missing=missing,
        cog=scog,
        difference=diff,
    )
    if modes != ("free",) or missing:
        return result(SKIP)
    full = {c: nominals[c].cog for c in faces}
    for p in range(topo.N_PAIRS):
        if not any(np.isfinite(cog[p]).all() for cog in full.values()):
            continue
        start = None
        for j, pres in enumerate(pressures):
            prs = np.zeros(topo.N_PAIRS)
            prs[p] = pres
            nodes = start = statics.equilibrium(params, prs, start=start)
            for c, contact in enumerate(CONTACTS):
                if contact in full and np.isfinite(full[contact][p]).all():
                    scog[c, p, j] = statics.support_cog(nodes, faces[contact])[0]
                    diff[c, p, j] = np.linalg.norm(full[contact][p, at[j]] - scog[c, p, j])
    if not np.isfinite(diff).any():
        return result(SKIP)
    return result(status(bool(np.nanmax(diff) <= tolerance)))


# ------------------------------------------------------------------ 3. symmetry mapping


def check_mapping(
    params: Params,
    workspace: Workspace,
    faces: Sequence[int],
    setup: SweepSetup,
    discard: float,
    tolerance: float = CheckSettings.mapping_tolerance,
    min_per_kind: int = 2,
    motors: TwistedString | None = None,
) -> MappingResult:
    """The workspace mapped by symmetry (results/workspace.nc, a `Workspace`) against a direct
    simulation standing on each face of `faces` (non-canonical; at least `min_per_kind` of each
    kind): the nominal CoG and the deformed support triangle (the staircase of `setup`, averaged
    after `discard` s; with `motors`, `twisted.TwistedString`, in volts); goal: largest distance
    under `tolerance` m."""
    faces = np.array([topo.face_number(f) for f in faces], np.int64)
    levels = np.asarray(setup.levels, float)
    F, P = len(faces), len(levels)
    dcog = np.full((F, topo.N_PAIRS, P, 3), np.nan)
    dcog_diff = np.full((F, topo.N_PAIRS, P), np.nan)
    dsup_diff = np.full((F, topo.N_PAIRS, P), np.nan)
    canonical = {topo.face_number(f) for f in topo.CONTACT_FACES.values()}
    kinds = {k: sum(1 for f in faces if topo.FACE_TYPES[f - 1] == k and f not in canonical) for k in CONTACTS}
    match = bool(np.allclose(workspace.levels, levels, rtol=0, atol=LEVEL_TOL))
    result = lambda st: MappingResult(
        status={"3": st},
        faces=faces,
        levels=levels,
        tolerance=tolerance,
        min_per_kind=min_per_kind,
        levels_match=match,
        kinds=kinds,
        cog=dcog,
        difference=dcog_diff,
        support_difference=dsup_diff,
    )
    if not match:
        return result(SKIP)
    for i, face in enumerate(faces):
        wc, ws = workspace.cog[face - 1], workspace.support[face - 1]
        pairs = [p + 1 for p in range(topo.N_PAIRS) if np.isfinite(wc[p]).all()]
        if not pairs:
            continue
        run = simulate_nominal(params, face, pairs, setup, discard, motors)
        idx = np.array(pairs) - 1
        dcog[i, idx] = run.cog
        dcog_diff[i, idx] = np.linalg.norm(wc[idx] - run.cog, axis=-1)
        dsup_diff[i, idx] = np.linalg.norm(ws[idx] - run.support, axis=-1).max(axis=-1)
    if not np.isfinite(dcog_diff).any():
        return result(SKIP)
    n_faces = int(np.isfinite(dcog_diff).any(axis=(1, 2)).sum())
    ok = np.nanmax(np.fmax(dcog_diff, dsup_diff)) <= tolerance and min(kinds.values()) >= min_per_kind and n_faces == F
    return result(status(bool(ok)))


# -------------------------------------------------------------------- 5. time step


@dataclass(frozen=True)
class TimestepResult(Result):
    """Numbers of check 5 on the contact cases C = CONTACTS, all N_PAIRS pairs and the P `levels`
    MPa: dt s (the pipeline's; the check ran dt/2), tolerance m, faces (contact -> face 1..20 of
    the cases run), cog (C, N_PAIRS, P, 3) m the nominal CoG at dt/2 and difference
    (C, N_PAIRS, P) m from the pipeline's; NaN where not computed."""

    levels: np.ndarray
    dt: float
    tolerance: float
    faces: dict[str, int]
    cog: np.ndarray
    difference: np.ndarray
    statics: bool = False  # the nominal files hold static equilibria: no time step to halve


def check_timestep(
    params: Params,
    nominals: Mapping[str, Nominal],
    setup: SweepSetup,
    discard: float,
    tolerance: float = CheckSettings.timestep_tolerance,
    motors: TwistedString | None = None,
) -> TimestepResult:
    """The pipeline's nominal CoG (time step setup.dt) against the same sweep at dt/2 (the same
    sample times: record_every doubled); goal: largest distance under `tolerance` m. Not
    evaluated for nominal files made by statics (`Nominal.method`): no time step made them
    (check 2 compares them with the independent statics solve)."""
    levels = common_levels(nominals)
    P = levels.size
    hcog = np.full((N_CONTACTS, topo.N_PAIRS, P, 3), np.nan)
    diff = np.full((N_CONTACTS, topo.N_PAIRS, P), np.nan)
    faces = {}
    statics_made = any(n.method == "statics" for n in nominals.values())
    for c, contact in enumerate(CONTACTS):
        n = nominals.get(contact)
        if n is None or statics_made:
            continue
        fc = n.cog
        pairs = [p + 1 for p in range(topo.N_PAIRS) if np.isfinite(fc[p]).all()]
        if not pairs:
            continue
        idx = np.array(pairs) - 1
        faces[contact] = n.face
        half = {"dt": setup.dt / 2, "record_every": 2 * setup.record_every}
        run = simulate_nominal(params, faces[contact], pairs, setup, discard, motors, **half)
        hcog[c, idx] = run.cog
        diff[c, idx] = np.linalg.norm(fc[idx] - run.cog, axis=-1)
    st = SKIP if not np.isfinite(diff).any() else status(bool(np.nanmax(diff) <= tolerance))
    return TimestepResult({"5": st}, levels, setup.dt, tolerance, faces, hcog, diff, statics_made)


# -------------------------------------------------------------------- all checks


def run_checks(
    params: Params,
    setup: SweepSetup,
    discard: float,
    nominals: Mapping[str, Nominal],
    workspace: Workspace | None,
    settings: CheckSettings | None = None,
    on_result: Callable[[Result], None] | None = None,
    runs: Mapping[str, demo_runs.RunSummary] | None = None,
    motors: TwistedString | None = None,
) -> list[Result]:
    """Every check, in order 1-7, with `params`, the pipeline's sweep `setup` (its nominal average
    after `discard` s) and `settings` (default `CheckSettings()`) on the nominal CoG of the contact
    cases (contact -> `Nominal`, results/nominal/{contact}.nc), the workspace (results/workspace.nc)
    and the demonstration runs (name -> `runs.RunSummary` of results/locomotion/{run}.nc; None or
    empty: check 6 is not evaluated). With `motors` (the
    twisted-string actuator, `twisted.TwistedString`; the nominal files in volts) checks 3-5 and 7
    are evaluated in volts; 1 (the paper's pressures) and 2 (the statics of the muscles) are not
    evaluated, each with its reason (`IN_VOLTS`).
    A check that raises gives a `CheckError` (FAIL; the traceback goes to stderr, i.e. the job's
    log). `on_result` is called with each result as soon as it is known (progress logging)."""
    s = settings or CheckSettings()
    if any(n.method == "statics" for n in nominals.values()):  # made without sweeps: check 3 against statics
        check3 = lambda: check_mapping_statics(params, workspace, s.faces, setup.levels, s.mapping_tolerance)
    else:
        check3 = lambda: check_mapping(params, workspace, s.faces, setup, discard, s.mapping_tolerance, motors=motors)
    check1 = lambda: paper.check_paper(
        nominals, params.strut_length, s.ranking_pressure, s.tip_pressure_tolerance, s.orbit_tolerance
    )
    check2 = lambda: check_statics(params, nominals, s.statics_pressures, s.statics_tolerance)
    if motors is not None:
        check1 = lambda: common.NotEvaluated.of("paper", ("1.1", "1.2", "1.3", "1.4", "1.5"), common.IN_VOLTS["paper"])
        check2 = lambda: common.NotEvaluated.of("statics", ("2",), common.IN_VOLTS["statics"])
    todo = [
        ("paper", "1", check1),
        ("statics", "2", check2),
        ("mapping", "3", check3),
        (
            "grounded",
            "4",
            lambda: grounded.check_grounded(
                params, nominals, setup, discard, s.grounded_settle, s.grounded_tolerance, motors
            ),
        ),
        ("timestep", "5", lambda: check_timestep(params, nominals, setup, discard, s.timestep_tolerance, motors)),
        ("runs", "6", lambda: demo_runs.check_runs(runs or {})),
        ("averaging", "7", lambda: averaging.check_averaging(nominals, s.averaging_tolerance)),
    ]
    out = []
    for name, num, fn in todo:
        print(f"validate: {name} ...", flush=True)
        try:
            res = fn()
        except Exception as e:  # shown as a failed check, not a stopped workflow
            traceback.print_exc()
            res = CheckError(status={num: FAIL}, name=name, number=num, error=f"{type(e).__name__}: {e}")
        if on_result is not None:
            on_result(res)
        out.append(res)
    return out
