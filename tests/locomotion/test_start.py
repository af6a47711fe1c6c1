"""Start poses that stand (locomotion.start, issue 30 item 3), checked against a plain
simulation of the robot left at rest with no actuation (no controller, no brake)."""

import re

import numpy as np

from tensegrity import cli, paper
from tensegrity import locomotion as lo
from tensegrity.io import config
from tensegrity.io import settings as io_settings
from tensegrity.locomotion import start
from tensegrity.physics import dynamics as d
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.physics.schedule import Schedule
from tensegrity.physics.terrain import Terrain


def _unactuated_travel(params, terrain, poses, seconds=start.STAND_TIME):
    """Horizontal CoG travel (P,) m of each pose (face, yaw) left at rest with zero pressure."""
    st = d.State.concat([d.stand_on(params, f, terrain, yaw_deg=y) for f, y in poses])
    c0 = d.nodes(st.x, st.q, params.strut_length).mean(axis=1)
    st, _ = d.simulate(params, st, Schedule.constant(np.zeros((len(poses), 12)), seconds), terrain, 1e-4, 10000)
    return np.linalg.norm((d.nodes(st.x, st.q, params.strut_length).mean(axis=1) - c0)[:, :2], axis=1)


def test_on_flat_ground_the_paper_start_pose_stands_and_is_the_default(ws):
    s = lo.RollSettings()
    got = start.choose(ws, Params(), Terrain.flat(), s)
    assert (got.face, got.yaw_deg) == (topo.face_number(paper.START_FACE), 0.0)
    assert "chosen" in got.message and "flat ground" in got.message


def test_roll_refuses_a_start_pose_that_tips_and_names_one_that_stands(ws, monkeypatch, capsys):
    """On a 24 deg slope the paper's start face at yaw 0 tips over before any roll (the issue's
    0/8); `roll` stops with exit 3 before simulating the run, and the pose it names stands."""
    from tensegrity.io import formats

    monkeypatch.setattr(formats, "read_workspace", lambda *a, **k: ws)
    argv = ["roll", "--goal", "2,0", "--terrain", "slope:24", "--face", "9,10,12", "--yaw", "0", "--workspace", "x"]
    assert cli.main(argv) == cli.EXIT_INPUT
    err = capsys.readouterr().err
    assert "does not stand on a 24 deg slope" in err, err
    m = re.search(r"\(--face (\d+),(\d+),(\d+) --yaw ([-\d.]+)\) stands", err)
    assert m, err
    named = (topo.face_number([int(m.group(k)) for k in (1, 2, 3)]), float(m.group(4)))
    cfg = config.load()
    params = io_settings.build(lo.RollSettings, cfg).rolling(io_settings.params(cfg))
    tips, stays = _unactuated_travel(params, Terrain.slope(24.0), [(topo.face_number(paper.START_FACE), 0.0), named])
    assert tips > 0.3  # tumbles down the slope (1.4 m in 2 s), not a sag
    assert stays < 0.02  # a standing robot sags by millimetres (8 mm)
