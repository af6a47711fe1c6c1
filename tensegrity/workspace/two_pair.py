"""The two-pair workspace: two actuator pairs driven together over a 2-D pressure grid (issue 10).

A combination is an unordered pair of distinct actuator pairs (a, b), a < b (66 of them,
`COMBOS`); its grid value [i, j] has pair a at levels[i] and pair b at levels[j] MPa. The sweeps
run in the free mode (the paper's assumption, docs/design.md §3) with the nominal averaging of
`workspace.nominal`. Only one combination per orbit of the stabiliser of the canonical face is
swept (`representatives`); every other combination of that face, and every face, follows by
mapping (`map_face`, as `workspace.mapping` does for single pairs). A map can send the first
pair of the source to the second of the target: the grid is transposed then.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from itertools import combinations

import numpy as np
from numpy.typing import ArrayLike

from ..physics import frames
from ..physics import symmetry as sym
from ..physics import topology as topo
from ..physics.params import Params
from ..physics.schedule import Schedule, whole_steps
from ..physics.twisted import TwistedString, Voltages
from . import nominal as nom
from .mapping import CANONICAL

COMBOS = np.array(list(combinations(range(1, topo.N_PAIRS + 1), 2)))  # (66, 2), 1-based, sorted
_INDEX = {tuple(c): k for k, c in enumerate(COMBOS.tolist())}


@dataclass(frozen=True)
class TwoPairSetup:
    """The two-pair staircase: levels (P,) MPa of each pair, each grid point held `hold` s and
    averaged after its first `discard` s, samples every record_every time steps of dt s. The
    defaults are the schema's `two_pair` and `sim` defaults (pinned by tests/io/test_settings.py)."""

    levels: tuple[float, ...] = (0.8, 1.6, 2.4, 3.2, 4.0, 4.8)
    hold: float = 2.0
    discard: float = 0.5
    record_every: int = 50
    dt: float = 1e-4

    def __post_init__(self):
        lv = self.levels
        bad = [i for i in range(1, len(lv)) if lv[i] <= lv[i - 1]]
        if bad:
            raise ValueError(
                f"two_pair.levels[{bad[0]}]: {lv[bad[0]]} is not greater than {lv[bad[0] - 1]} "
                "(MPa, strictly increasing)"
            )
        if not 0 <= self.discard < self.hold:
            raise ValueError(f"two_pair.discard: {self.discard} s is not in [0, two_pair.hold = {self.hold} s)")
        if not whole_steps(self.hold, self.record_every * self.dt):
            raise ValueError(
                f"two_pair.hold: {self.hold} s is not a whole number of recording intervals "
                f"(two_pair.record_every x sim.dt = {self.record_every * self.dt:g} s)"
            )


def combo_index(a: int, b: int) -> int:
    """Row of the combination of pairs a and b (1-based, any order) in COMBOS."""
    return _INDEX[tuple(sorted((topo.check_pair(a), topo.check_pair(b))))]


def stabiliser(face: int) -> list[sym.Symmetry]:
    """Group elements that map `face` (1..20) onto itself: the 3-fold rotations of an
    equilateral face, the mirror of an isosceles face (and the identity)."""
    return [s for s in sym.group() if s.faces[face - 1] == face - 1]


def image(s: sym.Symmetry, combo: Sequence[int]) -> tuple[tuple[int, int], bool]:
    """The combination (a', b') sorted that `s` maps `combo` (a, b) to, and whether it swaps
    the members (s(a) is the larger pair)."""
    a, b = (int(s.pairs[p - 1]) + 1 for p in combo)
    return (min(a, b), max(a, b)), a > b


def representatives(face: int, combos: ArrayLike = COMBOS) -> np.ndarray:
    """One combination (the smallest) of each orbit of the stabiliser of `face` that meets
    `combos` (n, 2): the combinations to sweep, (R, 2) 1-based, sorted."""
    reps = {min(image(s, c)[0] for s in stabiliser(face)) for c in np.asarray(combos, int).tolist()}
    return np.array(sorted(reps), int).reshape(-1, 2)


def grid_order(n: int) -> np.ndarray:
    """(n*n, 2) grid indices (i, j) in the order the staircase visits them: i rising, j up and
    down in turn (boustrophedon), so that every step changes one pair by one level."""
    return np.array([(i, j) for i in range(n) for j in (range(n) if i % 2 == 0 else range(n - 1, -1, -1))])


def schedule(combos: ArrayLike, levels: ArrayLike, hold: float, kind: type[Schedule] = Schedule) -> Schedule:
    """The staircase over the grid (`grid_order`), each point held `hold` s, one robot per
    combination (n, 2) 1-based; levels (P,) MPa, or V for kind=`twisted.Voltages`."""
    combos, levels = np.asarray(combos, int), kind.check(levels, "two_pair.levels")
    order = grid_order(levels.size)
    p = np.zeros((len(combos), len(order), topo.N_PAIRS))
    rows = np.arange(len(combos))[:, None]
    p[rows, :, combos[:, :1] - 1] = levels[order[:, 0]][None]
    p[rows, :, combos[:, 1:] - 1] = levels[order[:, 1]][None]
    return kind(np.full(len(order), float(hold)), p)


def sweep(
    params: Params, face: int, combos: ArrayLike, setup: TwoPairSetup, motors: TwistedString | None = None
) -> dict[str, np.ndarray]:
    """Free-mode staircase of `setup` of every combination (n, 2) standing on `face`, one
    batched run; each grid point's nominal CoG is the mean after the first `discard` s of its
    hold (paper III.A). Returns cog and cog_std (n, 3, P, P, 3) m, support (n, 3, P, P, 3, 3) m: in the
    support frame of the deformed face whose +y points to corner k (axis 1; corner k = the
    reference corner is the face's own support frame, docs/design.md §2, the others are what a
    map of the stabiliser that moves the reference corner needs, `map_face`; NaN for corners
    no such map needs), margin (n, P, P) m and averaging_error (n, P, P) m, the estimated error
    of each grid point's average (`nominal.averaging_error`, in the face's support frame). With
    `motors` (the twisted-string actuator, docs/design.md §10) the levels are motor voltages, V."""
    from ..physics import dynamics as d  # the simulator (numba) only here: mapping, fitting
    from .sweep import setup as mode_setup  # and drawing the two-pair workspace do not load it

    combos, levels = np.asarray(combos, int).reshape(-1, 2), np.asarray(setup.levels, float)
    hold, discard, dt, record_every = setup.hold, setup.discard, setup.dt, setup.record_every
    P, n = levels.size, len(combos)
    prm, terrain = mode_setup(params, "free")
    sched = schedule(combos, levels, hold, Schedule if motors is None else Voltages)
    _, tr = d.simulate(prm, d.stand_on(prm, face, terrain, batch=n), sched, terrain, dt, record_every, motors=motors)
    seg = np.searchsorted(np.cumsum(sched.durations), tr.t - 0.5 * dt * record_every)
    nodes = tr.nodes(prm.strut_length)
    tri = nodes[..., topo.FACES[face - 1], :]
    out = {
        "cog": np.full((n, 3, P, P, 3), np.nan),
        "cog_std": np.full((n, 3, P, P, 3), np.nan),
        "support": np.full((n, 3, P, P, 3, 3), np.nan),
        "averaging_error": np.full((n, P, P), np.nan),
    }
    i, j = grid_order(P).T
    ref_node = topo.FACES[face - 1, topo.FACE_REFERENCE[face - 1]]
    centre = nodes.mean(axis=-2)
    # the frames toward the corners the stabiliser carries onto the reference corner
    for corner in sorted({int(np.flatnonzero(s.nodes[topo.FACES[face - 1]] == ref_node)[0]) for s in stabiliser(face)}):
        origin, rot = frames.support_frame(tri, corner, centre)
        cog = frames.to_frame(centre, origin, rot)
        support = frames.to_frame(tri, origin[..., None, :], rot[..., None, :, :])
        for b in range(n):  # grid point k of the staircase is level k of workspace.nominal
            c, sd, t, _ = nom.nominal(tr.t, seg, cog[b], support[b], P * P, hold, discard)
            out["cog"][b, corner, i, j], out["cog_std"][b, corner, i, j], out["support"][b, corner, i, j] = c, sd, t
            if corner == topo.FACE_REFERENCE[face - 1]:
                out["averaging_error"][b, i, j] = nom.averaging_error(tr.t, seg, cog[b], P * P, hold, discard)
    ref = topo.FACE_REFERENCE[face - 1]
    out["margin"] = margins(out["cog"][:, ref], out["support"][:, ref])
    return out


def combos_of(pairs: Sequence[int]) -> np.ndarray:
    """The combinations (n, 2) of two distinct pairs among `pairs` (1-based)."""
    return COMBOS[np.isin(COMBOS, np.asarray(pairs, int)).all(axis=1)]


def contact_workspace(
    face: int, reps: ArrayLike, res: Mapping[str, np.ndarray], levels: ArrayLike
) -> tuple[dict[str, np.ndarray], np.ndarray, np.ndarray]:
    """The two-pair workspace of every combination on the canonical `face` from the sweep `res`
    (`sweep`) of the representatives `reps` (R, 2) at `levels` (P,) MPa: the arrays of
    `map_face` (cog, support, staircase) with the margin, the tipping pressure, its edge and the
    tipping boundary of each (`tipping`) and the averaging error (66, P, P) m of the swept ones
    (`sweep`; NaN: mapped, the same samples as the combination they map from); which
    combinations were swept (66,) and their CoG spread (66, P, P, 3) m (NaN: mapped)."""
    cog, support, path = map_face(face, face, reps, res["cog"], res["support"])
    ws = {"cog": cog, "support": support, "staircase": path, "margin": margins(cog, support)}
    ws |= tipping(levels, cog, support, ws["margin"], face)
    rows = np.array([combo_index(*c) for c in np.asarray(reps, int)])
    swept = np.isin(np.arange(len(COMBOS)), rows)
    std = np.full(cog.shape, np.nan)
    std[rows] = res["cog_std"][:, topo.FACE_REFERENCE[face - 1]]
    ws["averaging_error"] = np.full(cog.shape[:-1], np.nan)
    ws["averaging_error"][rows] = res["averaging_error"]
    return ws, swept, std


def map_face(
    src: int, dst: int, reps: ArrayLike, cog: np.ndarray, support: np.ndarray, paths: ArrayLike | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Every combination on face `dst` from combinations `reps` (R, 2) on face `src` of the
    same kind: cog (R, 3, P, P, 3) and support (R, 3, P, P, 3, 3) m in src's frames toward each
    corner (`sweep`; NaN: not computed) -> cog (66, P, P, 3), support (66, P, P, 3, 3) m in
    dst's support frame (NaN where nothing maps there) and the staircase order (66, 2) of each:
    the images of `paths` (R, 2) (default reps), the pairs in the order of the grid axes of
    the run the numbers come from (0: none). The nominal of an undamped robot depends a little
    on the path to a grid point, so a direct sweep reproduces a mapped one in that order. A map
    s carries the frame of src toward corner k = s^-1(dst's reference corner) onto dst's support
    frame, flipped in x if s is improper (docs/design.md §1): exact, as the data were averaged in
    that frame."""
    index = {tuple(c): k for k, c in enumerate(np.asarray(reps, int).tolist())}
    P = cog.shape[2]
    out_c, out_s = np.full((len(COMBOS), P, P, 3), np.nan), np.full((len(COMBOS), P, P, 3, 3), np.nan)
    paths = np.asarray(reps if paths is None else paths, int)
    path_out = np.zeros((len(COMBOS), 2), int)
    ref_dst = topo.FACES[dst - 1, topo.FACE_REFERENCE[dst - 1]]
    maps = sorted((s for s in sym.group() if s.faces[src - 1] == dst - 1), key=lambda s: np.linalg.det(s.matrix) < 0)
    for ci, c in enumerate(COMBOS.tolist()):
        for s in maps:
            inv = np.argsort(s.pairs)
            key = tuple(sorted(int(inv[p - 1]) + 1 for p in c))
            img = s.nodes[topo.FACES[src - 1]]
            corner = int(np.flatnonzero(img == ref_dst)[0])  # src corner carried to dst's reference
            if key not in index or not np.isfinite(cog[index[key], corner]).all():
                continue
            k = index[key]
            path_out[ci] = s.pairs[paths[k] - 1] + 1
            order = [int(np.flatnonzero(img == n)[0]) for n in topo.FACES[dst - 1]]
            diag = np.array([np.linalg.det(s.matrix), 1.0, 1.0])
            cc, ss = cog[k, corner] * diag, support[k, corner][..., order, :] * diag
            out_c[ci], out_s[ci] = (cc.swapaxes(0, 1), ss.swapaxes(0, 1)) if image(s, key)[1] else (cc, ss)
            break
    return out_c, out_s, path_out


def in_corner_frames(face: int, cog: np.ndarray, support: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """cog (n, P, P, 3) and support (n, P, P, 3, 3) m in the support frame of `face` as the
    (n, 3, ...) per-corner arrays of `map_face`, NaN for the other corners' frames."""
    ref = topo.FACE_REFERENCE[face - 1]
    c = np.full((cog.shape[0], 3, *cog.shape[1:]), np.nan)
    s = np.full((support.shape[0], 3, *support.shape[1:]), np.nan)
    c[:, ref], s[:, ref] = cog, support
    return c, s


def tipping(
    levels: ArrayLike, cog: np.ndarray, support: np.ndarray, margin: np.ndarray, face: int
) -> dict[str, np.ndarray]:
    """Tipping of n combinations on `face` from their grids cog (n, P, P, 3), support
    (n, P, P, 3, 3) and margin (n, P, P) m at levels (P,) MPa: tip_pressure (n,) MPa, the least
    equal pressure of both pairs at which the CoG projection leaves the triangle, and tip_edge
    (n, 2), the edge crossed (two nodes, (0, 0): none, docs/datasets.md), along the diagonal
    (`frames.crossing`); tip_boundary (n, P) MPa, for each level of the first pair the least
    pressure of the second at which it leaves. NaN where it never leaves or a grid has a NaN."""
    levels = np.asarray(levels, float)
    n, diag = len(margin), np.arange(levels.size)
    out = {
        "tip_pressure": np.full(n, np.nan),
        "tip_edge": np.zeros((n, 2), np.int64),
        "tip_boundary": np.full((n, levels.size), np.nan),
    }
    for c in np.flatnonzero(np.isfinite(margin).reshape(n, -1).all(axis=1)):
        p, _, edge = frames.crossing(levels, margin[c, diag, diag], cog[c, diag, diag], support[c, diag, diag], face)
        out["tip_pressure"][c], out["tip_edge"][c] = p, edge or (0, 0)
        out["tip_boundary"][c] = [frames.first_crossing(levels, m)[0] for m in margin[c]]
    return out


def margins(cog: np.ndarray, support: np.ndarray) -> np.ndarray:
    """Margin (...) m of CoG (..., 3) against support (..., 3, 3) m, NaN where they are NaN."""
    out = np.full(cog.shape[:-1], np.nan)
    ok = np.isfinite(cog[..., 0]) & np.isfinite(support[..., 0, 0])
    out[ok] = frames.margin_2d(cog[ok][:, :2], support[ok][:, :, :2])
    return out


def map_workspace(levels: ArrayLike, canonical: Mapping[str, tuple]) -> dict[str, np.ndarray]:
    """All 20 faces from the canonical contact cases: `canonical` maps 'equilateral' /
    'isosceles' to (combos (n, 2), cog (n, P, P, 3), support (n, P, P, 3, 3) m, staircase
    order (n, 2)) in the support frame of the canonical face. Returns cog (20, 66, P, P, 3),
    support (20, 66, P, P, 3, 3), margin (20, 66, P, P) m, staircase (20, 66, 2) (`map_face`),
    tip_pressure (20, 66) MPa, tip_edge (20, 66, 2) and tip_boundary (20, 66, P) MPa (`tipping`)."""
    levels = np.asarray(levels, float)
    P, F, C = levels.size, topo.N_FACES, len(COMBOS)
    out = {
        "cog": np.full((F, C, P, P, 3), np.nan),
        "support": np.full((F, C, P, P, 3, 3), np.nan),
        "staircase": np.zeros((F, C, 2), int),
    }
    for f in range(1, F + 1):
        kind = str(topo.FACE_TYPES[f - 1])
        if kind in canonical:
            src = CANONICAL[kind]
            combos, cog, support, paths = canonical[kind]
            out["cog"][f - 1], out["support"][f - 1], out["staircase"][f - 1] = map_face(
                src, f, combos, *in_corner_frames(src, cog, support), paths
            )
    out["margin"] = margins(out["cog"], out["support"])
    t = [tipping(levels, out["cog"][f], out["support"][f], out["margin"][f], f + 1) for f in range(F)]
    out |= {k: np.stack([x[k] for x in t]) for k in t[0]}
    return out
