"""Robot-steps per second of the compiled simulator. Prints figures; asserts nothing.

Usage: python benchmarks/bench_step.py [--seconds 0.5] [--cpu] [--actuator both]

Both actuators by default (docs/design.md §10): the pneumatic muscles (pair #10 at 0.4-2.4 MPa)
and the prototype's twisted strings (kernel/motors.py; pair #10 at 2-11 V), in the same run, the
two taking turns run by run.
"""

from __future__ import annotations

import argparse
import os
import resource
import sys
import time

import numpy as np

from tensegrity.physics import dynamics as d
from tensegrity.physics.params import Params
from tensegrity.physics.schedule import Schedule
from tensegrity.physics.terrain import Terrain
from tensegrity.physics.twisted import TwistedString, Voltages


def _cpu_seconds() -> float:
    """CPU seconds of this process so far, all threads."""
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def run(
    batch: int,
    grounded: bool,
    sim_seconds: float,
    dt: float = 1e-4,
    repeat: int = 3,
    cpu: bool = False,
    kinds: tuple[TwistedString | None, ...] = (None,),
) -> list[float]:
    """Robot-steps per second of each actuator of `kinds` (None: the pneumatic muscles; a
    TwistedString: the twisted-string kernel), the median of `repeat` timed runs; with `cpu`,
    per CPU second of the process, the best of `repeat` runs. The kinds take turns, run by run,
    so that a change of the machine's load falls on all of them alike."""
    params = Params() if grounded else Params(gravity=0.0)
    terrain = Terrain.flat() if grounded else Terrain.none()
    state = d.stand_on(params, (9, 10, 12), terrain, batch=batch)
    cases = []
    for motors in kinds:
        level = np.zeros((batch, 12))
        level[:, 9] = np.linspace(0.4, 2.4, batch)  # pair #10, differing per robot
        kind = Schedule
        if motors is not None:
            level[:, 9], kind = np.linspace(2.0, 11.0, batch), Voltages  # volts
        d.simulate(params, state, kind.constant(level, 0.001), terrain, dt, motors=motors)  # warm
        cases.append((kind.constant(level, sim_seconds), motors))
    walls = [[] for _ in kinds]
    for _ in range(repeat):
        for k, (sched, motors) in enumerate(cases):
            t0 = _cpu_seconds() if cpu else time.perf_counter()
            d.simulate(params, state, sched, terrain, dt, record_every=100, motors=motors)
            walls[k].append((_cpu_seconds() if cpu else time.perf_counter()) - t0)
    return [batch * round(sim_seconds / dt) / (np.min(w) if cpu else np.median(w)) for w in walls]


_MOTORS = {"twisted_string": TwistedString()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--seconds", type=float, default=0.5, help="simulated seconds per case")
    ap.add_argument(
        "--cpu",
        action="store_true",
        help="robot-steps per CPU second, best of 7 (on a shared machine; with "
        "NUMBA_NUM_THREADS=1, the code's own speed)",
    )
    ap.add_argument("--actuator", choices=("both", "pneumatic", "twisted_string"), default="both")
    a = ap.parse_args()
    kinds = ("pneumatic", "twisted_string") if a.actuator == "both" else (a.actuator,)
    t0 = time.perf_counter()
    d.simulate(Params(), d.stand_on(Params(), 8), Schedule.constant(np.zeros(12), 0.001))
    print(f"first call (compile or load cached code): {time.perf_counter() - t0:.2f} s")
    print(f"cores: {os.cpu_count()}, numba threads: {__import__('numba').get_num_threads()}, dt = 1e-4 s")
    print(f"{'batch':>6} {'mode':>9} " + " ".join(f"{k + ' steps/' + ('cpu-s' if a.cpu else 's'):>26}" for k in kinds))
    from tqdm import tqdm

    cases = [(grounded, batch) for grounded in (False, True) for batch in (1, 24, 288)]
    # a bar on stderr while the cases run, only on a terminal; the table goes to stdout
    with tqdm(cases, desc="cases", unit="case", disable=None, file=sys.stderr, leave=False) as bar:
        for grounded, batch in bar:
            secs = a.seconds if batch > 1 else 4 * a.seconds
            speeds = run(
                batch, grounded, secs, repeat=7 if a.cpu else 3, cpu=a.cpu, kinds=tuple(_MOTORS.get(k) for k in kinds)
            )
            ratio = f"   twisted/pneumatic {speeds[1] / speeds[0]:.2f}" if len(kinds) == 2 else ""
            bar.write(
                f"{batch:>6} {'grounded' if grounded else 'free':>9} "
                + " ".join(f"{s:>26,.0f}" for s in speeds)
                + ratio,
                file=sys.stdout,
            )


if __name__ == "__main__":
    main()
