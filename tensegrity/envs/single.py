"""`tensegrity/Roll-v0` as a single Gymnasium environment: one robot, the same task and code as
the vector environment (`core`), with Gymnasium's episode rules (reset after the end)."""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np

from ..physics.params import Params
from . import core
from .core import RollTask
from .vector import spaces


class RollEnv(gym.Env):
    """One robot rolling toward a goal (`core`'s task). Arguments: params (scalar `Params`,
    default `core.default_params`); task (`RollTask`) or its fields as keywords."""

    metadata = {"render_modes": []}

    def __init__(self, params: Params | None = None, task: RollTask | None = None, **kw: Any):
        if task is not None and kw:
            raise ValueError(f"give a task or its fields, not both: {sorted(kw)}")
        self.task = task or RollTask(**kw)
        self.params = params or core.default_params()
        self.terrain = self.task.ground()
        self.observation_space, self.action_space = spaces(self.params, self.task)
        self._prm = self.params.pack(1)
        self._start = core.start_state(self.params, self.task, self.terrain)
        self._state = None

    def reset(self, *, seed: int | None = None, options: dict | None = None) -> tuple[np.ndarray, dict]:
        super().reset(seed=seed, options=options)
        h = self.task.goal_heading
        heading = self.np_random.uniform(0.0, 360.0) if h is None else float(h)
        self._state = self._start.copy()
        self._goal = core.goals(self._start, np.array([heading]), self.task.goal_distance)
        self._steps, self._pressure = 0, np.zeros((1, 12))
        obs, dist, face, _ = self._observe()
        self._dist = dist
        return obs[0], self._info(dist, face, np.zeros(1, bool), np.zeros(1, np.int64))

    def step(self, action: np.ndarray) -> tuple[np.ndarray, float, bool, bool, dict]:
        if self._state is None:
            raise RuntimeError("call reset() before step()")
        a = np.asarray(action, dtype=float).reshape(1, 12)
        if not np.all(np.isfinite(a)):
            raise ValueError("action holds NaN or inf")
        self._pressure = core.ramp(self._pressure, a, self.task)
        status = core.advance(self._state, self._prm, self._pressure, self.terrain, self.task)
        self._steps += 1
        obs, dist, face, speed = self._observe()
        reward, terminated, arrived, _ = core.judge(self._dist, dist, speed, status, self.task)
        self._dist = dist
        truncated = bool(not terminated[0] and self._steps >= self.task.max_steps)
        return obs[0], float(reward[0]), bool(terminated[0]), truncated, self._info(dist, face, arrived, status)

    def _observe(self) -> tuple[np.ndarray, ...]:
        return core.observe(self.params, self._state, self._pressure, self._goal, self.terrain, self.task)

    def _info(self, dist: np.ndarray, face: np.ndarray, arrived: np.ndarray, status: np.ndarray) -> dict:
        return {
            "distance": float(dist[0]),
            "face": int(face[0]),
            "arrived": bool(arrived[0]),
            "status": int(status[0]),
            "goal": self._goal[0].copy(),
        }
