import pytest

from tensegrity.physics import dynamics as d
from tensegrity.physics import frames, topology as topo
from tensegrity.physics.actuation import Schedule
from tensegrity.physics.params import Params
from tensegrity.physics.terrain import Terrain

EQUI = topo.face_number((9, 10, 12))
ISO = topo.face_number((10, 11, 12))


@pytest.fixture(scope="session")
def free():
    """Default parameters in the free mode (no gravity; used with Terrain.none())."""
    return Params(gravity=0.0)


def support_cog(traj, params, face):
    """CoG (B, T, 3) and face corners (B, T, 3, 3) in the face's support frame."""
    return frames.in_support_frame(traj.nodes(params.strut_length), face)


def free_sweep(params, face, pairs, levels, hold=1.0, dt=1e-4):
    """Run the staircase in the free mode; return (t, cog_local, tri_local)."""
    s = d.stand_on(params, face, Terrain.none(), batch=len(pairs))
    _, tr = d.simulate(params, s, Schedule.staircase(pairs, levels, hold), Terrain.none(), dt)
    c, tri = support_cog(tr, params, face)
    return tr.t, c, tri
