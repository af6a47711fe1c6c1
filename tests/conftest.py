"""Shared fixtures of the test suite (pytest finds them by name; never import this module)."""

from pathlib import Path

import pytest

from tensegrity.physics import dynamics as d
from tensegrity.physics import frames
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.physics.schedule import Schedule
from tensegrity.physics.terrain import Terrain


@pytest.fixture(scope="session")
def equi() -> int:
    """The canonical equilateral contact face (9,10,12), by number."""
    return topo.face_number(topo.CONTACT_FACES["equilateral"])


@pytest.fixture(scope="session")
def iso() -> int:
    """The canonical isosceles contact face (10,11,12), by number."""
    return topo.face_number(topo.CONTACT_FACES["isosceles"])


@pytest.fixture(scope="session")
def free():
    """Default parameters in the free mode (no gravity; used with Terrain.none())."""
    return Params(gravity=0.0)


@pytest.fixture(scope="session")
def free_sweep():
    """run(params, face, pairs, levels, hold=1.0, dt=1e-4) -> (t, cog, support): the staircase in
    the free mode, CoG (B, T, 3) m and support (B, T, 3, 3) m in the face's support frame."""

    def run(params, face, pairs, levels, hold=1.0, dt=1e-4):
        s = d.stand_on(params, face, Terrain.none(), batch=len(pairs))
        _, tr = d.simulate(params, s, Schedule.staircase(pairs, levels, hold), Terrain.none(), dt)
        return (tr.t, *frames.in_support_frame(tr.nodes(params.strut_length), face))

    return run


_TIER = {
    "physics": "unit",
    "workspace": "unit",
    "locomotion": "unit",
    "validation": "unit",
    "io": "unit",
    "studies": "unit",
    "stages": "unit",
    "bridges": "unit",
    "envs": "unit",
    "calibration": "unit",
    "render": "render",
    "workflow": "workflow",
}


def pytest_collection_modifyitems(items):
    """Mark every test with its tier, from the folder it lives in (select with -m)."""
    root = Path(__file__).parent
    for item in items:
        parts = Path(item.fspath).relative_to(root).parts
        tier = "slurm" if parts[-1] == "test_slurm.py" else _TIER.get(parts[0])
        if tier:
            item.add_marker(getattr(pytest.mark, tier))
