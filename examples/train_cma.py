"""Train a rolling policy for `tensegrity/Roll-v0` with CMA-ES (the `cma` package; no GPU, no
deep-learning framework), then report its arrival rate on the locomotion benchmark's flat
ground: goals 2 m away in 8 evenly spaced directions (benchmarks/bench_locomotion.py's flat).

The policy is small and shares its weights across the 12 pairs (the robot's pairs are alike
under its symmetry group): the target pressure of pair #v is

    P_v = max_pressure * sigmoid(w . f_v),   f_v = (1, x_v, y_v, z_v, px_v, py_v, pz_v, P_v')

with (x_v, y_v, z_v) node v relative to the CoG and (px_v, py_v, pz_v) the pull of its two
cables (the mean of their other ends minus node v), both in the goal frame of the observation
over the strut length, and P_v' the pair's applied pressure / max_pressure: 8 weights. Tuning
uses headings drawn from --tune-seed; the report uses the 8 benchmark directions rotated by a
random offset from --eval-seed (disjoint from the tuning headings), and prints the arrival
rate, the median final distance and the wall time.

An episode is at most --max-steps steps of 0.02 s (default 1000: 20 s); the pressures ramp at
--ramp-rate MPa/s (default 10; the environment's default is 2). Every candidate of a generation
on every tuning heading is one robot of one vector environment (12 x 4 = 48 robots): one kernel
call per step for the whole generation.

Usage: python examples/train_cma.py [--generations 25] [--popsize 12] [--tune-headings 4]
                                    [--max-steps 1000] [--ramp-rate 10] [--threads 1]
                                    [--tune-seed 1] [--eval-seed 2]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

N_FEATURES = 10


def _other_ends() -> np.ndarray:
    """(12, 2): the other nodes of the two cables of pair #v (both cables start or end at v)."""
    from tensegrity.physics import topology as topo

    other = np.empty((12, 2), np.int64)
    for v in range(12):
        for k, c in enumerate(topo.PAIR_CABLES[v]):
            a, b = topo.CABLES[c]
            other[v, k] = b if a == v else a
    return other


def features(obs: np.ndarray, max_pressure: float, strut_length: float) -> np.ndarray:
    """Per-pair features (N, 12, N_FEATURES) of observations (N, OBS_SIZE) (module docstring)."""
    from tensegrity.envs import core

    p = obs[:, core.NODES].reshape(-1, 12, 3) / strut_length
    p = np.concatenate([p[..., :2], p[..., 2:] - p[..., 2:].min(axis=1, keepdims=True)], axis=-1)  # height
    o = p[:, _other_ends()].mean(axis=2)
    x, y, h, xo, yo, ho = p[..., 0], np.abs(p[..., 1]), p[..., 2], o[..., 0], np.abs(o[..., 1]), o[..., 2]
    applied = obs[:, core.PRESSURE] / max_pressure
    return np.stack([np.ones_like(x), x, y, h, xo, yo, ho, applied, x * h, xo * ho], axis=-1)


def act(w: np.ndarray, obs: np.ndarray, max_pressure: float, strut_length: float) -> np.ndarray:
    """Target pressures (N, 12) MPa of weights w (N, N_FEATURES) (one policy per robot)."""
    z = np.einsum("npf,nf->np", features(obs, max_pressure, strut_length), w)
    return (max_pressure / (1.0 + np.exp(-np.clip(z, -30, 30)))).astype(np.float32)


def episodes(
    weights: np.ndarray, headings: np.ndarray, max_steps: int, ramp_rate: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Every policy (K, N_FEATURES) on every heading (H,) deg, all K*H robots in one vector env:
    the first episode's return (K, H), whether it arrived (K, H) and its final distance (K, H) m."""
    from tensegrity.envs.vector import RollVectorEnv

    K, H = len(weights), len(headings)
    env = RollVectorEnv(K * H, max_steps=max_steps, ramp_rate=ramp_rate)
    obs, info = env.reset(seed=0, options={"goal_headings": np.tile(headings, K)})
    w = np.repeat(weights, H, axis=0)
    ret, done = np.zeros(K * H), np.zeros(K * H, bool)
    arrived, dist = np.zeros(K * H, bool), np.full(K * H, env.task.goal_distance)
    S, top = float(env.params.strut_length), env.task.max_pressure
    while not done.all():
        obs, r, term, trunc, info = env.step(act(w, obs, top, S))
        live = ~done
        ret[live] += r[live]
        arrived[live] = info["arrived"][live]
        dist[live] = info["distance"][live]
        done |= term | trunc
    return ret.reshape(K, H), arrived.reshape(K, H), dist.reshape(K, H)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--generations", type=int, default=25)
    ap.add_argument("--popsize", type=int, default=12)
    ap.add_argument("--tune-headings", type=int, default=4, help="random goal headings per evaluation while tuning")
    ap.add_argument("--max-steps", type=int, default=1000, help="environment steps per episode (0.02 s each)")
    ap.add_argument("--threads", type=int, default=1, help="numba threads")
    ap.add_argument("--ramp-rate", type=float, default=10.0, help="the task's pressure ramp, MPa/s (default 10)")
    ap.add_argument("--tune-seed", type=int, default=1)
    ap.add_argument("--eval-seed", type=int, default=2)
    a = ap.parse_args()
    for key in ("generations", "popsize", "tune_headings", "max_steps", "threads"):
        if getattr(a, key) < 1:
            ap.error(f"argument --{key.replace('_', '-')}: must be at least 1")
    import cma
    import numba

    numba.set_num_threads(a.threads)
    t0 = time.perf_counter()
    tune = np.random.default_rng(a.tune_seed)
    es = cma.CMAEvolutionStrategy(np.zeros(N_FEATURES), 1.0, {"popsize": a.popsize, "seed": a.tune_seed, "verbose": -9})
    for g in range(a.generations):
        xs = np.array(es.ask())
        headings = tune.uniform(0, 360, a.tune_headings)
        ret, arr, dist = episodes(xs, headings, a.max_steps, a.ramp_rate)
        es.tell(list(xs), list(-ret.mean(axis=1)))
        best = int(np.argmax(ret.mean(axis=1)))
        print(
            f"generation {g + 1:>3}: mean return {ret.mean():7.2f}, best {ret.mean(axis=1)[best]:7.2f} "
            f"(arrived {arr[best].sum()}/{len(headings)}), {time.perf_counter() - t0:6.0f} s",
            flush=True,
        )
    w = np.asarray(es.result.xfavorite)
    offset = np.random.default_rng(a.eval_seed).uniform(0, 45)
    headings = offset + 45.0 * np.arange(8)
    _, arr, dist = episodes(w[None], headings, a.max_steps, a.ramp_rate)
    print(f"policy weights: {np.round(w, 3).tolist()}")
    print(
        f"flat ground, goals 2 m away in 8 directions ({offset:.1f} + 45 k deg): arrived {arr.sum()}/8, "
        f"median final distance {np.median(dist):.3f} m; {time.perf_counter() - t0:.0f} s on {a.threads} thread(s)"
    )


if __name__ == "__main__":
    main()
