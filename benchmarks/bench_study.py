"""Design-study throughput (issue 12): designs per hour for a full free-mode workspace per design
(12 pairs x 12 levels x 2 contact cases, `--hold` s per level), computed as the chunk job does
(`stages.study.study_chunk`: one batched simulation of designs x contacts x pairs robots, the
level averages, the paper's statements per design, the chunk file). Prints figures; asserts
nothing. Target: 1,000 designs in under 10 minutes on 2 cores.

For each number of designs N (`--designs`, all in one chunk) it prints the wall time, the
robot-steps per second of the kernel (robots x time steps / kernel seconds: compare machines with
this), the designs per hour, the time 1,000 designs would take, and where the time goes: the
kernel (dynamics.simulate), the support-frame averaging, the paper's statements
(validation.paper.check_paper per design) and writing the file. Wall times are inflated on a
shared machine; the robot-steps per second say how busy it was.

Usage: python benchmarks/bench_study.py [--designs 8 32 128] [--hold 1.0] [--sample-every 10]
       [--threads 2]
(the example study stiffness_pretension uses --hold 0.5 --sample-every 50)
"""

from __future__ import annotations

import argparse
import contextlib
import tempfile
import time
from pathlib import Path

from tensegrity.io import config, datasets, study_config
from tensegrity.physics import dynamics
from tensegrity.stages import study as study_stage
from tensegrity.stages.config import stage_config
from tensegrity.validation import paper


@contextlib.contextmanager
def timed(module, name: str, clock: dict):
    """Add the wall time of every call of module.name to clock[name]."""
    orig = getattr(module, name)

    def wrapper(*a, **k):
        t0 = time.perf_counter()
        try:
            return orig(*a, **k)
        finally:
            clock[name] = clock.get(name, 0.0) + time.perf_counter() - t0

    setattr(module, name, wrapper)
    try:
        yield
    finally:
        setattr(module, name, orig)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--designs", type=int, nargs="+", default=[8, 32, 128])
    ap.add_argument("--hold", type=float, default=1.0, help="s per level (the workflow's default 1 s)")
    ap.add_argument(
        "--sample-every", type=int, default=10, help="steps between averaged samples (10: the pipeline's 1 ms)"
    )
    ap.add_argument("--threads", type=int, default=2)
    args = ap.parse_args()
    import numba

    numba.set_num_threads(min(args.threads, numba.config.NUMBA_NUM_THREADS))
    cfg = stage_config(config.load(), "study_chunk")
    dt = cfg["sim"]["dt"]
    print(
        f"full workspace per design: 12 pairs x 12 levels x 2 contacts, hold {args.hold} s, dt {dt} s, "
        f"samples every {args.sample_every} steps, {numba.get_num_threads()} threads"
    )
    print(
        f"{'designs':>8} {'robots':>7} {'wall s':>8} {'Mrobot-steps/s':>15} {'designs/h':>10} "
        f"{'1000 designs':>13} | {'kernel':>7} {'frames':>7} {'paper':>7} {'write':>7}"
    )
    for n in args.designs:
        st = study_config.validate(
            {
                "parameters": {
                    "cable_stiffness": {"low": 700.0, "high": 1500.0, "units": "N/m"},
                    "cable_pretension": {"low": 12.0, "high": 30.0, "units": "N"},
                },
                "design": {"method": "lhs", "n": n, "seed": 1},
                "chunk_size": n,
                "workspace": {"hold": args.hold, "discard": min(0.2, args.hold / 2), "sample_every": args.sample_every},
            },
            dt=dt,
        )
        st = {"name": "bench", **st}
        clock: dict = {}
        with (
            tempfile.TemporaryDirectory() as tmp,
            timed(dynamics, "simulate", clock),
            timed(paper, "check_paper", clock),
            timed(datasets, "write", clock),
        ):
            t0 = time.perf_counter()
            study_stage.study_chunk(cfg, st, 0, Path(tmp) / "chunk.nc")
            wall = time.perf_counter() - t0
        robots = n * 24
        steps = robots * round(12 * args.hold / dt)
        kernel = clock.get("simulate", 0.0)
        rest = {"paper": clock.get("check_paper", 0.0), "write": clock.get("write", 0.0)}
        frames = wall - kernel - sum(rest.values())
        per_h = n / wall * 3600
        print(
            f"{n:8d} {robots:7d} {wall:8.2f} {steps / kernel / 1e6:15.2f} {per_h:10.0f} "
            f"{1000 / per_h * 60:10.1f} min | "
            + " ".join(f"{100 * x / wall:6.1f}%" for x in (kernel, frames, rest["paper"], rest["write"]))
        )


if __name__ == "__main__":
    main()
