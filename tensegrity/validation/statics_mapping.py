"""Check 3 for a workspace made by statics (nominal.method statics, issue 34): the workspace mapped
by symmetry against the independent static equilibrium (`physics.statics`, energy minimisation)
seen from each sample face, instead of against direct simulations, whose averages would hold
the oscillation left in their windows (up to 0.4 mm with short holds and coarse steps) and so
measure the averaging, not the mapping. The same numbers and verdict as `checks.check_mapping`."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..physics import statics
from ..physics import topology as topo
from ..physics.params import Params
from ..physics.topology import CONTACTS
from ..workspace.lookup import Workspace
from .common import LEVEL_TOL, SKIP, MappingResult, status


def check_mapping_statics(
    params: Params,
    workspace: Workspace,
    faces: Sequence[int],
    levels: Sequence[float],
    tolerance: float,
    min_per_kind: int = 2,
) -> MappingResult:
    """The `MappingResult` of the workspace (results/workspace.nc, a `Workspace`) against the
    static equilibrium of every pair it holds at `levels` (the sweep's, MPa) on each face of
    `faces` (non-canonical; at least `min_per_kind` of each kind): nominal CoG and deformed
    support triangle; goal: largest distance under `tolerance` m. The free robot's equilibrium
    does not depend on the face it is seen from: one solve per pair and level."""
    faces = np.array([topo.face_number(f) for f in faces], np.int64)
    levels = np.asarray(levels, float)
    F, P = len(faces), len(levels)
    cog = np.full((F, topo.N_PAIRS, P, 3), np.nan)
    dcog, dsup = np.full((F, topo.N_PAIRS, P), np.nan), np.full((F, topo.N_PAIRS, P), np.nan)
    canonical = {topo.face_number(f) for f in topo.CONTACT_FACES.values()}
    kinds = {k: sum(1 for f in faces if topo.FACE_TYPES[f - 1] == k and f not in canonical) for k in CONTACTS}
    match = bool(np.allclose(workspace.levels, levels, rtol=0, atol=LEVEL_TOL))
    for p in range(topo.N_PAIRS) if match else ():
        held = [i for i, f in enumerate(faces) if np.isfinite(workspace.cog[f - 1, p]).all()]  # faces with p
        start = None
        for k, lv in enumerate(levels if held else ()):
            prs = np.zeros(topo.N_PAIRS)
            prs[p] = lv
            start = statics.equilibrium(params, prs, start=start)
            for i in held:
                f = int(faces[i])
                c, s = statics.support_cog(start, f)
                cog[i, p, k] = c
                dcog[i, p, k] = np.linalg.norm(workspace.cog[f - 1, p, k] - c)
                dsup[i, p, k] = np.linalg.norm(workspace.support[f - 1, p, k] - s, axis=-1).max()
    if not np.isfinite(dcog).any():
        st = SKIP
    else:
        n_faces = int(np.isfinite(dcog).any(axis=(1, 2)).sum())
        ok = np.nanmax(np.fmax(dcog, dsup)) <= tolerance and min(kinds.values()) >= min_per_kind and n_faces == F
        st = status(bool(ok))
    return MappingResult(
        {"3": st}, faces, levels, tolerance, min_per_kind, match, kinds, cog, dcog, dsup, reference="statics"
    )
