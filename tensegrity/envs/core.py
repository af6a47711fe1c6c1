"""The rolling task over the batched kernel (issue 33, item 2), as plain functions on arrays that
the single and the vector Gymnasium environments share: the task's settings (`RollTask`), the
start state, one control step of N robots in one kernel call (`advance`), the observation and
the reward.

Observation of a robot, float32 (OBS_SIZE,) = 106, in the **goal frame** tied to the robot:
origin at its CoG, z up (against gravity), x the horizontal direction from the CoG to the goal
(y = z × x):
    [0:36]   node positions (12, 3) m relative to the CoG, clipped to +-S
    [36:72]  node velocities (12, 3) m/s, clipped to +-max_speed
    [72:84]  the pair pressures (12,) MPa applied during the last step
    [84:105] contact face one-hot (21,): index 0 no face rests on the terrain, F face F
             (`contact.resting_face` with the task's contact tolerance)
    [105]    horizontal distance to the goal, m
Action: the 12 target pair pressures (MPa) in [0, max_pressure]. The applied pressure moves
toward the target by at most ramp_rate * interval per step and is held over the step (`ramp`;
a step of every pair from 0 to 6 MPa at once throws the robot into the air), as the
locomotion controller ramps (`locomotion.ramp_rate`); ramp_rate 0: the target at once.
Reward per step: progress_scale times the decrease of the horizontal CoG distance to the goal
(m); plus arrive_bonus on arrival (distance < arrive_tolerance: terminated), or minus
fail_penalty where the robot tumbled (its CoG faster than tumble_speed, a proxy: the trained
rolls of examples/train_cma.py stay below it), blew up (non-finite, a node faster than
max_speed) or left the terrain (all terminated). Truncated after max_steps steps.
A robot that fails is terminated at the step it failed (the kernel keeps the state of its
failure); a state that is not finite observes zeros.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np

from .. import paper
from ..physics import contact, kernel
from ..physics import dynamics as d
from ..physics import topology as topo
from ..physics.params import Params
from ..physics.schedule import MAX_PRESSURE, Schedule
from ..physics.state import State
from ..physics.terrain import Terrain, from_spec

OBS_SIZE = 2 * topo.N_NODES * 3 + topo.N_PAIRS + topo.N_FACES + 1 + 1
NODES, VELOCITIES, PRESSURE, FACE, DISTANCE = slice(0, 36), slice(36, 72), slice(72, 84), slice(84, 105), 105


@dataclass(frozen=True)
class RollTask:
    """Settings of the rolling task (module docstring). dt s (the kernel's step); interval s
    (one environment step: the pressure is held, as `locomotion.interval`); max_pressure MPa;
    ramp_rate MPa/s (0: no ramp);
    goal_distance m from the start CoG; goal_heading deg from +x (None: uniform at random per
    episode, from the environment's seed); arrive_tolerance m (locomotion's); tumble_speed m/s;
    contact_tolerance m; settle s at zero pressure before the first step (once, cached);
    max_steps; progress_scale per m; arrive_bonus, fail_penalty; start_face (1..20 or nodes);
    terrain a spec as the command line's --terrain (`terrain.from_spec`; not `none`)."""

    dt: float = 1e-4
    interval: float = 0.02
    max_pressure: float = 6.0
    ramp_rate: float = 2.0
    goal_distance: float = 2.0
    goal_heading: float | None = None
    arrive_tolerance: float = 0.3
    tumble_speed: float = 2.0
    contact_tolerance: float = 0.01
    settle: float = 1.0
    max_steps: int = 1500
    progress_scale: float = 10.0
    arrive_bonus: float = 10.0
    fail_penalty: float = 10.0
    start_face: int | tuple = paper.START_FACE
    terrain: str = "flat"

    def __post_init__(self):
        for f in fields(self):
            v = getattr(self, f.name)
            if f.name in ("start_face", "terrain", "goal_heading") or isinstance(v, bool):
                continue
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v >= 0):
                raise ValueError(f"RollTask {f.name} = {v!r} must be a finite number >= 0")
        for name in ("dt", "interval", "max_pressure", "goal_distance", "arrive_tolerance", "max_steps"):
            if not getattr(self, name) > 0:
                raise ValueError(f"RollTask {name} = {getattr(self, name)!r} must be positive")
        if not 0 < self.dt <= 1e-3:
            raise ValueError(f"RollTask dt = {self.dt!r} s must be in (0, 1e-3]")
        if abs(self.interval / self.dt - round(self.interval / self.dt)) > 1e-6:
            raise ValueError(f"RollTask interval = {self.interval!r} s is not a whole number of dt = {self.dt!r} s")
        if self.max_pressure > MAX_PRESSURE:
            raise ValueError(f"RollTask max_pressure = {self.max_pressure!r} MPa is above {MAX_PRESSURE} MPa")
        if self.goal_heading is not None and not math.isfinite(self.goal_heading):
            raise ValueError(f"RollTask goal_heading = {self.goal_heading!r} must be finite or None")
        topo.face_number(self.start_face)  # ValueError naming a bad face
        if self.ground().kind == "none":
            raise ValueError("RollTask terrain 'none' has no ground to roll on: use flat, slope:..., random:...")

    def ground(self) -> Terrain:
        """The terrain of the spec (ValueError naming a bad spec)."""
        return from_spec(self.terrain)

    @property
    def substeps(self) -> int:
        """Kernel steps per environment step."""
        return int(round(self.interval / self.dt))


def default_params() -> Params:
    """The robot of the rolling runs: the defaults with strut damping 1.0 1/s
    (`locomotion.strut_damping`, docs/design.md §3)."""
    return Params(strut_damping=1.0)


def start_state(params: Params, task: RollTask, terrain: Terrain) -> State:
    """One robot at rest on the start face, settled for task.settle s at zero pressure."""
    s = d.stand_on(params, task.start_face, terrain)
    if task.settle > 0:
        n = max(1, round(task.settle / task.interval))
        s, _ = d.simulate(
            params, s, Schedule.constant(np.zeros((1, 12)), n * task.interval), terrain, task.dt, task.substeps
        )
    return s.copy()


def goals(start: State, headings_deg: np.ndarray, distance: float) -> np.ndarray:
    """Goal points (n, 2) m: `distance` from the start CoG along headings (n,) deg from +x."""
    h = np.radians(np.asarray(headings_deg, float))
    return d.cog(start.x)[0, :2] + distance * np.stack([np.cos(h), np.sin(h)], axis=-1)


def ramp(applied: np.ndarray, target: np.ndarray, task: RollTask) -> np.ndarray:
    """The pressures (N, 12) MPa of the next step: `applied` moved toward `target` (clipped to
    [0, max_pressure]) by at most ramp_rate * interval (module docstring)."""
    target = np.clip(np.asarray(target, dtype=float), 0.0, task.max_pressure)
    if task.ramp_rate == 0:
        return target
    dp = task.ramp_rate * task.interval
    return applied + np.clip(target - applied, -dp, dp)


def advance(state: State, prm: np.ndarray, pressure: np.ndarray, terrain: Terrain, task: RollTask) -> np.ndarray:
    """Advance every robot of `state` in place by one environment step (task.substeps kernel
    steps) under pair pressures (N, 12) MPa, in ONE kernel call; prm the packed (N, NP)
    parameters. Returns the kernel's status per robot (N,): 0 ok, kernel.NON_FINITE, TOO_FAST or
    OFF_TERRAIN."""
    n = state.batch
    kind, meta, hz = terrain.packed()
    status, fail = np.zeros(n, np.int64), np.zeros(n, np.int64)
    out_x, out_q = np.empty((n, 1, 6, 3)), np.empty((n, 1, 6, 4))
    pres = np.ascontiguousarray(topo.cable_levels(pressure))  # the kernel's: one per cable
    kernel.advance(
        state.x, state.v, state.q, state.w, state.anchor, state.stuck, prm, pres, kind, meta, hz, 1,
        task.substeps, task.dt, out_x, out_q, status, fail,
    )  # fmt: skip
    return status


def _goal_frame(v: np.ndarray, ex: np.ndarray) -> np.ndarray:
    """World vectors v (N, 12, 3) in the goal frame: x = ex (N, 2) horizontal unit, y = z x x,
    z up (a turn about z)."""
    cx, cy = ex[:, 0, None], ex[:, 1, None]
    out = np.empty_like(v)
    out[..., 0] = cx * v[..., 0] + cy * v[..., 1]
    out[..., 1] = cx * v[..., 1] - cy * v[..., 0]
    out[..., 2] = v[..., 2]
    return out


def observe(
    params: Params, state: State, pressure: np.ndarray, goal: np.ndarray, terrain: Terrain, task: RollTask
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Observations (N, OBS_SIZE) float32 (module docstring) of robots `state` under the pair
    pressures (N, 12) MPa of the last step, the horizontal distance to the
    goal (N,) m, the contact face (N,) (0: none) and the CoG speed (N,) m/s. Robots whose state
    is not finite observe zeros, distance inf and speed inf."""
    S = float(params.strut_length)
    ok = np.isfinite(state.x).all((1, 2)) & np.isfinite(state.v).all((1, 2))
    ok &= np.isfinite(state.q).all((1, 2)) & np.isfinite(state.w).all((1, 2))
    p = d.nodes(state.x, state.q, S)
    u = d.node_velocities(state, S)
    c = d.cog(state.x)
    to_goal = goal - c[:, :2]
    dist = np.where(ok, np.hypot(to_goal[:, 0], to_goal[:, 1]), np.inf)
    ex = np.where(ok[:, None], to_goal, 1.0) / np.where(ok & (dist > 0), dist, 1.0)[:, None]
    rel, vel = _goal_frame(p - c[:, None], ex), _goal_frame(u, ex)
    face = np.zeros(state.batch, np.int64)
    if ok.any():
        h, n = terrain.height_and_normal(p[ok, :, 0], p[ok, :, 1])
        gap = np.where(np.isnan(h), np.inf, (p[ok, :, 2] - h) * n[..., 2] - float(params.strut_radius))
        face[ok] = contact.resting_face(gap, task.contact_tolerance)
    obs = np.zeros((state.batch, OBS_SIZE), np.float32)
    obs[:, NODES] = np.clip(rel.reshape(-1, 36), -S, S)
    obs[:, VELOCITIES] = np.clip(vel.reshape(-1, 36), -params.max_speed, params.max_speed)
    obs[:, PRESSURE] = pressure
    obs[np.arange(state.batch), FACE.start + face] = 1.0
    obs[:, DISTANCE] = np.minimum(dist, np.finfo(np.float32).max)
    obs[~ok] = 0.0
    speed = np.where(ok, np.linalg.norm(state.v.mean(axis=1), axis=-1), np.inf)
    return obs, dist, face, speed


def judge(
    before: np.ndarray, dist: np.ndarray, speed: np.ndarray, status: np.ndarray, task: RollTask
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Reward (N,), terminated (N,), arrived (N,), failed (N,) of one step: distance to the goal
    before and after (m), the CoG speed (m/s) and the kernel status (module docstring)."""
    failed = (status != 0) | ~np.isfinite(dist) | (speed > task.tumble_speed)
    arrived = ~failed & (dist < task.arrive_tolerance)
    progress = np.where(failed, 0.0, before - np.where(np.isfinite(dist), dist, before))
    reward = task.progress_scale * progress + task.arrive_bonus * arrived - task.fail_penalty * failed
    return reward, failed | arrived, arrived, failed
