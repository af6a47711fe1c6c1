"""The MuJoCo export (tensegrity.bridges.mjcf) against the toolkit's own physics: the cable law
force by force (eq. 1-2, the NumPy twin), MuJoCo's settled free-mode CoG against the independent
statics (S1-S2) for every pair at 1.2, 2.4 and 3.6 MPa, and free-mode node trajectories over 2 s
against `dynamics.simulate` (the same semi-implicit Euler: agreement to round-off)."""

import mujoco
import numpy as np
import pytest
from mujoco import rollout

from tensegrity import paper
from tensegrity.bridges.mjcf import cable_name, controls, exact_below, mjcf
from tensegrity.physics import actuator, frames, statics
from tensegrity.physics import dynamics as d
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.physics.schedule import Schedule
from tensegrity.physics.terrain import Terrain

FREE = Params(gravity=0.0)
LEVELS = (1.2, 2.4, 3.6)  # MPa
TOL = 1e-9  # m = 1e-6 mm (issue 33); both sides converge to round-off (~1e-15 m)


def _model(params=FREE, mode="free", **kw):
    return mujoco.MjModel.from_xml_string(mjcf(params, mode, **kw))


def _nodes(model, data) -> np.ndarray:
    """Node positions (12, 3) m, node order, from the sites `node1`..`node12`."""
    return np.array([data.site(f"node{n}").xpos for n in range(1, topo.N_NODES + 1)])


def test_the_model_holds_the_robot():
    """Names, masses, inertias, gravity, contact and the time step are those of the parameters."""
    p = Params(strut_mass=0.3, strut_length=0.6)
    for mode, g in (("free", 0.0), ("grounded", p.gravity)):
        m = _model(p, mode, dt=5e-4)
        assert (m.nbody, m.njnt, m.ntendon, m.nu) == (7, 6, 24, 24)
        assert m.opt.timestep == 5e-4 and np.allclose(m.opt.gravity, [0, 0, -g])
        assert np.allclose(m.body_mass[1:], 0.3)
        It = 0.3 * (0.6**2 / 12 + 0.01**2 / 4)
        assert np.allclose(m.body_inertia[1:], [It, It, 0.3 * 0.01**2 / 2])
        assert m.ngeom == (13 if mode == "grounded" else 0)  # a sphere per node and the plane
    names = [mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_ACTUATOR, i) for i in range(24)]
    assert names == [f"cable_{a + 1}_{b + 1}" for a, b in topo.CABLES] == [cable_name(j) for j in range(24)]
    assert all(int(n.split("_")[1]) < int(n.split("_")[2]) for n in names)


def test_actuator_force_is_the_cable_law():
    """MuJoCo's actuator force on random states (slack, taut, shorter than Lmin, moving) is minus
    the tension of eq. 1-2 (`actuator.tensions`, the NumPy twin of the kernel's law), wherever
    the rate is below `exact_below` (module docstring), and never positive (no pushing)."""
    rng = np.random.default_rng(7)
    m, data = _model(), None
    data = mujoco.MjData(m)
    rows = actuator.constants([getattr(FREE, k) for k in actuator.NAMES])
    checked = 0
    for _ in range(40):
        s = d.stand_on(FREE, 8, Terrain.none())
        data.qpos[:] = np.concatenate(
            [s.x[0] + rng.normal(0, 0.03, (6, 3)), s.q[0] + rng.normal(0, 0.1, (6, 4))], 1
        ).ravel()
        data.qvel[:] = rng.normal(0, 1.0, 36)
        pressure = rng.uniform(0, 4.8, 12)
        data.ctrl[:] = controls(pressure)
        mujoco.mj_forward(m, data)
        ln, ldot = data.ten_length.copy(), data.ten_velocity.copy()
        want = actuator.tensions(ln, ldot, actuator.activations(FREE.muscle_gain, pressure), rows[:, None])
        ok = (ln >= FREE.muscle_min_length) | (ldot < exact_below(FREE))
        assert np.all(data.actuator_force <= 0.0)
        np.testing.assert_allclose(-data.actuator_force[ok], want[ok], rtol=1e-12, atol=1e-9)
        checked += ok.sum()
    assert checked > 900 and np.any(want == 0) and np.any(want > 0)


def _settle(model, pressure: np.ndarray, qpos: np.ndarray) -> np.ndarray:
    """MuJoCo's equilibrium at rest under pair pressures (12,) MPa from qpos: Newton on MuJoCo's
    own generalised forces (qfrc_actuator at qvel = 0; free mode: nothing else acts), the
    Jacobian by central differences in MuJoCo's tangent space (mj_integratePos), the six
    rigid motions left out by lstsq. Returns the settled qpos."""
    data = mujoco.MjData(model)
    data.ctrl[:] = controls(pressure)
    data.qpos[:] = qpos

    def force(q):
        data.qpos[:] = q
        mujoco.mj_forward(model, data)
        return data.qfrc_actuator.copy()

    q = qpos.copy()
    for _ in range(40):
        r = force(q)
        if np.abs(r).max() < 1e-11:  # N and N m; stiffness ~1e3 N/m: ~1e-14 m
            return q
        J = np.empty((model.nv, model.nv))
        for k in range(model.nv):
            qp, qm, dv = q.copy(), q.copy(), np.zeros(model.nv)
            dv[k] = 1e-6
            mujoco.mj_integratePos(model, qp, dv, 1.0)
            mujoco.mj_integratePos(model, qm, -dv, 1.0)
            J[:, k] = (force(qp) - force(qm)) / 2e-6
        mujoco.mj_integratePos(model, q, np.linalg.lstsq(J, -r, rcond=1e-7)[0], 1.0)
    raise AssertionError(f"MuJoCo's equilibrium not found: residual {np.abs(r).max():.3g}")


def _settled_cogs(pair: int) -> tuple[np.ndarray, np.ndarray]:
    """CoG (3, 3) m in the support frame of the paper's start face at LEVELS on `pair`: MuJoCo
    settled (`_settle`, each level from the last) and the statics (static_workspace)."""
    model = _model()
    q = model.qpos0.copy()
    data, ours = mujoco.MjData(model), []
    for level in LEVELS:
        p = np.zeros(12)
        p[pair - 1] = level
        q = _settle(model, p, q)
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        ours.append(frames.in_support_frame(_nodes(model, data), paper.START_FACE)[0])
    return np.array(ours), statics.static_workspace(FREE, paper.START_FACE, pair, LEVELS)[0]


def _check_settled(pair):
    mj, st = _settled_cogs(pair)
    rest = frames.in_support_frame(topo.reference_nodes(FREE.strut_length), paper.START_FACE)[0]
    assert np.abs(st - rest).max() > 1e-3  # the pressures move the CoG (> 1 mm), so the match says something
    assert np.abs(mj - st).max() < TOL, (mj - st) * 1e3


@pytest.mark.parametrize("pair", [10, 11])
def test_settled_cog_equals_statics(pair):
    """Two pairs in the default run (#10 rolls the robot at 4.2 MPa; #11 barely moves it on this
    face); all twelve under `slow`."""
    _check_settled(pair)


@pytest.mark.slow
@pytest.mark.parametrize("pair", [p for p in range(1, 13) if p not in (10, 11)])
def test_settled_cog_equals_statics_every_pair(pair):
    _check_settled(pair)


def test_free_trajectories_agree_over_two_seconds():
    """Three robots, pressures on different pairs (1.2, 2.4, 3.6 MPa), 2 s of free motion from
    rest: MuJoCo's Euler with the exported model and `dynamics.simulate` agree at every 10 ms
    to < 1e-6 mm, while the nodes move by centimetres."""
    dt, every, n = 1e-4, 100, 20000
    pressure = np.zeros((3, 12))
    pressure[[0, 1, 2], [9, 3, 6]] = LEVELS
    state = d.stand_on(FREE, paper.START_FACE, Terrain.none(), batch=3)
    _, tr = d.simulate(FREE, state, Schedule.constant(pressure, n * dt), Terrain.none(), dt, every)
    ours = tr.nodes(FREE.strut_length)
    model = _model(state=state.take([0]))
    data = mujoco.MjData(model)
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    x0 = np.empty((3, mujoco.mj_stateSize(model, spec)))
    for b in range(3):
        mujoco.mj_resetData(model, data)
        mujoco.mj_getState(model, data, x0[b], spec)
    out = np.empty((3, n, x0.shape[1]))
    ctrl = np.ascontiguousarray(np.broadcast_to(controls(pressure)[:, None], (3, n, 24)))
    rollout.rollout(model, data, x0, ctrl, state=out, nstep=n)
    rec = out[:, every - 1 :: every, 1 : 1 + model.nq].reshape(3, -1, 6, 7)
    theirs = d.nodes(rec[..., :3], rec[..., 3:], FREE.strut_length)
    moved = np.abs(ours - ours[:, :1]).max()
    assert moved > 0.01, moved
    assert np.abs(ours - theirs).max() < TOL, np.abs(ours - theirs).max() * 1e3


@pytest.mark.parametrize(
    "change, word",
    [({"cable_exponent": 1.5}, "cable_exponent"), ({"strut_damping": 1.0}, "strut_damping")],
)
def test_what_cannot_be_written_is_refused_by_name(change, word):
    with pytest.raises(ValueError, match=word):
        mjcf(Params().replace(**change))
    with pytest.raises(ValueError, match="mode"):
        mjcf(Params(), "sloped")


def test_another_actuator_law_is_refused(monkeypatch):
    """A law with other fields than eq. 1-2's (say, issue 31's motor-driven actuator) is not
    silently exported as eq. 1-2."""
    monkeypatch.setattr(actuator, "NAMES", (*actuator.NAMES, "motor_voltage"))
    with pytest.raises(NotImplementedError, match="motor_voltage"):
        mjcf(Params())


def test_command_writes_a_model_mujoco_loads(tmp_path, capsys):
    """`tensegrity export mjcf` writes the configured design (--set reaches it); a bad mode is a
    usage error before anything is written."""
    from tensegrity.cli import main

    out, bad = tmp_path / "robot.xml", tmp_path / "bad.xml"
    cmd = ["export", "mjcf", "--mode", "grounded", "--set", "params.strut_mass=0.25"]
    assert main([*cmd, "--out", str(out)]) == 0
    m = mujoco.MjModel.from_xml_path(str(out))
    assert np.allclose(m.body_mass[1:], 0.25) and m.opt.gravity[2] < 0
    data = mujoco.MjData(m)
    mujoco.mj_forward(m, data)
    assert np.abs(_nodes(m, data)[:, 2].min() - 0.01) < 1e-12  # standing on the plane, radius r
    with pytest.raises(SystemExit) as e:
        main(["export", "mjcf", "--out", str(bad), "--mode", "sloped"])
    assert e.value.code == 2 and "sloped" in capsys.readouterr().err and not bad.exists()
    assert main(["export", "mjcf", "--out", str(bad), "--set", "params.cable_exponent=2"]) == 3
    assert "cable_exponent" in capsys.readouterr().err and not bad.exists()
