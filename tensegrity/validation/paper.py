"""Check 1: the paper's statements (III.A, III.C, IV.B) against the pipeline's nominal CoG.
Numbers and statuses only (`PaperResult`); `validation.summary` words them."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from .. import paper
from ..physics import frames
from ..physics import symmetry as sym
from ..physics import topology as topo
from ..physics.params import Params
from ..physics.topology import CONTACTS
from ..workspace.nominal import Nominal
from .common import LEVEL_TOL, N_CONTACTS, SKIP, CheckSettings, Result, status
from .nominals import common_levels

# The paper's statements are `tensegrity.paper`'s. The pressure of the second roll is not given:
# the prototype needed 6 V against 11.1 V for the first (IV.B), i.e. a lower drive.


def migration(levels: ArrayLike, cog: np.ndarray, rest: np.ndarray, pressure: float) -> np.ndarray:
    """In-plane distance (m) of the nominal CoG from the unactuated CoG `rest` (3,) m at
    `pressure` MPa, linearly interpolated between `levels` (P,) MPa; cog (n, P, 3) m -> (n,).
    ValueError if `pressure` is outside the levels."""
    levels = np.asarray(levels, float)
    if not levels[0] - LEVEL_TOL <= pressure <= levels[-1] + LEVEL_TOL:
        raise ValueError(f"pressure {pressure} MPa is outside the swept levels {levels[0]}..{levels[-1]} MPa")
    xy = np.stack([[np.interp(pressure, levels, c[:, a]) for a in range(2)] for c in cog])
    return np.linalg.norm(xy - rest[:2], axis=1)


def _face_rotations(face: int) -> list[sym.Symmetry]:
    f = face - 1
    return [s for s in sym.group() if s.faces[f] == f and np.linalg.det(s.matrix) > 0]


def three_fold_orbits(face: int) -> list[tuple[int, ...]]:
    """Orbits (1-based pair numbers) of the pairs under the rotations keeping `face` (1..20):
    the 3-fold rotation of an equilateral face; only the identity for an isosceles face."""
    rots = _face_rotations(face)
    seen, orbits = set(), []
    for p in range(topo.N_PAIRS):
        if p not in seen:
            orb = sorted({int(s.pairs[p]) for s in rots})
            seen.update(orb)
            orbits.append(tuple(q + 1 for q in orb))
    return orbits


def orbit_spread(
    cog: np.ndarray, support: np.ndarray, face: int, orbit: Sequence[int]
) -> tuple[np.ndarray, np.ndarray]:
    """How unequally the pairs of a 3-fold orbit move the CoG, per level: the largest distance
    (m) between a member's CoG and the first member's, each expressed with y toward the corner
    its rotation carries the reference vertex to (the deformed triangle is not exactly
    equilateral, so the fixed frame would show a spurious difference), and the spread (m) of
    the in-plane distances from the centroid. cog (N_PAIRS, P, 3) m, support (N_PAIRS, P, 3, 3)
    m in the support frame of `face` -> (P,), (P,)."""
    f = face - 1
    nodes = list(topo.FACES[f])
    ref = topo.FACES[f, topo.FACE_REFERENCE[f]]
    rots = _face_rotations(face)
    rel = []
    for pair in orbit:
        s = next(s for s in rots if s.pairs[orbit[0] - 1] == pair - 1)
        corner = nodes.index(s.nodes[ref])
        v = support[pair - 1, :, corner, :2]
        ang = np.arctan2(v[:, 0], v[:, 1])  # turn the frame so that y points to `corner`
        c, sn = np.cos(ang), np.sin(ang)
        x, y = cog[pair - 1, :, 0], cog[pair - 1, :, 1]
        rel.append(np.stack([c * x - sn * y, sn * x + c * y, cog[pair - 1, :, 2]], axis=-1))
    rel = np.array(rel)  # (members, P, 3)
    diff = np.linalg.norm(rel - rel[0], axis=-1).max(axis=0)
    mag = np.linalg.norm(rel[..., :2], axis=-1)
    return diff, mag.max(axis=0) - mag.min(axis=0)


@dataclass(frozen=True)
class PaperResult(Result):
    """Numbers of check 1 on the contact cases C = CONTACTS (equilateral, isosceles) and all
    N_PAIRS pairs; NaN where not computed.

    levels (P,) MPa; faces: contact -> face (1..20) of each contact case given; the settings
    ranking_pressure MPa, tip_tolerance MPa, orbit_tolerance m; swept (C, N_PAIRS) bool, the pair
    was swept at every level; migration (C, N_PAIRS) m at ranking_pressure; ranking_in_levels,
    ranking_pressure is among the swept range; ranking (N_PAIRS,) 1-based pairs by decreasing
    migration on the equilateral case (empty if 1.1 was not evaluated); tip_pressure (C, N_PAIRS)
    MPa (NaN: never) and tip_edge (C, N_PAIRS, 2) its nodes (0: none); orbit_pairs (orbits,
    members) of the paper's equilateral face (0 unless that face was given); orbit_difference and orbit_magnitude_spread
    (orbits, P) m (`orbit_spread`); status of verdicts 1.1-1.5."""

    levels: np.ndarray
    faces: dict[str, int]
    ranking_pressure: float
    tip_tolerance: float
    orbit_tolerance: float
    swept: np.ndarray
    migration: np.ndarray
    ranking_in_levels: bool
    ranking: np.ndarray
    tip_pressure: np.ndarray
    tip_edge: np.ndarray
    orbit_pairs: np.ndarray
    orbit_difference: np.ndarray
    orbit_magnitude_spread: np.ndarray


def check_paper(
    nominals: Mapping[str, Nominal],
    strut_length: float = Params.strut_length,
    ranking_pressure: float = CheckSettings.ranking_pressure,
    tip_tolerance: float = CheckSettings.tip_pressure_tolerance,
    orbit_tolerance: float = CheckSettings.orbit_tolerance,
    tip_pressure: np.ndarray | None = None,
) -> PaperResult:
    """The paper's statements against the nominal CoG of the contact cases (`nominals` maps
    'equilateral'/'isosceles' to its `Nominal`, results/nominal/{contact}.nc; strut length m):

    1.1 standing on (9,10,12), #9, #10, #12 move the CoG most and #4, #6, #7 next (III.A, Fig. 7),
        ranked by the in-plane distance from the unactuated CoG at `ranking_pressure` MPa;
    1.2 #10 moves the CoG projection out over edge 10-12 at 4.2 MPa (+- `tip_tolerance` MPa);
    1.3 standing on (10,11,12), #11 moves it out over edge 10-11 (the roll to (6,10,11), IV.B);
    1.4 ... at a lower pressure than #10 needs on (9,10,12) (6 V against 11.1 V, IV.B);
    1.5 the pairs of each 3-fold orbit of (9,10,12) move the CoG equally (`orbit_tolerance` m).

    `tip_pressure` (C, N_PAIRS) MPa, if given, replaces the crossings interpolated between the
    levels (e.g. roots of the static margin, `workspace.equilibria`); the edges stay those
    crossed at the first level outside.
    """
    levels = common_levels(nominals)
    P = levels.size
    tipp = np.full((N_CONTACTS, topo.N_PAIRS), np.nan)
    edges = np.zeros((N_CONTACTS, topo.N_PAIRS, 2), dtype=np.int64)
    mig = np.full((N_CONTACTS, topo.N_PAIRS), np.nan)
    swept = np.zeros((N_CONTACTS, topo.N_PAIRS), bool)
    arrays, faces = {}, {}
    for c, contact in enumerate(CONTACTS):
        n = nominals.get(contact)
        if n is None:
            continue
        face = faces[contact] = n.face
        cog, sup, mar = arrays[contact] = n.cog, n.support, n.margin
        swept[c] = np.isfinite(mar).all(axis=1)
        for p in np.flatnonzero(swept[c]):
            tipp[c, p], _, e = frames.crossing(levels, mar[p], cog[p], sup[p], face)
            edges[c, p] = e or (0, 0)
            if tip_pressure is not None:
                tipp[c, p] = tip_pressure[c, p]
        try:
            mig[c] = migration(levels, cog, frames.rest_frame(face, strut_length)[0], ranking_pressure)
        except ValueError:
            pass
    st: dict[str, str] = {}
    eq, iso = CONTACTS
    on_paper = {k: k in faces and faces[k] == topo.face_number(topo.CONTACT_FACES[k]) for k in CONTACTS}

    # 1.1 ranking
    in_levels = bool(levels[0] - LEVEL_TOL <= ranking_pressure <= levels[-1] + LEVEL_TOL)
    ranking = np.zeros(0, np.int64)
    if eq not in faces or not np.isfinite(mig[0]).all():
        st["1.1"] = SKIP
    else:
        ranking = np.argsort(-mig[0], kind="stable") + 1
        st["1.1"] = status(
            on_paper[eq] and set(ranking[:3]) == set(paper.LARGE_PAIRS) and set(ranking[3:6]) == set(paper.LESS_PAIRS)
        )

    # 1.2, 1.3, 1.4 tipping pressures and edges
    p10, p11 = tipp[0, 10 - 1], tipp[1, 11 - 1]
    st["1.2"] = (
        SKIP
        if not swept[0, 10 - 1]
        else status(
            bool(
                on_paper[eq]
                and abs(p10 - paper.TIP_PRESSURE) <= tip_tolerance
                and set(edges[0, 10 - 1]) == set(paper.EDGE[10])
            )
        )
    )
    st["1.3"] = (
        SKIP if not swept[1, 11 - 1] else status(bool(on_paper[iso] and set(edges[1, 11 - 1]) == set(paper.EDGE[11])))
    )
    st["1.4"] = (
        SKIP
        if not (swept[0, 10 - 1] and swept[1, 11 - 1])
        else status(bool(np.isfinite(p11) and (not np.isfinite(p10) or p11 < p10)))
    )

    # 1.5 three-fold orbits
    orbits = three_fold_orbits(topo.face_number(topo.CONTACT_FACES[eq]))
    size = max(len(o) for o in orbits)
    odiff, ospread = np.full((len(orbits), P), np.nan), np.full((len(orbits), P), np.nan)
    opairs = np.zeros((len(orbits), size), dtype=np.int64)
    if on_paper[eq]:
        cog, sup, _ = arrays[eq]
        for i, orb in enumerate(orbits):
            opairs[i, : len(orb)] = orb
            if np.isfinite(cog[np.array(orb) - 1]).all():
                odiff[i], ospread[i] = orbit_spread(cog, sup, faces[eq], orb)
    st["1.5"] = SKIP if not np.isfinite(odiff).all(axis=1).any() else status(bool(np.nanmax(odiff) <= orbit_tolerance))
    return PaperResult(
        status=st,
        levels=levels,
        faces=faces,
        ranking_pressure=ranking_pressure,
        tip_tolerance=tip_tolerance,
        orbit_tolerance=orbit_tolerance,
        swept=swept,
        migration=mig,
        ranking_in_levels=in_levels,
        ranking=ranking,
        tip_pressure=tipp,
        tip_edge=edges,
        orbit_pairs=opairs,
        orbit_difference=odiff,
        orbit_magnitude_spread=ospread,
    )
