"""`tensegrity/Roll-v0` as a Gymnasium vector environment: N robots advanced together, one
kernel call per step (`core.advance`). Autoreset NEXT_STEP (Gymnasium's default): the step
after a robot's episode ended resets it (reward 0, not terminated) instead of stepping it."""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from ..physics.params import Params
from . import core
from .core import RollTask


def spaces(params: Params, task: RollTask) -> tuple[gym.spaces.Box, gym.spaces.Box]:
    """The observation space (OBS_SIZE,) and the action space (12,) MPa of one robot."""
    S, vmax = float(params.strut_length), float(params.max_speed)
    low, high = np.zeros(core.OBS_SIZE, np.float32), np.ones(core.OBS_SIZE, np.float32)
    low[core.NODES], high[core.NODES] = -S, S
    low[core.VELOCITIES], high[core.VELOCITIES] = -vmax, vmax
    high[core.PRESSURE] = task.max_pressure
    high[core.DISTANCE] = np.finfo(np.float32).max
    obs = gym.spaces.Box(low, high, dtype=np.float32)
    act = gym.spaces.Box(0.0, task.max_pressure, (12,), dtype=np.float32)
    return obs, act


class RollVectorEnv(VectorEnv):
    """N robots rolling toward goals (`core`'s task). Arguments: num_envs; params (scalar
    `Params`, default `core.default_params`); task (`RollTask`) or its fields as keywords."""

    metadata = {"autoreset_mode": AutoresetMode.NEXT_STEP, "render_modes": []}

    def __init__(self, num_envs: int = 1, params: Params | None = None, task: RollTask | None = None, **kw: Any):
        if isinstance(num_envs, bool) or not isinstance(num_envs, (int, np.integer)) or num_envs < 1:
            raise ValueError(f"num_envs = {num_envs!r} must be a whole number >= 1")
        if task is not None and kw:
            raise ValueError(f"give a task or its fields, not both: {sorted(kw)}")
        self.task = task or RollTask(**kw)
        self.params = params or core.default_params()
        if self.params.batch_size() is not None:
            raise ValueError("params must be scalar (shared by the robots of the batch)")
        self.num_envs = int(num_envs)
        self.terrain = self.task.ground()
        self.single_observation_space, self.single_action_space = spaces(self.params, self.task)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self._prm = self.params.pack(self.num_envs)
        self._start = core.start_state(self.params, self.task, self.terrain)
        self._state = None

    def _new(self, idx: np.ndarray, heading: np.ndarray | None = None) -> None:
        """Put robots idx at the start with new goals: headings (len(idx),) deg, default the
        task's or drawn from the environment's RNG."""
        n = len(idx)
        h = self.task.goal_heading
        if heading is None:
            heading = self.np_random.uniform(0.0, 360.0, n) if h is None else np.full(n, float(h))
        start = self._start.take(np.zeros(n, np.int64))
        for k in ("x", "v", "q", "w", "anchor", "stuck"):
            getattr(self._state, k)[idx] = getattr(start, k)
        self._goal[idx] = core.goals(self._start, heading, self.task.goal_distance)
        self._pressure[idx] = 0.0
        self._steps[idx] = 0

    def reset(self, *, seed: int | None = None, options: dict | None = None) -> tuple[np.ndarray, dict]:
        """All robots at the start. options={"goal_headings": (N,) deg} sets this episode's
        goals (later episodes: the task's rule)."""
        super().reset(seed=seed, options=options)
        n = self.num_envs
        unknown = set(options or {}) - {"goal_headings"}
        if unknown:
            raise ValueError(f"unknown reset option(s) {sorted(unknown)}: the one option is goal_headings")
        heading = (options or {}).get("goal_headings")
        if heading is not None:
            heading = np.asarray(heading, dtype=float)
            if heading.shape != (n,) or not np.all(np.isfinite(heading)):
                raise ValueError(f"goal_headings must be {n} finite numbers (deg), got shape {heading.shape}")
        self._state = self._start.take(np.zeros(n, np.int64)).copy()
        self._goal, self._steps, self._pressure = np.zeros((n, 2)), np.zeros(n, np.int64), np.zeros((n, 12))
        self._new(np.arange(n), heading)
        obs, dist, face, _ = self._observe()
        self._dist, self._autoreset = dist, np.zeros(n, bool)
        return obs, self._info(dist, face, np.zeros(n, bool), np.zeros(n, np.int64))

    def step(self, actions: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, dict]:
        if self._state is None:
            raise RuntimeError("call reset() before step()")
        a = np.asarray(actions, dtype=float).reshape(self.num_envs, 12)
        if not np.all(np.isfinite(a)):
            raise ValueError("actions hold NaN or inf")
        self._pressure = core.ramp(self._pressure, a, self.task)  # within the Box's bounds
        status = core.advance(self._state, self._prm, self._pressure, self.terrain, self.task)
        self._steps += 1
        redo = np.flatnonzero(self._autoreset)
        if redo.size:
            self._new(redo)
            status[redo] = 0
        obs, dist, face, speed = self._observe()
        reward, terminated, arrived, _ = core.judge(self._dist, dist, speed, status, self.task)
        truncated = ~terminated & (self._steps >= self.task.max_steps)
        reward[redo], terminated[redo], truncated[redo], arrived[redo] = 0.0, False, False, False
        self._dist, self._autoreset = dist, terminated | truncated
        return obs, reward, terminated, truncated, self._info(dist, face, arrived, status)

    def _observe(self) -> tuple[np.ndarray, ...]:
        return core.observe(self.params, self._state, self._pressure, self._goal, self.terrain, self.task)

    def _info(self, dist: np.ndarray, face: np.ndarray, arrived: np.ndarray, status: np.ndarray) -> dict:
        """Per-robot info, every key with its all-true mask `_key` (Gymnasium's vector info)."""
        info = {"distance": dist, "face": face, "arrived": arrived, "status": status, "goal": self._goal.copy()}
        return {**info, **{f"_{k}": np.ones(self.num_envs, bool) for k in info}}
