"""Environment steps per second of `tensegrity/Roll-v0` (issue 33, item 2): the vector
environment (`tensegrity.envs.vector.RollVectorEnv`, N robots, one kernel call per step) at
N = 1, 64 and 1024, beside the same robot stepped through MuJoCo's Python API: the exported
grounded model (`tensegrity.bridges.mjcf`), one `mujoco.mj_step` call per time step in a Python
loop, the controls set once per environment step, the 12 node positions read after it.

One environment step = one control interval (0.02 s = 200 steps of 1e-4 s) for every robot.
Both sides get the same random target pressures (seeded), ramped by the task's rule
(`envs.core.ramp`); the robot is the same (strut damping 0 on both sides: the export cannot
write it) except for the ground contact, which is MuJoCo's own in MuJoCo. MuJoCo's loop steps
robots one after another, so its rate per robot does not depend on N: it is measured once
with one robot and printed on every row. The tensegrity rate includes the observation, the
reward and the autoresets; MuJoCo's only the stepping and the read of the nodes.

Usage: python benchmarks/bench_env.py [--sizes 1 64 1024] [--steps 50] [--mujoco-steps 20]
                                      [--threads 2] [--repeat 3]
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

try:
    import mujoco
except ImportError:
    mujoco = None


def _args() -> argparse.Namespace:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[1, 64, 1024], help="robots N (default 1 64 1024)")
    ap.add_argument("--steps", type=int, default=50, help="timed environment steps per N (default 50)")
    ap.add_argument("--mujoco-steps", type=int, default=20, help="timed MuJoCo environment steps (default 20)")
    ap.add_argument("--threads", type=int, default=2, help="numba threads of the kernel (default 2)")
    ap.add_argument("--repeat", type=int, default=3, help="timed runs, median (default 3)")
    a = ap.parse_args()
    for key in ("steps", "mujoco_steps", "threads", "repeat"):
        if getattr(a, key) < 1:
            ap.error(f"argument --{key.replace('_', '-')}: {getattr(a, key)} must be at least 1")
    if min(a.sizes) < 1:
        ap.error(f"argument --sizes: {a.sizes} must all be at least 1")
    if mujoco is None:
        sys.exit("bench_env.py: MuJoCo is not installed: pip install -r benchmarks/requirements-mujoco.txt")
    import numba

    if a.threads > numba.config.NUMBA_NUM_THREADS:
        ap.error(f"argument --threads: {a.threads} is more than numba's {numba.config.NUMBA_NUM_THREADS} threads")
    numba.set_num_threads(a.threads)
    return a


def targets(steps: int, n: int, top: float, seed: int = 0) -> np.ndarray:
    """Random target pressures (steps, n, 12) MPa: each step one random pair of each robot at a
    random level in [0, top], the others 0 (a rolling-like load, not a launch of all twelve)."""
    rng = np.random.default_rng(seed)
    out = np.zeros((steps, n, 12), np.float32)
    pair = rng.integers(0, 12, (steps, n))
    out[np.arange(steps)[:, None], np.arange(n)[None], pair] = rng.uniform(0, top, (steps, n))
    return out


def time_env(n: int, steps: int, params, repeat: int) -> float:
    """Median wall time (s) of `steps` steps of the vector environment of n robots."""
    from tensegrity.envs.vector import RollVectorEnv

    env = RollVectorEnv(n, params=params)
    acts = targets(steps, n, env.task.max_pressure)
    env.reset(seed=0)
    env.step(acts[0])  # compile or load the cached code
    walls = []
    for _ in range(repeat):
        env.reset(seed=0)
        t0 = time.perf_counter()
        for a in acts:
            env.step(a)
        walls.append(time.perf_counter() - t0)
    return float(np.median(walls))


def time_mujoco(steps: int, params, repeat: int) -> float:
    """Median wall time (s) of `steps` environment steps of one robot in MuJoCo's Python loop."""
    from tensegrity.bridges.mjcf import controls, mjcf
    from tensegrity.envs import core

    task = core.RollTask()
    start = core.start_state(params, task, task.ground())
    model = mujoco.MjModel.from_xml_string(mjcf(params, "grounded", task.dt, state=start))
    data = mujoco.MjData(model)
    sites = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, f"node{k}") for k in range(1, 13)]
    acts = targets(steps, 1, task.max_pressure)
    walls = []
    for _ in range(repeat):
        mujoco.mj_resetData(model, data)
        applied = np.zeros((1, 12))
        t0 = time.perf_counter()
        for a in acts:
            applied = core.ramp(applied, a, task)
            data.ctrl[:] = controls(applied[0])
            for _ in range(task.substeps):
                mujoco.mj_step(model, data)
            data.site_xpos[sites].copy()
        walls.append(time.perf_counter() - t0)
    return float(np.median(walls))


def main() -> None:
    a = _args()
    from tensegrity.envs import core

    params = core.default_params().replace(strut_damping=0.0)
    task = core.RollTask()
    mj = a.mujoco_steps / time_mujoco(a.mujoco_steps, params, a.repeat)
    print(
        f"tensegrity/Roll-v0 (RollVectorEnv, {a.threads} numba threads) against MuJoCo {mujoco.__version__} "
        f"mj_step in a Python loop; one env step = {task.interval:g} s = {task.substeps} steps of {task.dt:g} s; "
        f"{os.cpu_count()} cores; median of {a.repeat} runs; {a.steps} env steps per N, {a.mujoco_steps} in MuJoCo"
    )
    print(f"{'N':>6} {'tensegrity':>14} {'MuJoCo':>10} {'ratio':>8}   (env steps/s, all robots)")
    for n in a.sizes:
        ours = n * a.steps / time_env(n, a.steps, params, a.repeat)
        print(f"{n:>6} {ours:>14,.0f} {mj:>10,.1f} {ours / mj:>8,.1f}", flush=True)
    print(f"MuJoCo's loop: {mj * task.substeps:,.0f} mj_step calls/s (one robot; the same per robot at any N)")


if __name__ == "__main__":
    main()
