"""Design-study throughput (issues 12, 34): designs per hour for a full free-mode workspace per
design (12 pairs x 12 levels x 2 contact cases, tipping pressures and edges), computed as
`tensegrity study` does (`stages.study.run_study`: the chunk jobs, the merge and the analysis),
by either workspace method of the study file:

- dynamics: one batched simulation of designs x contacts x pairs robots per chunk, `--hold` s per
  level, averaged per level; tipping pressures interpolated between the levels;
- statics: each level's equilibrium by batched Newton (physics.equilibrium), tipping pressures
  by root-finding on the margin (workspace.equilibria).

Prints figures; asserts nothing. Targets: 1,000 designs in 10 min (dynamics, issue 12); 10,000
designs in 10 min on 2 cores (statics, issue 34).

For each number of designs N (`--designs`) and method it prints the wall time, the designs per
hour, the time 10,000 designs would take, the CPU seconds of all threads (wall x 2 if it had
both cores to itself: compare with it on a shared machine), and where the time goes: the kernel
(dynamics.simulate) or the Newton solves (equilibrium.solve), the paper's statements
(validation.paper.check_paper per design), writing files, and the rest (support frames,
averaging, merge, analysis). Wall times are inflated on a shared machine. When both methods run,
it prints their agreement on the same N designs: CoG (every design, contact, pair, level) and
tipping pressure, the statics' root against the dynamics' interpolation, and the statics'
own interpolation between the levels against the dynamics' (the same rule: what is left is
physics and averaging). Target: 0.05 mm and 0.01 MPa on >= 50 designs.

Usage: python benchmarks/bench_study.py [--designs 8 32 128] [--method dynamics statics]
       [--hold 1.0] [--sample-every 10] [--chunk-size 1000] [--threads 2]
(the agreement of issue 34: --designs 50; the speed: --designs 10000 --method statics)
"""

from __future__ import annotations

import argparse
import contextlib
import tempfile
import time
from pathlib import Path

import numpy as np

from tensegrity.io import config, datasets, study_config
from tensegrity.physics import dynamics, equilibrium, frames
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


def run(cfg: dict, n: int, method: str, args, out: Path) -> tuple[float, float, dict]:
    """Run a study of n designs by `method` into `out`; wall and CPU time (s, all threads) and
    the clock of its parts."""
    st = study_config.validate(
        {
            "parameters": {
                "cable_stiffness": {"low": 700.0, "high": 1500.0, "units": "N/m"},
                "cable_pretension": {"low": 12.0, "high": 30.0, "units": "N"},
            },
            "design": {"method": "lhs", "n": n, "seed": 1},
            "chunk_size": min(n, args.chunk_size),
            "workspace": {
                "method": method,
                "hold": args.hold,
                "discard": min(0.2, args.hold / 2),
                "sample_every": args.sample_every,
            },
        },
        dt=cfg["sim"]["dt"],
    )
    clock: dict = {}
    with (
        timed(dynamics, "simulate", clock),
        timed(equilibrium, "solve", clock),
        timed(paper, "check_paper", clock),
        timed(datasets, "write", clock),
    ):
        t0, c0 = time.perf_counter(), time.process_time()
        study_stage.run_study(cfg, {"name": f"bench_{method}", **st}, out)
        return time.perf_counter() - t0, time.process_time() - c0, clock


def agreement(dyn: Path, sta: Path) -> None:
    """The table of statics against dynamics on the same designs (module docstring)."""
    a, b = datasets.read(dyn / "designs.nc"), datasets.read(sta / "designs.nc")
    d_cog = 1e3 * np.abs(a["cog"].values - b["cog"].values).max(axis=-1).ravel()
    levels = a["pressure"].values
    tip_d, tip_s = a["tip_pressure"].values, b["tip_pressure"].values
    interp = np.array([frames.first_crossing(levels, m)[0] for m in b["margin"].values.reshape(-1, levels.size)])
    both = np.isfinite(tip_d.ravel()) & np.isfinite(tip_s.ravel())
    print(f"\nagreement statics vs dynamics on {a.sizes['design']} designs ({both.sum()} paths tip by both):")
    print(f"{'quantity':<52} {'max':>9} {'median':>9} {'p99':>9} {'n':>7} {'within':>7}")
    for name, v, tol in (
        ("CoG, mm (every design, contact, pair, level)", d_cog, 0.05),
        ("tip pressure, MPa: statics root - dynamics interp.", (tip_s.ravel() - tip_d.ravel())[both], 0.01),
        ("tip pressure, MPa: statics interp. - dynamics interp.", (interp - tip_d.ravel())[both], 0.01),
        ("tip pressure, MPa: statics root - statics interp.", (tip_s.ravel() - interp)[both], 0.01),
    ):
        v = np.abs(v)
        print(
            f"{name:<52} {v.max():9.4f} {np.median(v):9.4f} {np.percentile(v, 99):9.4f} {v.size:7d} "
            f"{np.mean(v <= tol):6.1%}"
        )
    one = np.isfinite(tip_d.ravel()) != np.isfinite(tip_s.ravel())
    print(f"paths that tip by one method only: {int(one.sum())}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--designs", type=int, nargs="+", default=[8, 32, 128])
    ap.add_argument("--method", nargs="+", choices=["dynamics", "statics"], default=["dynamics", "statics"])
    ap.add_argument("--hold", type=float, default=1.0, help="s per level (the workflow's default 1 s)")
    ap.add_argument(
        "--sample-every", type=int, default=10, help="steps between averaged samples (10: the pipeline's 1 ms)"
    )
    ap.add_argument("--chunk-size", type=int, default=1000, help="designs per chunk job")
    ap.add_argument("--threads", type=int, default=2)
    args = ap.parse_args()
    import numba

    numba.set_num_threads(min(args.threads, numba.config.NUMBA_NUM_THREADS))
    cfg = stage_config(config.load(), "study_chunk")
    dt = cfg["sim"]["dt"]
    print(
        f"full workspace per design: 12 pairs x 12 levels x 2 contacts; dynamics: hold {args.hold} s, dt {dt} s, "
        f"samples every {args.sample_every} steps; {numba.get_num_threads()} threads; chunks of {args.chunk_size}"
    )
    print(
        f"{'designs':>8} {'method':>8} {'wall s':>8} {'cpu s':>8} {'designs/h':>10} {'10000 designs':>14} | "
        f"{'solver':>7} {'paper':>7} {'write':>7} {'rest':>7}"
    )
    for n in args.designs:
        with tempfile.TemporaryDirectory() as tmp:
            for method in args.method:
                wall, cpu, clock = run(cfg, n, method, args, Path(tmp) / method)
                solver = clock.get("simulate", 0.0) + clock.get("solve", 0.0)
                parts = (solver, clock.get("check_paper", 0.0), clock.get("write", 0.0))
                per_h = n / wall * 3600
                print(
                    f"{n:8d} {method:>8} {wall:8.2f} {cpu:8.1f} {per_h:10.0f} {10000 / per_h * 60:10.1f} min | "
                    + " ".join(f"{100 * x / wall:6.1f}%" for x in (*parts, wall - sum(parts)))
                )
            if len(args.method) == 2:
                agreement(Path(tmp) / "dynamics", Path(tmp) / "statics")


if __name__ == "__main__":
    main()
