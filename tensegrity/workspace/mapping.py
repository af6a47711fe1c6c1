"""Map the canonical workspaces to all 20 faces with the symmetry group (paper III.A)."""
from __future__ import annotations

import numpy as np

from ..physics import topology as topo
from ..physics import symmetry as sym

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


def map_face(face: int, cog: np.ndarray, support: np.ndarray):
    """Workspace of `face` from the canonical one of its kind: cog (12, P, 3) and support
    (12, P, 3, 3) indexed by 0-based canonical pair -> the same for `face`'s pairs."""
    pair_src, corner_src, diag = face_map(face)
    return cog[pair_src] * diag, support[pair_src][:, :, corner_src] * diag
