"""Map the canonical workspaces to all 20 faces with the symmetry group (paper III.A)."""

from __future__ import annotations

from collections.abc import Iterable, Mapping

import numpy as np
from numpy.typing import ArrayLike

from ..physics import frames
from ..physics import symmetry as sym
from ..physics import topology as topo

CANONICAL = {kind: topo.face_number(nodes) for kind, nodes in topo.CONTACT_FACES.items()}


def face_map(face: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For 1-based `face`: the canonical pair index feeding each target pair (12,), the canonical
    corner index feeding each target corner (3,), and the diagonal (3,) that carries support-frame
    coordinates of the canonical face to those of `face` (x flips under an improper map)."""
    src = CANONICAL[str(topo.FACE_TYPES[face - 1])]
    s = max(sym.maps_between(src, face), key=lambda s: np.linalg.det(s.matrix))  # proper if any
    pair_src = np.argsort(s.pairs)  # target pair p comes from canonical pair s^-1(p)
    img = s.nodes[topo.FACES[src - 1]]
    corner_src = np.array([int(np.flatnonzero(img == n)[0]) for n in topo.FACES[face - 1]])
    return pair_src, corner_src, np.array([np.linalg.det(s.matrix), 1.0, 1.0])


def map_face(face: int, cog: np.ndarray, support: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Workspace of `face` from the canonical one of its kind: cog (12, P, 3) and support
    (12, P, 3, 3) indexed by 0-based canonical pair -> the same for `face`'s pairs."""
    pair_src, corner_src, diag = face_map(face)
    return cog[pair_src] * diag, support[pair_src][:, :, corner_src] * diag


def all_pairs(pairs: ArrayLike, values: np.ndarray) -> np.ndarray:
    """`values` (n, ...) of the swept 1-based `pairs` (n,) spread over all 12 pairs (12, ...),
    NaN for the pairs that were not swept."""
    values = np.asarray(values, float)
    out = np.full((topo.N_PAIRS, *values.shape[1:]), np.nan)
    out[np.asarray(pairs, int) - 1] = values
    return out


def same_levels(levels: Iterable[ArrayLike]) -> np.ndarray:
    """The pressure levels (P,) MPa shared by every contact case in `levels` (a sequence of
    (P,) arrays); ValueError if there is none or they differ."""
    levels = [np.asarray(lv, float) for lv in levels]
    if not levels:
        raise ValueError("no nominal dataset given")
    if any(not np.array_equal(lv, levels[0]) for lv in levels[1:]):
        raise ValueError("the contact cases were swept at different pressure levels")
    return levels[0]


def map_workspace(levels: ArrayLike, canonical: Mapping[str, tuple]) -> dict[str, np.ndarray]:
    """The workspace of all 20 faces from the canonical contact cases.

    levels (P,) MPa; canonical maps 'equilateral'/'isosceles' to (pairs (n,), cog (n, P, 3) m,
    support (n, P, 3, 3) m) in the canonical face's support frame; a missing case leaves its
    faces NaN. Returns cog (20, 12, P, 3) m, support (20, 12, P, 3, 3) m, margin (20, 12, P) m
    and tip_pressure (20, 12) MPa (NaN where not swept or never tipping)."""
    levels = np.asarray(levels, float)
    P = levels.size
    cog = np.full((topo.N_FACES, topo.N_PAIRS, P, 3), np.nan)
    support = np.full((topo.N_FACES, topo.N_PAIRS, P, 3, 3), np.nan)
    for face in range(1, topo.N_FACES + 1):
        case = canonical.get(str(topo.FACE_TYPES[face - 1]))
        if case is not None:
            pairs, c, s = case
            cog[face - 1], support[face - 1] = map_face(face, all_pairs(pairs, c), all_pairs(pairs, s))
    margin = np.full(cog.shape[:-1], np.nan)
    ok = np.isfinite(cog[..., 0])
    margin[ok] = frames.margin_2d(cog[ok][:, :2], support[ok][:, :, :2])
    tip = np.array(
        [[frames.first_crossing(levels, m)[0] if np.isfinite(m).all() else np.nan for m in mf] for mf in margin]
    )
    return {"cog": cog, "support": support, "margin": margin, "tip_pressure": tip}
