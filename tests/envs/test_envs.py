"""`tensegrity/Roll-v0` (tensegrity.envs): Gymnasium's own checker, one kernel call per vector
step, the vector robots the same bits as single ones, seeding, the goal frame, the reward as the
CoG's progress, termination (arrival, tumbling, a blown-up state) and the next-step autoreset."""

import warnings

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import tensegrity.envs
from tensegrity.envs import core
from tensegrity.envs.core import RollTask
from tensegrity.envs.single import RollEnv
from tensegrity.envs.vector import RollVectorEnv
from tensegrity.physics import kernel

QUICK = {"settle": 0.2}  # s: a shorter settling keeps the tests quick


def test_single_env_passes_gymnasiums_checker():
    env = gym.make(tensegrity.envs.ROLL, **QUICK)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # any other warning of the checker fails the test
        warnings.filterwarnings("ignore", message=".*symmetric and normalized space.*")  # pressures are MPa
        check_env(env.unwrapped)
        env.reset(seed=0)
        env.step(env.action_space.sample())  # gym.make's passive checker on a real step
    assert isinstance(gym.make_vec(tensegrity.envs.ROLL, 3, "vector_entry_point", **QUICK), RollVectorEnv)


def test_one_kernel_call_per_step_and_the_same_bits_as_single_robots(monkeypatch):
    """Three robots stepped together are, bit for bit, three robots stepped alone (the kernel's
    lanes do not mix robots), and a vector step is one kernel call."""
    calls = []
    real = kernel.advance
    monkeypatch.setattr(kernel, "advance", lambda *a: calls.append(a[0].shape[0]) or real(*a))
    task = RollTask(goal_heading=30.0, **QUICK)
    vec = RollVectorEnv(3, task=task)
    vec.reset(seed=0)
    calls.clear()
    rng = np.random.default_rng(1)
    actions = rng.uniform(0, 4, (10, 3, 12)).astype(np.float32)
    for a in actions:
        obs_v, rew_v, *_ = vec.step(a)
    assert calls == [3] * 10
    for b in range(3):
        one = RollEnv(task=task)
        one.reset(seed=5)
        for a in actions:
            obs, rew, *_ = one.step(a[b])
        np.testing.assert_array_equal(obs, obs_v[b])
        assert rew == rew_v[b]


def test_seeding_draws_the_goals():
    envs = [RollVectorEnv(4, **QUICK) for _ in range(3)]
    g = [e.reset(seed=s)[1]["goal"] for e, s in zip(envs, (7, 7, 8))]
    np.testing.assert_array_equal(g[0], g[1])
    assert not np.allclose(g[0], g[2])
    start = core.start_state(envs[0].params, envs[0].task, envs[0].terrain)
    d = np.linalg.norm(g[0] - start.x[0].mean(0)[:2], axis=1)
    np.testing.assert_allclose(d, 2.0, rtol=1e-12)  # goal_distance from the start CoG
    g = envs[0].reset(options={"goal_headings": [0, 90, 180, 270]})[1]["goal"]
    np.testing.assert_allclose(np.degrees(np.arctan2(*(g - start.x[0].mean(0)[:2]).T[::-1])), [0, 90, 180, -90])
    with pytest.raises(ValueError, match="goal_headings"):
        envs[0].reset(options={"goal_headings": [0, 90]})


def test_goal_frame_and_reward_are_the_cogs_progress():
    """The observed nodes are centred on the CoG (their mean is 0), the frame is a rotation
    (node speeds kept), and the summed reward is progress_scale times the CoG's approach."""
    env = RollVectorEnv(2, goal_heading=-60.0, **QUICK)
    obs, info = env.reset(seed=0)
    d0, total = info["distance"].copy(), 0.0
    a = np.zeros((2, 12), np.float32)
    a[:, 9] = 4.0  # pair #10: the robot leans toward edge 10-12, then rolls
    for _ in range(40):
        obs, r, term, trunc, info = env.step(a)
        total = total + r
        assert not term.any() and not trunc.any()
    nodes = obs[:, core.NODES].reshape(2, 12, 3)
    np.testing.assert_allclose(nodes.mean(axis=1), 0.0, atol=1e-6)
    from tensegrity.physics import dynamics as d

    u = d.node_velocities(env._state, env.params.strut_length)
    vel = obs[:, core.VELOCITIES].reshape(2, 12, 3)
    np.testing.assert_allclose(np.linalg.norm(vel, axis=-1), np.linalg.norm(u, axis=-1), rtol=1e-5, atol=1e-6)
    p = d.nodes(env._state.x, env._state.q, env.params.strut_length)
    to_goal = env._goal - p.mean(axis=1)[:, :2]
    ex = to_goal / np.linalg.norm(to_goal, axis=1, keepdims=True)  # x: horizontal, toward the goal
    np.testing.assert_allclose(
        nodes[..., 0], np.einsum("bnk,bk->bn", (p - p.mean(1, keepdims=True))[..., :2], ex), atol=1e-6
    )
    np.testing.assert_allclose(nodes[..., 2], p[..., 2] - p[..., 2].mean(1, keepdims=True), atol=1e-6)  # z up
    assert np.abs(d0 - info["distance"]).max() > 1e-3  # the robot moved
    np.testing.assert_allclose(total, 10.0 * (d0 - info["distance"]), rtol=1e-9)
    np.testing.assert_allclose(obs[:, core.PRESSURE][:, 9], 1.6, rtol=1e-6)  # 2 MPa/s for 0.8 s, toward 4


@pytest.mark.parametrize(
    "kw, params, arrived",
    [
        ({"arrive_tolerance": 5.0}, None, True),  # the goal is 2 m away: arrived at once
        ({"tumble_speed": 1e-4}, None, False),  # any motion counts as tumbling
        ({"settle": 0.0}, {"max_speed": 1e-3}, False),  # a node faster than max_speed: blown up
    ],
)
def test_termination_and_next_step_autoreset(kw, params, arrived):
    from tensegrity.physics.params import Params

    p = Params(strut_damping=1.0, **(params or {}))
    env = RollVectorEnv(2, params=p, **{**QUICK, **kw})
    env.reset(seed=0)
    a = np.full((2, 12), 3.0, np.float32)
    _, r, term, trunc, info = env.step(a)
    assert term.all() and not trunc.any() and (info["arrived"] == arrived).all()
    assert np.all(r > 5.0) if arrived else np.all(r < -5.0)
    assert (info["status"] != 0).all() == bool(params)
    obs, r, term, trunc, info = env.step(a)  # the autoreset step: the robots are back at the start
    assert (r == 0).all() and not term.any() and not trunc.any()
    np.testing.assert_allclose(info["distance"], 2.0, rtol=1e-9)
    np.testing.assert_array_equal(obs[:, core.PRESSURE], 0.0)


def test_truncation_after_max_steps():
    env = RollEnv(max_steps=3, **QUICK)
    env.reset(seed=0)
    out = [env.step(np.zeros(12, np.float32))[2:4] for _ in range(3)]
    assert out == [(False, False), (False, False), (False, True)]


@pytest.mark.parametrize(
    "kw, word",
    [
        ({"terrain": "bumpy"}, "bumpy"),
        ({"terrain": "none"}, "none"),
        ({"interval": 0.01005}, "interval"),
        ({"max_pressure": 20.0}, "max_pressure"),
        ({"start_face": 21}, "face"),
        ({"goal_distance": -1.0}, "goal_distance"),
    ],
)
def test_bad_settings_are_named_before_any_work(kw, word):
    with pytest.raises(ValueError, match=word):
        RollTask(**kw)


def test_terrain_comes_from_the_command_lines_specs():
    env = RollVectorEnv(1, terrain="slope:10", **QUICK)
    obs, info = env.reset(seed=0)
    assert env.terrain.kind == "plane" and info["face"][0] == 8
    with pytest.raises(ValueError, match="num_envs"):
        RollVectorEnv(0)


def _example() -> dict:
    import runpy
    from pathlib import Path

    return runpy.run_path(str(Path(__file__).resolve().parents[2] / "examples" / "train_cma.py"))


def test_the_training_examples_policy_is_its_own_mirror_image():
    """examples/train_cma.py's policy (without CMA-ES, whose import alone takes seconds): the
    pressures of a robot and of its mirror image across the goal direction (y -> -y) are the
    same, and a policy's episodes run in one vector env."""
    ex = _example()
    env = RollVectorEnv(1, goal_heading=0.0, **QUICK)
    obs, _ = env.reset(seed=0)
    mirror = obs.copy()
    mirror[:, core.NODES] = (obs[:, core.NODES].reshape(-1, 12, 3) * [1, -1, 1]).reshape(-1, 36)
    w = np.random.default_rng(0).normal(size=(1, ex["N_FEATURES"]))
    a, b = ex["act"](w, obs, 6.0, 0.5), ex["act"](w, mirror, 6.0, 0.5)
    np.testing.assert_array_equal(a, b)
    assert a.shape == (1, 12) and (a >= 0).all() and (a <= 6.0).all()
    ret, arrived, dist = ex["episodes"](np.zeros((2, ex["N_FEATURES"])), np.array([0.0, 90.0]), 3, 10.0)
    assert ret.shape == arrived.shape == dist.shape == (2, 2) and not arrived.any()


@pytest.mark.slow
def test_the_training_example_runs(monkeypatch, capsys):
    """examples/train_cma.py end to end on tiny arguments (its figures: docs/benchmarks.md)."""
    import runpy
    import sys
    from pathlib import Path

    script = Path(__file__).resolve().parents[2] / "examples" / "train_cma.py"
    argv = ["--generations", "1", "--popsize", "2", "--tune-headings", "1", "--max-steps", "3"]
    monkeypatch.setattr(sys, "argv", [str(script), *argv])
    runpy.run_path(str(script), run_name="__main__")
    out = capsys.readouterr().out
    assert "generation   1" in out and "arrived 0/8" in out  # 3 steps (0.06 s) reach no goal 2 m away
