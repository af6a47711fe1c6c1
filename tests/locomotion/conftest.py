"""Shared fixtures of the locomotion tests: the workspace computed once per session by the
independent static solver (tensegrity.physics.statics) at 0.8..4.8 MPa; it agrees with the dynamic
free-mode workspace of the pipeline to 0.03 mm."""

import numpy as np
import pytest

from tensegrity import locomotion as lo
from tensegrity.physics import statics
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.workspace import mapping

LEVELS = [0.8, 1.6, 2.4, 3.2, 4.0, 4.8]


@pytest.fixture(scope="session")
def levels() -> list[float]:
    """The swept pressures of `ws`, MPa (a fixture: `from conftest import` names whichever
    conftest.py was imported first)."""
    return LEVELS


@pytest.fixture(scope="session")
def ws():
    free = Params(gravity=0.0)
    canon = {}
    for kind, face in topo.CONTACT_FACES.items():
        c = np.empty((12, len(LEVELS), 3))
        t = np.empty((12, len(LEVELS), 3, 3))
        for pair in range(1, 13):
            nodes = None
            for k, lev in enumerate(LEVELS):
                p = np.zeros(12)
                p[pair - 1] = lev
                nodes = statics.equilibrium(free, p, start=nodes)
                c[pair - 1, k], t[pair - 1, k] = statics.support_cog(nodes, face)
        canon[kind] = (c, t)
    cog = np.empty((20, 12, len(LEVELS), 3))
    sup = np.empty((20, 12, len(LEVELS), 3, 3))
    for face in range(1, 21):
        cog[face - 1], sup[face - 1] = mapping.map_face(face, *canon[str(topo.FACE_TYPES[face - 1])])
    return lo.Workspace.from_arrays(LEVELS, cog, sup)
