"""Validation of the kinematic workspace (issue 5): the workflow checks its own results.

Five checks, each a function returning a `Check` (its rows of the summary table and its numbers,
with units):

1. `check_paper`     the paper's statements (III.A, III.C, IV.B) against the nominal CoG;
2. `check_statics`   the nominal CoG against a static equilibrium solved by energy minimisation;
3. `check_mapping`   the workspace mapped by symmetry against direct simulations on other faces;
4. `check_grounded`  the paper's assumption: the same sweep with gravity, ground and friction;
5. `check_timestep`  the nominal CoG at the time step against half of it.

A check never raises because a comparison failed: a failure is a verdict shown with its numbers.
Checks 3-5 run their own (batched) simulations; nothing here reads or writes files except the
stage function `run_stage` and the writers at the end of the module.
"""
from __future__ import annotations

import traceback
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from ..io import datasets
from ..physics import frames, topology as topo
from ..workspace import nominal as nom
from ..physics import statics
from ..workspace import sweep as sw
from ..physics import symmetry as sym
from ..io.config import params_from_config
from ..physics.params import Params

PASS, FAIL, SKIP = "pass", "fail", "not evaluated"
CONTACTS = tuple(topo.CONTACT_FACES)            # ("equilateral", "isosceles")
AXES = ("x", "y", "z")

# The paper's statements (section and value). The pressure of the second roll is not given: the
# prototype needed 6 V against 11.1 V for the first (IV.B), i.e. a lower drive.
PAPER_FACE = {"equilateral": (9, 10, 12), "isosceles": (10, 11, 12)}
PAPER_LARGE, PAPER_LESS = (9, 10, 12), (4, 6, 7)        # III.A, Fig. 7
PAPER_TIP_PRESSURE = 4.2                                # MPa, #10 on (9,10,12), III.C
PAPER_EDGE = {10: (10, 12), 11: (10, 11)}               # III.C and IV.B: (10,11,12), (6,10,11)
PAPER_VOLTAGE = {10: 11.1, 11: 6.0}                     # V, IV.B


@dataclass(frozen=True)
class Verdict:
    """One row of the summary table: what is claimed, what was measured (with units), the
    paper's value or the goal, and the status PASS, FAIL or SKIP."""
    id: str
    statement: str
    measured: str
    reference: str
    status: str

    @property
    def passed(self) -> bool:
        return self.status == PASS


@dataclass(frozen=True)
class Check:
    """Outcome of one check: `verdicts`, and `data`, netCDF variables name -> (dims, values,
    attrs with units and long_name) on the dimensions of `COORDS_DOC`; `allow_nan` names the
    variables where NaN means 'not computed' (a missing pair, a robot that rolled). `tables`
    are extra (title, header, rows) tables for the summary."""
    name: str
    verdicts: tuple[Verdict, ...]
    data: dict = field(default_factory=dict)
    allow_nan: tuple[str, ...] = ()
    tables: tuple = ()


@dataclass(frozen=True)
class SweepSetup:
    """How the pipeline's sweeps were run, so that the checks can run the same sweep: levels
    (P,) MPa, hold s, settle s, mode, dt s, record_every steps, discard s (nominal average)."""
    levels: tuple[float, ...]
    hold: float = 1.0
    settle: float = 0.0
    mode: str = "free"
    dt: float = 1e-4
    record_every: int = 10
    discard: float = 0.2

    @classmethod
    def from_config(cls, cfg: Mapping) -> "SweepSetup":
        s, sim = cfg["sweep"], cfg["sim"]
        return cls(tuple(float(p) for p in s["levels"]), float(s["hold"]), float(s["settle"]),
                   str(s["mode"]), float(sim["dt"]), int(sim["record_every"]),
                   float(cfg["nominal"]["discard"]))


@dataclass(frozen=True)
class NominalRun:
    """Nominal CoG of a simulated sweep, per pair (n,) and level (P,): cog (n, P, 3) m and
    support (n, P, 3, 3) m in the face's support frame, margin (n, P) m, and end_face (n, P),
    the 1-based face of the three lowest nodes at the end of each level (0: not a face)."""
    pairs: np.ndarray
    cog: np.ndarray
    support: np.ndarray
    margin: np.ndarray
    end_face: np.ndarray


# ------------------------------------------------------------------------------ helpers

def _mm(x: float, digits: int = 3) -> str:
    """A length in m written in mm."""
    if not np.isfinite(x):
        return "n/a"
    v = 1e3 * float(x)
    return f"{v:.{digits}g} mm" if abs(v) < 10 ** digits else f"{v:.0f} mm"


def _label(face: int) -> str:
    return topo.face_label(int(face))


def _edge_label(edge) -> str:
    return "-".join(str(int(n)) for n in sorted(edge)) if edge is not None and min(edge) > 0 else "none"


def _status(ok: bool) -> str:
    return PASS if ok else FAIL


def full_nominal(ds: xr.Dataset) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A nominal dataset (results/nominal/{contact}.nc) as arrays over all 12 pairs: cog
    (12, P, 3) m, support (12, P, 3, 3) m and margin (12, P) m, NaN for pairs not swept."""
    P = ds.sizes["pressure"]
    cog, sup, mar = np.full((12, P, 3), np.nan), np.full((12, P, 3, 3), np.nan), np.full((12, P), np.nan)
    idx = ds["pair"].values.astype(int) - 1
    cog[idx] = ds["cog"].values
    sup[idx] = ds["support"].values
    mar[idx] = ds["margin"].values
    return cog, sup, mar


def _levels(nominals: Mapping[str, xr.Dataset]) -> np.ndarray:
    levels = [ds["pressure"].values for ds in nominals.values()]
    if not levels:
        raise ValueError("no nominal dataset given")
    for lv in levels[1:]:
        if not np.array_equal(lv, levels[0]):
            raise ValueError("the contact cases were swept at different pressure levels")
    return np.asarray(levels[0], float)


def _face(ds: xr.Dataset) -> int:
    return int(ds.attrs["face"])


def rest_cog(face, strut_length: float = 0.5) -> np.ndarray:
    """CoG (3,) m of the symmetric, unactuated robot in the support frame of `face`."""
    return frames.rest_frame(face, strut_length)[0]


def tip(levels, cog, support, margin, face: int) -> tuple[float, tuple[int, int] | None]:
    """Least pressure (MPa, interpolated; NaN: never) at which the CoG projection leaves the
    triangle, and the edge (two 1-based node numbers) it crosses at the first level outside.
    cog (P, 3), support (P, 3, 3), margin (P,) of one pair in the support frame of `face`."""
    pressure, k = frames.first_crossing(levels, margin)
    if k < 0:
        return pressure, None
    return pressure, topo.edge_nodes(face, frames.crossed_edge(cog[k, :2], support[k, :, :2]))


def migration(levels, cog, rest, pressure: float) -> np.ndarray:
    """In-plane distance (m) of the nominal CoG from the unactuated CoG `rest` (3,) at
    `pressure` MPa, linearly interpolated between levels; cog (n, P, 3) -> (n,)."""
    levels = np.asarray(levels, float)
    if not levels[0] - 1e-9 <= pressure <= levels[-1] + 1e-9:
        raise ValueError(f"pressure {pressure} MPa is outside the swept levels "
                         f"{levels[0]}..{levels[-1]} MPa")
    xy = np.stack([[np.interp(pressure, levels, c[:, a]) for a in range(2)] for c in cog])
    return np.linalg.norm(xy - rest[:2], axis=1)


def three_fold_orbits(face: int) -> list[tuple[int, ...]]:
    """Orbits (1-based pair numbers) of the pairs under the rotations keeping `face` (the
    3-fold rotation of an equilateral face; only the identity for an isosceles face)."""
    rots = _face_rotations(face)
    seen, orbits = set(), []
    for p in range(topo.N_PAIRS):
        if p not in seen:
            orb = sorted({int(s.pairs[p]) for s in rots})
            seen.update(orb)
            orbits.append(tuple(q + 1 for q in orb))
    return orbits


def _face_rotations(face: int):
    f = face - 1
    return [s for s in sym.group() if s.faces[f] == f and np.linalg.det(s.matrix) > 0]


def orbit_spread(cog, support, face: int, orbit: Sequence[int]) -> tuple[np.ndarray, np.ndarray]:
    """How unequally the pairs of a 3-fold orbit move the CoG, per level: the largest distance
    (m) between a member's CoG and the first member's, each expressed with y toward the corner
    its rotation carries the reference vertex to (the deformed triangle is not exactly
    equilateral, so the fixed frame would show a spurious difference), and the spread (m) of
    the in-plane distances from the centroid. cog (12, P, 3), support (12, P, 3, 3) -> (P,), (P,)."""
    f = face - 1
    nodes = list(topo.FACES[f])
    ref = topo.FACES[f, topo.FACE_REFERENCE[f]]
    rots = _face_rotations(face)
    rel = []
    for pair in orbit:
        s = next(s for s in rots if s.pairs[orbit[0] - 1] == pair - 1)
        corner = nodes.index(s.nodes[ref])
        v = support[pair - 1, :, corner, :2]
        ang = np.arctan2(v[:, 0], v[:, 1])        # turn the frame so that y points to `corner`
        c, sn = np.cos(ang), np.sin(ang)
        x, y = cog[pair - 1, :, 0], cog[pair - 1, :, 1]
        rel.append(np.stack([c * x - sn * y, sn * x + c * y, cog[pair - 1, :, 2]], axis=-1))
    rel = np.array(rel)                               # (members, P, 3)
    diff = np.linalg.norm(rel - rel[0], axis=-1).max(axis=0)
    mag = np.linalg.norm(rel[..., :2], axis=-1)
    return diff, mag.max(axis=0) - mag.min(axis=0)


def simulate_nominal(params: Params, face, pairs, setup: SweepSetup, *, mode: str | None = None,
                     settle: float | None = None, dt: float | None = None,
                     record_every: int | None = None) -> NominalRun:
    """Run the staircase of `setup` on `pairs` (batched) standing on `face` and average each
    level as the pipeline does (nominal.nominal); `mode`, `settle`, `dt`, `record_every`
    override the setup's."""
    face = topo.face_number(face)
    res = sw.run(params, face, pairs, setup.levels, setup.hold,
                 setup.settle if settle is None else settle, mode or setup.mode,
                 setup.dt if dt is None else dt,
                 setup.record_every if record_every is None else record_every)
    P = len(setup.levels)
    out = [nom.nominal(res.t, res.level, res.cog[b], res.support[b], P, setup.hold, setup.discard)
           for b in range(len(res.pairs))]
    last = np.array([np.flatnonzero(res.level == k)[-1] for k in range(P)])
    end_face = res.resting_face[:, last]
    return NominalRun(res.pairs, *(np.stack([o[k] for o in out]) for k in (0, 2, 3)), end_face)


# ------------------------------------------------------------------- 1. paper statements

def check_paper(nominals: Mapping[str, xr.Dataset], strut_length: float = 0.5,
                ranking_pressure: float = 2.4, tip_tolerance: float = 0.2,
                orbit_tolerance: float = 1e-4) -> Check:
    """The paper's statements against the nominal CoG of the contact cases (`nominals` maps
    'equilateral'/'isosceles' to results/nominal/{contact}.nc datasets):

    1.1 standing on (9,10,12), #9, #10, #12 move the CoG most and #4, #6, #7 next (III.A, Fig. 7),
        ranked by the in-plane distance from the unactuated CoG at `ranking_pressure` MPa;
    1.2 #10 moves the CoG projection out over edge 10-12 at 4.2 MPa (+- `tip_tolerance` MPa);
    1.3 standing on (10,11,12), #11 moves it out over edge 10-11 (the roll to (6,10,11), IV.B);
    1.4 ... at a lower pressure than #10 needs on (9,10,12) (6 V against 11.1 V, IV.B);
    1.5 the pairs of each 3-fold orbit of (9,10,12) move the CoG equally (`orbit_tolerance` m).
    """
    levels = _levels(nominals)
    P = levels.size
    tipp = np.full((2, 12), np.nan)
    edges = np.zeros((2, 12, 2), dtype=np.int64)
    mig = np.full((2, 12), np.nan)
    arrays, faces = {}, {}
    for c, contact in enumerate(CONTACTS):
        ds = nominals.get(contact)
        if ds is None:
            continue
        face = faces[contact] = _face(ds)
        cog, sup, mar = arrays[contact] = full_nominal(ds)
        for p in range(12):
            if np.isfinite(mar[p]).all():
                tipp[c, p], e = tip(levels, cog[p], sup[p], mar[p], face)
                edges[c, p] = e or (0, 0)
        try:
            mig[c] = migration(levels, cog, rest_cog(face, strut_length), ranking_pressure)
        except ValueError:
            pass
    verdicts = []
    eq, iso = "equilateral", "isosceles"
    on = {k: f"standing on {_label(faces[k])}" if k in faces else f"{k} case not computed" for k in CONTACTS}

    # 1.1 ranking
    stmt = (f"Standing on (9,10,12), pairs #9, #10, #12 move the CoG most and #4, #6, #7 next "
            f"(in-plane distance from the unactuated CoG at {ranking_pressure:g} MPa)")
    ref = "#9, #10, #12 large; #4, #6, #7 less (III.A, Fig. 7)"
    if eq not in faces or not np.isfinite(mig[0]).all():
        inside = levels[0] - 1e-9 <= ranking_pressure <= levels[-1] + 1e-9
        why = (on[eq] if eq not in faces else "not all 12 pairs swept" if inside
               else f"{ranking_pressure:g} MPa is outside the swept levels")
        verdicts.append(Verdict("1.1", stmt, why, ref, SKIP))
    else:
        order = [int(p) + 1 for p in np.argsort(-mig[0], kind="stable")]
        groups = [order[:3], order[3:6], order[6:]]
        txt = "; ".join(", ".join(f"#{p} {_mm(mig[0, p - 1])}" for p in grp) if i < 2 else
                        f"others {_mm(mig[0, grp[-1] - 1])}..{_mm(mig[0, grp[0] - 1])}"
                        for i, grp in enumerate(groups))
        ok = (faces[eq] == topo.face_number(PAPER_FACE[eq]) and set(groups[0]) == set(PAPER_LARGE)
              and set(groups[1]) == set(PAPER_LESS))
        verdicts.append(Verdict("1.1", stmt, f"{on[eq]}: {txt}", ref, _status(ok)))

    # 1.2, 1.3, 1.4 tipping pressures and edges
    def tip_text(c, pair):
        p, e = tipp[c, pair - 1], edges[c, pair - 1]
        if not np.isfinite(p):
            return f"#{pair} keeps it inside up to {levels[-1]:g} MPa"
        return f"#{pair}: {p:.2f} MPa over edge {_edge_label(e)} ({on[CONTACTS[c]]})"

    def have(c, pair):
        return CONTACTS[c] in faces and np.isfinite(arrays[CONTACTS[c]][2][pair - 1]).all()

    stmt = "Standing on (9,10,12), #10 moves the CoG projection out over edge 10-12"
    ref = f"{PAPER_TIP_PRESSURE} MPa over edge 10-12 (III.C), within {tip_tolerance:g} MPa"
    if not have(0, 10):
        verdicts.append(Verdict("1.2", stmt, "#10 not swept " + on[eq], ref, SKIP))
    else:
        ok = (faces[eq] == topo.face_number(PAPER_FACE[eq]) and abs(tipp[0, 9] - PAPER_TIP_PRESSURE) <= tip_tolerance
              and set(edges[0, 9]) == set(PAPER_EDGE[10]))
        verdicts.append(Verdict("1.2", stmt, tip_text(0, 10), ref, _status(bool(ok))))
    stmt = "Standing on (10,11,12), #11 moves the CoG projection out over edge 10-11"
    ref = "over edge 10-11: the robot rolls on to (6,10,11) (IV.B)"
    if not have(1, 11):
        verdicts.append(Verdict("1.3", stmt, "#11 not swept " + on[iso], ref, SKIP))
    else:
        ok = faces[iso] == topo.face_number(PAPER_FACE[iso]) and set(edges[1, 10]) == set(PAPER_EDGE[11])
        verdicts.append(Verdict("1.3", stmt, tip_text(1, 11), ref, _status(bool(ok))))
    stmt = "#11 on (10,11,12) needs a lower pressure than #10 on (9,10,12)"
    ref = (f"lower: the prototype needed {PAPER_VOLTAGE[11]:g} V against {PAPER_VOLTAGE[10]:g} V "
           f"(ratio {PAPER_VOLTAGE[11] / PAPER_VOLTAGE[10]:.2f}, IV.B)")
    if not (have(0, 10) and have(1, 11)):
        verdicts.append(Verdict("1.4", stmt, "#10 or #11 not swept", ref, SKIP))
    else:
        p10, p11 = tipp[0, 9], tipp[1, 10]
        ok = np.isfinite(p11) and (not np.isfinite(p10) or p11 < p10)
        fmt = lambda p: f"{p:.2f} MPa" if np.isfinite(p) else f"never (up to {levels[-1]:g} MPa)"
        ratio = f" (ratio {p11 / p10:.2f})" if np.isfinite(p10) and np.isfinite(p11) else ""
        meas = f"#11 {fmt(p11)}, #10 {fmt(p10)}{ratio}"
        verdicts.append(Verdict("1.4", stmt, meas, ref, _status(bool(ok))))

    # 1.5 three-fold orbits
    orbits = three_fold_orbits(topo.face_number(PAPER_FACE[eq]))
    n_orb = len(orbits)
    size = max(len(o) for o in orbits)
    odiff, ospread = np.full((n_orb, P), np.nan), np.full((n_orb, P), np.nan)
    opairs = np.zeros((n_orb, size), dtype=np.int64)
    stmt = "The pairs of each 3-fold orbit of (9,10,12) move the CoG equally (120 deg apart)"
    ref = f"equal (III.A, the symmetry); goal: under {_mm(orbit_tolerance)}"
    if eq in faces and faces[eq] == topo.face_number(PAPER_FACE[eq]):
        cog, sup, _ = arrays[eq]
        for i, orb in enumerate(orbits):
            opairs[i, :len(orb)] = orb
            if np.isfinite(cog[np.array(orb) - 1]).all():
                odiff[i], ospread[i] = orbit_spread(cog, sup, faces[eq], orb)
    done = np.isfinite(odiff).all(axis=1)
    if not done.any():
        verdicts.append(Verdict("1.5", stmt, "no complete orbit swept " + on[eq], ref, SKIP))
    else:
        worst = max(range(n_orb), key=lambda i: np.nanmax(odiff[i]) if done[i] else -1)
        k = int(np.nanargmax(odiff[worst]))
        meas = (f"largest difference {_mm(np.nanmax(odiff))} (orbit "
                f"{', '.join(f'#{p}' for p in orbits[worst])} at {levels[k]:g} MPa; magnitudes differ by "
                f"at most {_mm(np.nanmax(ospread))}) over {int(done.sum())} orbits x {P} levels")
        verdicts.append(Verdict("1.5", stmt, meas, ref, _status(bool(np.nanmax(odiff) <= orbit_tolerance))))

    data = {
        "migration": datasets.var(("contact", "pair"), mig, "m",
                          f"in-plane distance of the nominal CoG from the unactuated CoG at {ranking_pressure:g} MPa",
                          pressure_MPa=ranking_pressure),
        "tip_pressure": datasets.var(("contact", "pair"), tipp, "MPa",
                             "least pressure at which the CoG projection leaves the support triangle (NaN: never)"),
        "tip_edge": datasets.var(("contact", "pair", "end"), edges, "1",
                         "nodes of the edge the CoG projection crosses first (0: none)"),
        "paper_tip_pressure": datasets.var((), PAPER_TIP_PRESSURE, "MPa",
                                   "paper's pressure at which #10 rolls the robot off (9,10,12) (III.C)",
                                   tolerance_MPa=tip_tolerance),
        "orbit_pairs": datasets.var(("orbit", "member"), opairs, "1", "pairs of each 3-fold orbit of (9,10,12)"),
        "orbit_difference": datasets.var(("orbit", "pressure"), odiff, "m",
                                 "largest difference between the orbit members' CoG, each seen from the "
                                 "corner its rotation carries the reference vertex to", goal_m=orbit_tolerance),
        "orbit_magnitude_spread": datasets.var(("orbit", "pressure"), ospread, "m",
                                       "spread of the orbit members' in-plane CoG distance from the centroid"),
    }
    return Check("paper", tuple(verdicts), data,
                 ("migration", "tip_pressure", "orbit_difference", "orbit_magnitude_spread"))


# ----------------------------------------------------------------------- 2. statics

def check_statics(params: Params, nominals: Mapping[str, xr.Dataset], pressures=(0.8, 2.4, 4.0),
                  tolerance: float = 1e-4) -> Check:
    """For every swept pair at `pressures` (MPa, among the swept levels), the nominal CoG against
    the free-mode static equilibrium solved by energy minimisation (tensegrity.statics), both in
    the support frame of each contact face; goal: largest distance under `tolerance` m."""
    levels = _levels(nominals)
    pressures = np.asarray(pressures, float)
    S = len(pressures)
    scog = np.full((2, 12, S, 3), np.nan)
    diff = np.full((2, 12, S), np.nan)
    at = [int(np.flatnonzero(np.isclose(levels, p, rtol=0, atol=1e-9))[0])
          if np.isclose(levels, p, rtol=0, atol=1e-9).any() else -1 for p in pressures]
    stmt = (f"Nominal CoG = static equilibrium by energy minimisation (scipy), every pair at "
            f"{', '.join(f'{p:g}' for p in pressures)} MPa, in the support frame")
    ref = f"under {_mm(tolerance)}"
    modes = {str(ds.attrs.get("mode", "free")) for ds in nominals.values()}
    data_vars = lambda: {
        "statics_cog": datasets.var(("contact", "pair", "statics_pressure", "axis"), scog, "m",
                            "CoG of the free-mode static equilibrium in the support frame"),
        "statics_difference": datasets.var(("contact", "pair", "statics_pressure"), diff, "m",
                                   "distance between the nominal CoG and the static-equilibrium CoG",
                                   goal_m=tolerance)}
    nan = ("statics_cog", "statics_difference")
    if modes != {"free"}:
        return Check("statics", (Verdict("2", stmt, f"the sweeps ran in the {'/'.join(sorted(modes))} mode; "
                                          "the statics solve is of the free mode", ref, SKIP),), data_vars(), nan)
    if min(at) < 0:
        missing = [f"{p:g}" for p, k in zip(pressures, at) if k < 0]
        return Check("statics", (Verdict("2", stmt, f"{', '.join(missing)} MPa not among the swept levels",
                                          ref, SKIP),), data_vars(), nan)
    full = {c: full_nominal(nominals[c])[0] for c in CONTACTS if c in nominals}
    for p in range(12):
        if not any(np.isfinite(cog[p]).all() for cog in full.values()):
            continue
        start = None
        for j, pres in enumerate(pressures):
            prs = np.zeros(topo.N_PAIRS)
            prs[p] = pres
            nodes = statics.equilibrium(params, prs, start=start)
            start = nodes
            for c, contact in enumerate(CONTACTS):
                if contact in full and np.isfinite(full[contact][p]).all():
                    scog[c, p, j] = statics.support_cog(nodes, _face(nominals[contact]))[0]
                    diff[c, p, j] = np.linalg.norm(full[contact][p, at[j]] - scog[c, p, j])
    c, p, j = np.unravel_index(int(np.nanargmax(diff)), diff.shape)
    meas = (f"largest {_mm(np.nanmax(diff))} (#{p + 1} at {pressures[j]:g} MPa on "
            f"{_label(_face(nominals[CONTACTS[c]]))}) over {int(np.isfinite(diff).sum())} cases")
    return Check("statics", (Verdict("2", stmt, meas, ref, _status(bool(np.nanmax(diff) <= tolerance))),),
                 data_vars(), nan)


# ------------------------------------------------------------------ 3. symmetry mapping

def check_mapping(params: Params, workspace: xr.Dataset, faces: Sequence[int], setup: SweepSetup,
                  tolerance: float = 1e-4, min_per_kind: int = 2) -> Check:
    """The workspace mapped by symmetry (results/workspace.nc) against a direct simulation
    standing on each face of `faces` (non-canonical; at least `min_per_kind` of each kind):
    the nominal CoG and the deformed support triangle; goal: largest distance under `tolerance` m."""
    faces = [topo.face_number(f) for f in faces]
    levels = np.asarray(setup.levels, float)
    F, P = len(faces), len(levels)
    dcog = np.full((F, 12, P, 3), np.nan)
    dcog_diff, dsup_diff = np.full((F, 12, P), np.nan), np.full((F, 12, P), np.nan)
    stmt = ("Workspace mapped by symmetry = direct simulation standing on the face "
            "(nominal CoG and deformed triangle), sample faces " + ", ".join(_label(f) for f in faces))
    ref = f"under {_mm(tolerance)}; at least {min_per_kind} non-canonical faces of each kind"
    canonical = {topo.face_number(f) for f in topo.CONTACT_FACES.values()}
    kinds = {k: sum(1 for f in faces if topo.FACE_TYPES[f - 1] == k and f not in canonical) for k in CONTACTS}
    data = lambda: {
        "sample_face_type": (("sample_face",), np.array([str(topo.FACE_TYPES[f - 1]) for f in faces]),
                             {"long_name": "kind of the sample face"}),
        "direct_cog": datasets.var(("sample_face", "pair", "pressure", "axis"), dcog, "m",
                           "nominal CoG of a direct simulation standing on the sample face, in its support frame"),
        "mapping_difference": datasets.var(("sample_face", "pair", "pressure"), dcog_diff, "m",
                                   "distance between the mapped and the directly simulated nominal CoG",
                                   goal_m=tolerance),
        "mapping_support_difference": datasets.var(("sample_face", "pair", "pressure"), dsup_diff, "m",
                                           "largest corner distance between the mapped and the directly "
                                           "simulated support triangle", goal_m=tolerance)}
    nan = ("direct_cog", "mapping_difference", "mapping_support_difference")
    if not np.allclose(workspace["pressure"].values, levels, rtol=0, atol=1e-9):
        return Check("mapping", (Verdict("3", stmt, "the workspace was swept at other levels", ref, SKIP),), data(), nan)
    wfaces = list(workspace["face"].values.astype(int))
    for i, face in enumerate(faces):
        wc = workspace["cog"].values[wfaces.index(face)]
        ws = workspace["support"].values[wfaces.index(face)]
        pairs = [p + 1 for p in range(12) if np.isfinite(wc[p]).all()]
        if not pairs:
            continue
        run = simulate_nominal(params, face, pairs, setup)
        idx = np.array(pairs) - 1
        dcog[i, idx] = run.cog
        dcog_diff[i, idx] = np.linalg.norm(wc[idx] - run.cog, axis=-1)
        dsup_diff[i, idx] = np.linalg.norm(ws[idx] - run.support, axis=-1).max(axis=-1)
    if not np.isfinite(dcog_diff).any():
        return Check("mapping", (Verdict("3", stmt, "the workspace holds no data for the sample faces",
                                          ref, SKIP),), data(), nan)
    worst = np.fmax(dcog_diff, dsup_diff)
    i, p, k = np.unravel_index(int(np.nanargmax(worst)), worst.shape)
    n_faces = int(np.isfinite(dcog_diff).any(axis=(1, 2)).sum())
    meas = (f"largest {_mm(np.nanmax(dcog_diff))} (CoG), {_mm(np.nanmax(dsup_diff))} (triangle), at "
            f"#{p + 1}, {levels[k]:g} MPa on {_label(faces[i])}; {n_faces} faces "
            f"({kinds['equilateral']} equilateral, {kinds['isosceles']} isosceles), "
            f"{int(np.isfinite(dcog_diff).sum())} cases")
    ok = np.nanmax(worst) <= tolerance and min(kinds.values()) >= min_per_kind and n_faces == F
    if n_faces < F:
        meas += f"; {F - n_faces} faces without workspace data"
    return Check("mapping", (Verdict("3", stmt, meas, ref, _status(bool(ok))),), data(), nan)


# -------------------------------------------------------------- 4. grounded vs free

def compare_grounded(levels, face: int, free_cog, free_support, free_margin, grounded_cog,
                     grounded_margin, end_face, tolerance: float = 5e-3) -> dict:
    """Compare a grounded sweep with the free one, per pair (n) and level (P), on `face`.

    free_* and grounded_*: nominal cog (n, P, 3) m, free support (n, P, 3, 3) m, margins
    (n, P) m; end_face (n, P) the grounded robot's face at the end of each level.
    A level counts as rolled from the first level whose end face is not `face` on (the robot
    stands elsewhere: its CoG in this face's frame means nothing, so its shift is NaN).
    Returns arrays: shift (n, P, 3) m, margin_change (n, P) m, rolled (n, P) bool,
    roll_pressure / free_roll_pressure (n,) MPa (first rolled level; first level with a
    negative free margin; NaN: none), roll_face / free_roll_face (n,) (the face reached; the
    face across the crossed edge; 0: none), in_plane_max (float, m), agree (n,) bool, and the
    verdicts shift_ok (None if the robot rolled at every level) and roll_ok."""
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
        t, edge = tip(levels, free_cog[b], free_support[b], free_margin[b], face)
        out = np.flatnonzero(free_margin[b] < 0)
        if out.size:
            free_p[b], free_f[b] = levels[out[0]], topo.neighbour(face, edge)
        agree[b] = (r.size == 0 and out.size == 0) or (r.size > 0 and out.size > 0 and r[0] == out[0]
                                                        and roll_f[b] == free_f[b])
    in_plane = np.linalg.norm(shift[..., :2], axis=-1)
    in_plane_max = float(np.nanmax(in_plane)) if np.isfinite(in_plane).any() else float("nan")
    return {"shift": shift, "margin_change": margin_change, "rolled": rolled, "roll_pressure": roll_p,
            "free_roll_pressure": free_p, "roll_face": roll_f, "free_roll_face": free_f,
            "in_plane_max": in_plane_max, "agree": agree,
            "shift_ok": bool(in_plane_max <= tolerance) if np.isfinite(in_plane_max) else None,
            "roll_ok": bool(agree.all())}


def check_grounded(params: Params, nominals: Mapping[str, xr.Dataset], setup: SweepSetup,
                   settle: float = 0.5, tolerance: float = 5e-3) -> Check:
    """The paper's assumption (III.A-B: cable forces dominate, gravity does not change the
    shape, the robot rolls when the CoG projection leaves the triangle), measured: the pipeline's
    sweep repeated in the grounded mode (gravity, ground, friction; `settle` s on the ground
    first) against the pipeline's nominal CoG (free mode by default).

    4.1 where the robot stays on its face, gravity and contact shift the nominal CoG in the
        support plane by less than `tolerance` m;
    4.2 the grounded robot first rolls at the level where the free CoG projection first leaves
        the triangle, onto the face across the edge it crosses.
    """
    levels = _levels(nominals)
    P = levels.size
    gcog, shift = np.full((2, 12, P, 3), np.nan), np.full((2, 12, P, 3), np.nan)
    dmargin = np.full((2, 12, P), np.nan)
    rolled = np.zeros((2, 12, P), np.int8)
    endf = np.zeros((2, 12, P), np.int64)
    rp, frp = np.full((2, 12), np.nan), np.full((2, 12), np.nan)
    rf, frf = np.zeros((2, 12), np.int64), np.zeros((2, 12), np.int64)
    shift_txt, roll_txt, shift_ok, roll_ok, rows = [], [], [], [], []
    for c, contact in enumerate(CONTACTS):
        ds = nominals.get(contact)
        if ds is None:
            continue
        face = _face(ds)
        fc, fs, fm = full_nominal(ds)
        pairs = [p + 1 for p in range(12) if np.isfinite(fm[p]).all()]
        idx = np.array(pairs) - 1
        run = simulate_nominal(params, face, pairs, setup, mode="grounded", settle=settle)
        cmp_ = compare_grounded(levels, face, fc[idx], fs[idx], fm[idx], run.cog, run.margin,
                                run.end_face, tolerance)
        gcog[c, idx] = np.where(cmp_["rolled"][..., None], np.nan, run.cog)
        shift[c, idx], dmargin[c, idx] = cmp_["shift"], cmp_["margin_change"]
        rolled[c, idx], endf[c, idx] = cmp_["rolled"], run.end_face
        rp[c, idx], frp[c, idx] = cmp_["roll_pressure"], cmp_["free_roll_pressure"]
        rf[c, idx], frf[c, idx] = cmp_["roll_face"], cmp_["free_roll_face"]
        if cmp_["shift_ok"] is not None:
            shift_ok.append(cmp_["shift_ok"])
        roll_ok.append(cmp_["roll_ok"])
        inpl = np.linalg.norm(shift[c, ..., :2], axis=-1)
        if np.isfinite(inpl).any():
            p, k = np.unravel_index(int(np.nanargmax(inpl)), inpl.shape)
            dz = shift[c, ..., 2]
            shift_txt.append(f"{_label(face)}: {_mm(inpl[p, k])} (#{p + 1} at {levels[k]:g} MPa); "
                             f"normal {_mm(np.nanmin(dz))}..{_mm(np.nanmax(dz))}")
        else:
            shift_txt.append(f"{_label(face)}: no level without a roll")
        bad = [int(p) for p in pairs if not cmp_["agree"][pairs.index(p)]]
        if bad:
            by = {}  # pairs with the same outcome share a phrase
            for p in bad:
                a, af, b, bf = rp[c, p - 1], rf[c, p - 1], frp[c, p - 1], frf[c, p - 1]
                key = (f"rolls at {a:g} MPa onto {_label(af) if af else 'an edge'}" if np.isfinite(a)
                       else "does not roll",
                       f"{b:g} MPa onto {_label(bf)}" if np.isfinite(b) else "never")
                by.setdefault(key, []).append(p)
            roll_txt.append(f"{_label(face)}: " + "; ".join(
                f"{', '.join(f'#{p}' for p in ps)} {g_} (free workspace: {f_})" for (g_, f_), ps in by.items()))
        else:
            n_roll = int(np.isfinite(rp[c, idx]).sum())
            roll_txt.append(f"{_label(face)}: all {len(pairs)} pairs agree ({n_roll} roll)")
        for p in pairs:
            inp = np.linalg.norm(shift[c, p - 1, :, :2], axis=-1)
            rows.append([_label(face), f"#{p}",
                         f"{1e3 * np.nanmax(inp):.2f}" if np.isfinite(inp).any() else "n/a",
                         f"{1e3 * np.nanmin(shift[c, p - 1, :, 2]):.2f}" if np.isfinite(inp).any() else "n/a",
                         f"{1e3 * np.nanmin(dmargin[c, p - 1]):.2f}" if np.isfinite(inp).any() else "n/a",
                         f"{frp[c, p - 1]:g} -> {_label(frf[c, p - 1])}" if np.isfinite(frp[c, p - 1]) else "-",
                         f"{rp[c, p - 1]:g} -> {_label(rf[c, p - 1]) if rf[c, p - 1] else 'edge'}"
                         if np.isfinite(rp[c, p - 1]) else "-"])
    mode = "/".join(sorted({str(ds.attrs.get("mode", "free")) for ds in nominals.values()}))
    v1 = Verdict("4.1", f"Gravity and ground contact (grounded mode) barely move the nominal CoG in the "
                        f"support plane while the robot stands (against the {mode} mode)",
                 "; ".join(shift_txt), f"under {_mm(tolerance)} (III.A-B: cable forces dominate)",
                 _status(all(shift_ok)) if shift_ok else SKIP)
    v2 = Verdict("4.2", "The grounded robot rolls first at the level where the free CoG projection "
                        "leaves the triangle, over the same edge",
                 "; ".join(roll_txt), "same level and edge (III.B)", _status(all(roll_ok)) if roll_ok else SKIP)
    data = {
        "grounded_cog": datasets.var(("contact", "pair", "pressure", "axis"), gcog, "m",
                             "nominal CoG in the grounded mode, support frame (NaN once the robot rolled)"),
        "grounded_shift": datasets.var(("contact", "pair", "pressure", "axis"), shift, "m",
                               "grounded minus free nominal CoG, support frame (NaN once the robot rolled)",
                               goal_m=tolerance),
        "grounded_margin_change": datasets.var(("contact", "pair", "pressure"), dmargin, "m",
                                       "grounded minus free margin of the CoG projection (NaN once rolled)"),
        "grounded_rolled": datasets.var(("contact", "pair", "pressure"), rolled, "1",
                                "1 if the grounded robot has left its contact face by the end of the level"),
        "grounded_face": datasets.var(("contact", "pair", "pressure"), endf, "1",
                              "face of the three lowest nodes at the end of the level (0: none)"),
        "grounded_roll_pressure": datasets.var(("contact", "pair"), rp, "MPa",
                                       "level at which the grounded robot first left its face (NaN: never)"),
        "grounded_roll_face": datasets.var(("contact", "pair"), rf, "1", "face the grounded robot rolled onto (0: none)"),
        "free_roll_pressure": datasets.var(("contact", "pair"), frp, "MPa",
                                   "first level at which the free nominal CoG projection is outside the triangle"),
        "free_roll_face": datasets.var(("contact", "pair"), frf, "1", "face across the edge the free CoG projection crosses"),
        "grounded_settle": datasets.var((), settle, "s", "time on the ground at zero pressure before the first level"),
    }
    table = ("Grounded against free mode, per pair (check 4; mm, MPa)",
             ["contact", "pair", "max in-plane shift", "min normal shift", "min margin change",
              "free: leaves at -> face", "grounded: rolls at -> face"], rows)
    return Check("grounded", (v1, v2), data,
                 ("grounded_cog", "grounded_shift", "grounded_margin_change", "grounded_roll_pressure",
                  "free_roll_pressure"), (table,))


# -------------------------------------------------------------------- 5. time step

def check_timestep(params: Params, nominals: Mapping[str, xr.Dataset], setup: SweepSetup,
                   tolerance: float = 1e-4) -> Check:
    """The pipeline's nominal CoG (time step setup.dt) against the same sweep at dt/2 (the same
    sample times: record_every doubled); goal: largest distance under `tolerance` m."""
    levels = _levels(nominals)
    P = levels.size
    hcog, diff = np.full((2, 12, P, 3), np.nan), np.full((2, 12, P), np.nan)
    for c, contact in enumerate(CONTACTS):
        ds = nominals.get(contact)
        if ds is None:
            continue
        fc = full_nominal(ds)[0]
        pairs = [p + 1 for p in range(12) if np.isfinite(fc[p]).all()]
        idx = np.array(pairs) - 1
        run = simulate_nominal(params, _face(ds), pairs, setup, dt=setup.dt / 2,
                               record_every=2 * setup.record_every)
        hcog[c, idx] = run.cog
        diff[c, idx] = np.linalg.norm(fc[idx] - run.cog, axis=-1)
    stmt = f"Nominal CoG at dt = {setup.dt:g} s = the same sweep at dt/2 = {setup.dt / 2:g} s"
    ref = f"under {_mm(tolerance)}"
    data = {"half_dt_cog": datasets.var(("contact", "pair", "pressure", "axis"), hcog, "m",
                                "nominal CoG at half the time step, support frame", dt_s=setup.dt / 2),
            "timestep_difference": datasets.var(("contact", "pair", "pressure"), diff, "m",
                                        "distance between the nominal CoG at dt and at dt/2", goal_m=tolerance)}
    if not np.isfinite(diff).any():
        return Check("timestep", (Verdict("5", stmt, "no sweep", ref, SKIP),), data,
                     ("half_dt_cog", "timestep_difference"))
    c, p, k = np.unravel_index(int(np.nanargmax(diff)), diff.shape)
    meas = (f"largest {_mm(np.nanmax(diff))} (#{p + 1} at {levels[k]:g} MPa on "
            f"{_label(_face(nominals[CONTACTS[c]]))}) over {int(np.isfinite(diff).sum())} cases")
    return Check("timestep", (Verdict("5", stmt, meas, ref, _status(bool(np.nanmax(diff) <= tolerance))),),
                 data, ("half_dt_cog", "timestep_difference"))


# -------------------------------------------------------------------- all checks

def run_checks(cfg: Mapping, nominals: Mapping[str, xr.Dataset], workspace: xr.Dataset | None) -> list[Check]:
    """Every check with the configuration's `validate` section; a check that raises is shown
    as failed with the error (the traceback goes to stderr, i.e. the job's log)."""
    v = cfg["validate"]
    params = params_from_config(cfg)
    setup = SweepSetup.from_config(cfg)
    todo = [
        ("paper", "1", lambda: check_paper(nominals, params.strut_length, v["ranking_pressure"],
                                           v["tip_pressure_tolerance"], v["orbit_tolerance"])),
        ("statics", "2", lambda: check_statics(params, nominals, v["statics_pressures"], v["statics_tolerance"])),
        ("mapping", "3", lambda: check_mapping(params, workspace, v["faces"], setup, v["mapping_tolerance"])),
        ("grounded", "4", lambda: check_grounded(params, nominals, setup, v["grounded_settle"],
                                                 v["grounded_tolerance"])),
        ("timestep", "5", lambda: check_timestep(params, nominals, setup, v["timestep_tolerance"])),
    ]
    out = []
    for name, num, fn in todo:
        print(f"validate: {name} ...", flush=True)
        try:
            chk = fn()
        except Exception as e:  # shown as a failed check, not a stopped workflow
            traceback.print_exc()
            chk = Check(name, (Verdict(num, f"{name} check", f"error: {type(e).__name__}: {e}", "runs", FAIL),))
        for row in chk.verdicts:
            print(f"  {row.id} {row.status}: {row.measured}", flush=True)
        out.append(chk)
    return out
