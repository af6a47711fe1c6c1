"""The default pipeline, cold (issue 11 item 3: <= 30 s on 2 cores, Snakemake's start included):
prints the wall time and the CPU time (user + sys of Snakemake and every job) of each run, and
the CPU time of every job that keeps a benchmark file. Asserts nothing.

Each run copies the workflow (Snakefile, config/, workflow/) of this checkout into an empty
temporary folder and runs `snakemake --cores N` there with this checkout's package, so
`results/` of the checkout is left alone; the numba cache is warmed first (the README's set-up
does it once). The machine's load average is printed with each run: on a shared machine the
wall time measures the other jobs as much as the code; the CPU time less so.

Usage: python benchmarks/bench_pipeline.py [--runs 3] [--cores 2] [--keep DIR]
       [--configfile FILE] [--until RULE]   (another configuration; a part of the pipeline)
"""

from __future__ import annotations

import argparse
import csv
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def children_cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def one_run(folder: Path, cores: int, extra: list[str]) -> tuple[float, float, dict[str, float]]:
    """Wall s, CPU s and {job: CPU s} of a cold run of the pipeline in `folder` (the default
    one; `extra`: more Snakemake arguments)."""
    for name in ("Snakefile", "config", "workflow"):
        src = ROOT / name
        (shutil.copytree if src.is_dir() else shutil.copy)(src, folder / name)
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    cpu0, t0 = children_cpu(), time.perf_counter()
    p = subprocess.run(
        [sys.executable, "-m", "snakemake", "--cores", str(cores), "-q", *extra],
        cwd=folder,
        env=env,
        capture_output=True,
        text=True,
    )
    wall, cpu = time.perf_counter() - t0, children_cpu() - cpu0
    if p.returncode:
        raise SystemExit(f"the pipeline failed (exit {p.returncode}):\n{p.stderr[-3000:]}")
    jobs = {}
    for tsv in sorted((folder / "results" / "benchmarks").rglob("*.tsv")):
        with open(tsv) as f:
            row = next(csv.DictReader(f, delimiter="\t"))
        jobs[str(tsv.relative_to(folder / "results" / "benchmarks").with_suffix(""))] = float(row["cpu_time"])
    return wall, cpu, jobs


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--cores", type=int, default=2)
    ap.add_argument("--keep", type=Path, help="leave the last run's folder here (new or empty)")
    ap.add_argument("--configfile", type=Path, help="a configuration over config/config.yaml")
    ap.add_argument("--until", help="run the pipeline up to this rule only")
    args = ap.parse_args()
    if args.keep and args.keep.exists() and any(args.keep.iterdir()):
        ap.error(f"--keep {args.keep}: the folder exists and is not empty")
    extra = (["--configfile", str(args.configfile.resolve())] if args.configfile else []) + (
        ["--until", args.until] if args.until else []
    )
    subprocess.run(
        [sys.executable, "-c", "from tensegrity.physics.dynamics import warm; warm()"],
        check=True,
        env=dict(os.environ, PYTHONPATH=str(ROOT)),
        capture_output=True,
    )
    walls, cpus = [], []
    for k in range(args.runs):
        with tempfile.TemporaryDirectory(prefix="bench_pipeline_") as tmp:
            load = os.getloadavg()[0]
            wall, cpu, jobs = one_run(Path(tmp), args.cores, extra)
            walls.append(wall)
            cpus.append(cpu)
            print(f"run {k + 1}: {wall:6.1f} s wall, {cpu:6.1f} s CPU  (load average {load:.1f} at the start)")
            if k == args.runs - 1:
                print("  CPU s of the jobs with a benchmark file (last run):")
                for name, c in sorted(jobs.items(), key=lambda kv: -kv[1]):
                    print(f"    {name:32s} {c:6.2f}")
                if args.keep:
                    shutil.copytree(tmp, args.keep, dirs_exist_ok=True)
    walls.sort(), cpus.sort()
    print(
        f"median of {args.runs}: {walls[len(walls) // 2]:.1f} s wall, {cpus[len(cpus) // 2]:.1f} s CPU "
        f"on {args.cores} cores (target: 30 s wall)"
    )


if __name__ == "__main__":
    main()
