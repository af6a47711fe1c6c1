"""Side by side with MuJoCo (issue 11, item 2): the same robot and workload in one process, our
simulator (`dynamics.simulate`) against MuJoCo's batched, multithreaded `rollout`. Prints both
rates in robot-steps/s, the ratio, and the largest node-trajectory difference in the free mode.

The MuJoCo model is the package's export (`tensegrity.bridges.mjcf`, `tensegrity export mjcf`):
6 rigid struts on free joints with the same masses and thin-tube inertias (docs/design.md §3),
sites at the 12 nodes, 24 spatial tendons, and one `general` actuator per tendon for the cable
law (eq. 1-2, a = 1) whose control is the pair pressure (MPa). Semi-implicit Euler, dt 1e-4 s.
Free mode: no gravity, no contact. Grounded mode: gravity and a plane with MuJoCo's OWN
soft-constraint contact (a sphere of radius r at each node, friction mu, default solref and
solimp), not our penalty and stick-spring model, so grounded trajectories are not compared.
Results and their explanation: docs/benchmarks.md.

MuJoCo (pip mujoco-core) is a test dependency pinned in environment.txt, never a runtime one:
    pip install -r benchmarks/requirements-mujoco.txt
Usage: python benchmarks/bench_mujoco.py [--seconds 2] [--batch 24] [--threads 2] [--repeat 3]
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

from tensegrity.bridges.mjcf import INTEGRATORS, controls, mjcf

try:
    import mujoco
    from mujoco import rollout
except ImportError:
    mujoco = None

DT = 1e-4  # s, both simulators
EVERY = 100  # steps between recorded samples (both simulators): 0.01 s
CHUNK = 10  # `rollout` writes the state of every step: EVERY * CHUNK steps per call
PAIR = 10  # the pressurised pair (pressures: robot 0 at 2.4 MPa)


def pressures(batch: int) -> np.ndarray:
    """Pair pressures (B, 12) MPa: pair #10 from 2.4 MPa (robot 0) down to 0.4 MPa."""
    p = np.zeros((batch, 12))
    p[:, PAIR - 1] = np.linspace(2.4, 0.4, batch)
    return p


def initial_states(model, state) -> np.ndarray:
    """MuJoCo full-physics states (B, nstate) of our batch `state` (dynamics.State): free joint
    qpos = (centre m, quaternion w x y z), qvel = (velocity m/s world, angular rad/s body)."""
    data = mujoco.MjData(model)
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    out = np.empty((state.batch, mujoco.mj_stateSize(model, spec)))
    for b in range(state.batch):
        mujoco.mj_resetData(model, data)
        data.qpos[:] = np.concatenate([state.x[b], state.q[b]], axis=1).ravel()
        data.qvel[:] = np.concatenate([state.v[b], state.w[b]], axis=1).ravel()
        mujoco.mj_getState(model, data, out[b], spec)
    return out


def run_mujoco(
    model, x0: np.ndarray, ctrl: np.ndarray, nstep: int, nthread: int
) -> tuple[float, np.ndarray, np.ndarray]:
    """`rollout` of B robots from states x0 (B, nstate) with actuator controls ctrl (B, 24) MPa,
    nstep steps on nthread threads. Returns the wall time (s), the strut centres (B, T, 6, 3) m
    and quaternions (B, T, 6, 4) every EVERY steps."""
    datas = [mujoco.MjData(model) for _ in range(nthread)]
    B, n = x0.shape[0], min(EVERY * CHUNK, nstep)
    out = np.empty((B, n, x0.shape[1]))
    ctrl = np.ascontiguousarray(np.broadcast_to(ctrl[:, None], (B, n, ctrl.shape[1])))
    recs, state, done = [], x0, 0
    with rollout.Rollout(nthread=nthread if nthread > 1 else 0) as pool:
        t0 = time.perf_counter()
        while done < nstep:  # nstep is a multiple of EVERY; `out[:, t]` is after step t + 1
            k = min(n, nstep - done)
            pool.rollout(model, datas, state, ctrl[:, :k], state=out[:, :k], nstep=k)
            recs.append(out[:, EVERY - 1 : k : EVERY, 1 : 1 + model.nq].copy())
            state = out[:, k - 1].copy()
            done += k
        wall = time.perf_counter() - t0
    rec = np.concatenate(recs, 1).reshape(B, -1, 6, 7)
    return wall, rec[..., :3], rec[..., 3:]


def run_ours(params, state, pressure: np.ndarray, terrain, nstep: int) -> tuple[float, np.ndarray]:
    """`dynamics.simulate` of the batch for nstep steps. Returns the wall time (s) and the node
    positions (B, T, 12, 3) m every EVERY steps."""
    from tensegrity.physics import dynamics as d
    from tensegrity.physics.schedule import Schedule

    t0 = time.perf_counter()
    _, tr = d.simulate(params, state, Schedule.constant(pressure, nstep * DT), terrain, DT, EVERY)
    return time.perf_counter() - t0, tr.nodes(params.strut_length)


def _args() -> argparse.Namespace:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument(
        "--seconds", type=float, default=2.0, help="simulated seconds per robot, a multiple of 0.01 (default 2)"
    )
    ap.add_argument("--batch", type=int, default=24, help="robots per batch (default 24)")
    ap.add_argument("--threads", type=int, default=2, help="threads of each simulator (default 2)")
    ap.add_argument("--repeat", type=int, default=3, help="timed runs per case, median (default 3)")
    ap.add_argument(
        "--integrator",
        choices=INTEGRATORS,
        default="Euler",
        help="MuJoCo's integrator (default Euler, semi-implicit as ours; the others "
        "show how far a different scheme moves the trajectories)",
    )
    a = ap.parse_args()
    n = a.seconds / (EVERY * DT)
    if not (np.isfinite(n) and n >= 0.5 and abs(n - round(n)) < 1e-6):
        ap.error(f"argument --seconds: {a.seconds} is not a positive multiple of {EVERY * DT:g} s")
    for key in ("batch", "threads", "repeat"):
        if getattr(a, key) < 1:
            ap.error(f"argument --{key}: {getattr(a, key)} must be at least 1")
    if mujoco is None:
        sys.exit(
            "bench_mujoco.py: MuJoCo is not installed. It is an optional benchmark requirement: "
            "pip install -r benchmarks/requirements-mujoco.txt"
        )
    import numba

    if a.threads > numba.config.NUMBA_NUM_THREADS:
        ap.error(
            f"argument --threads: {a.threads} is more than numba's "
            f"{numba.config.NUMBA_NUM_THREADS} threads (NUMBA_NUM_THREADS)"
        )
    numba.set_num_threads(a.threads)
    return a


def main() -> None:
    a = _args()
    from tqdm import tqdm

    from tensegrity.physics import dynamics as d
    from tensegrity.physics.params import Params
    from tensegrity.physics.terrain import Terrain

    nstep = round(a.seconds / DT)
    pressure = pressures(a.batch)
    ctrl = controls(pressure)  # per actuator (cable): its pair's pressure
    print(
        f"MuJoCo {mujoco.__version__} `rollout` against tensegrity `dynamics.simulate`: "
        f"{a.batch} robots x {a.seconds:g} s, dt {DT:g} s, {a.threads} threads each, "
        f"{os.cpu_count()} cores; pair #{PAIR} at {pressure[-1, PAIR - 1]:g}-"
        f"{pressure[0, PAIR - 1]:g} MPa; MuJoCo integrator {a.integrator}; median of {a.repeat} runs"
    )
    print(f"{'mode':>9} {'tensegrity':>14} {'MuJoCo':>12} {'ratio':>7}   (robot-steps/s)")
    result = {}
    bar = tqdm(
        total=2 * a.repeat, desc="timed runs", unit="run", disable=None, file=sys.stderr, leave=False
    )  # on stderr, only on a terminal; the figures go to stdout
    for grounded in (False, True):
        params = Params() if grounded else Params(gravity=0.0)
        terrain = Terrain.flat() if grounded else Terrain.none()
        state = d.stand_on(params, (9, 10, 12), terrain, batch=a.batch)
        model = mujoco.MjModel.from_xml_string(
            mjcf(params, "grounded" if grounded else "free", DT, integrator=a.integrator)
        )
        x0 = initial_states(model, state)
        run_ours(params, state, pressure, terrain, EVERY)  # compile or load the cached code
        run_mujoco(model, x0, ctrl, EVERY, a.threads)  # warm up
        walls_ours, walls_mj = [], []
        for _ in range(a.repeat):
            wall, nodes_ours = run_ours(params, state, pressure, terrain, nstep)
            walls_ours.append(wall)
            wall, x, q = run_mujoco(model, x0, ctrl, nstep, a.threads)
            walls_mj.append(wall)
            bar.update()
        rate = [a.batch * nstep / np.median(w) for w in (walls_ours, walls_mj)]
        bar.write(
            f"{'grounded' if grounded else 'free':>9} {rate[0]:>14,.0f} {rate[1]:>12,.0f} {rate[0] / rate[1]:>7.1f}",
            file=sys.stdout,
        )
        result[grounded] = nodes_ours, d.nodes(x, q, params.strut_length), params, state, terrain
    bar.close()
    ours, theirs, params, state, terrain = result[False]
    # the round-off floor: MuJoCo against itself with the cables listed in reverse order (the
    # same model; only the order in which floating-point forces are summed changes)
    rev = np.arange(24)[::-1]
    model = mujoco.MjModel.from_xml_string(mjcf(params, "free", DT, integrator=a.integrator, order=rev))
    _, x, q = run_mujoco(model, initial_states(model, state), ctrl[:, rev], nstep, a.threads)
    floor = np.abs(theirs - d.nodes(x, q, params.strut_length)).max() * 1e3
    travel = np.abs(ours - d.nodes(state.x, state.q, params.strut_length)[:, None]).max() * 1e3
    print(
        f"free mode, largest node-trajectory difference (all robots, every {EVERY * DT:g} s): "
        f"{np.abs(ours - theirs).max() * 1e3:.2g} mm\n"
        f"  round-off floor, MuJoCo against itself with the 24 cables in reverse order: "
        f"{floor:.2g} mm; the nodes move by up to {travel:.3g} mm"
    )
    ours, theirs = result[True][:2]
    cog = [n.mean(axis=-2)[:, -1] for n in (ours, theirs)]  # the CoG (B, 3) m (equal masses)
    start = result[True][3].x.mean(axis=-2)  # (B, 3) m
    stood = np.all([np.linalg.norm(c - start, axis=-1) < 0.05 for c in cog], axis=0)  # neither rolled
    gap = np.linalg.norm(cog[0] - cog[1], axis=-1) * 1e3
    print(
        f"grounded mode, not compared (MuJoCo's contact model is not ours): the CoGs at the end "
        f"differ by up to {gap.max():.3g} mm; robots that stand in both ({stood.sum()} of {len(stood)}, "
        f"the lowest pressures): {gap[stood].max() if stood.any() else float('nan'):.3g} mm, "
        f"of which height {np.abs(cog[0] - cog[1])[stood, 2].max() * 1e3 if stood.any() else float('nan'):.3g} mm"
    )


if __name__ == "__main__":
    main()
