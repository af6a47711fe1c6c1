"""The tiny workflow submitted through a real single-node SLURM cluster: run unchanged
with `--workflow-profile workflow/profiles/slurm`, it gives the same datasets as a local run.

The cluster (munged, slurmctld, slurmd from Debian's packages) is started by
tests/workflow/slurm/start_cluster.sh, which installs the packages with apt if they are missing, and is
stopped by tests/workflow/slurm/stop_cluster.sh if this module started it, which also puts the machine's
/etc/slurm back as it was. The executor plugin (workflow/profiles/slurm/requirements.txt, not in
environment.txt) is used from the environment if installed there, else installed with pip into a
temporary folder put on the runs' PYTHONPATH. Needs root; skipped otherwise, or with
TENSEGRITY_SKIP_SLURM=1. Takes about 2 minutes on 2 cores. A tiny design study (issue 12) goes
through the cluster too and must give the same bytes as locally.
"""

import collections
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest
import xarray as xr

ROOT = Path(__file__).resolve().parents[2]
SCRIPTS = ROOT / "tests" / "workflow" / "slurm"
SNAKEMAKE = [sys.executable, "-m", "snakemake"]
# Up to the workspace and the curves (which fit with the two-pair surfaces: they need the
# two-pair sweeps), and the gravity-aware workspace (the figures are left out; the whole tiny
# workflow runs locally in the `tiny` fixture).
TARGETS = ["results/workspace.nc", "results/curves/curves.json", "results/workspace_gravity.nc"]
# Rules that are not `localrule: True` and so must go through sbatch, with their job counts.
SUBMITTED = {"sweep": 1, "two_pair": 1, "gravity": 1}
PIDFILES = ["/run/munge/munged.pid", "/run/slurmctld.pid", "/run/slurmd.pid"]
# One file per test session using the cluster (named by its PID): the last one out stops it, so
# that a session does not stop the cluster under another's jobs, nor leave it running.
USERS = Path("/run/tensegrity-slurm-test-users")
STATE = Path("/var/lib/tensegrity-slurm-test")  # written by start_cluster.sh (its first start)
SUBMIT_LINE = re.compile(r"Job \d+ has been submitted with SLURM jobid (\d+) \(log: .*/rule_(\w+)/")


def _skip_reason() -> str | None:
    if os.environ.get("TENSEGRITY_SKIP_SLURM") == "1":
        return "TENSEGRITY_SKIP_SLURM=1"
    if os.geteuid() != 0:
        return "needs root to install and run a SLURM cluster (munged, slurmctld, slurmd)"
    if not (Path("/usr/sbin/slurmctld").exists() or shutil.which("apt-get")):
        return "SLURM is not installed and apt-get is not available to install it"
    return None


SKIP = _skip_reason()
pytestmark = pytest.mark.skipif(SKIP is not None, reason=f"SLURM test: {SKIP}")


def _slurm_conf() -> tuple[str, ...]:
    """/etc/slurm/slurm.conf* as "name:contents", sorted by name."""
    return tuple(f"{p.name}:{p.read_text()}" for p in sorted(Path("/etc/slurm").glob("slurm.conf*")))


def _ours(entry: str) -> bool:
    """Whether an entry of _slurm_conf() was written by start_cluster.sh (any version)."""
    return entry.partition(":")[2].startswith("# Written by tests/")


def _running(pidfile: str) -> bool:
    try:
        os.kill(int(Path(pidfile).read_text()), 0)
        return True
    except (OSError, ValueError):
        return False


@pytest.fixture(scope="module")
def plugin_env(tmp_path_factory) -> dict:
    """The environment of the Snakemake runs: PYTHONPATH holds the SLURM executor plugin if it
    is not installed (it is kept out of environment.txt, see workflow/profiles/slurm/)."""
    env = dict(os.environ)
    probe = [sys.executable, "-c", "import snakemake_executor_plugin_slurm"]
    if subprocess.run(probe, capture_output=True).returncode == 0:
        return env
    target = tmp_path_factory.mktemp("slurm-plugin")
    r = subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "install",
            "-q",
            "--no-deps",
            "--target",
            str(target),
            "-r",
            str(ROOT / "workflow/profiles/slurm/requirements.txt"),
        ],
        capture_output=True,
        text=True,
        timeout=600,
    )
    if r.returncode != 0:
        pytest.skip(f"the SLURM executor plugin could not be installed: {r.stderr.strip()[-500:]}")
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(target), env.get("PYTHONPATH")]))
    return env


@pytest.fixture(scope="module")
def cluster():
    """A running single-node cluster; stopped at the end if this fixture started it. Yields
    (whether it started it, the slurm.conf files before)."""
    was_running = all(_running(p) for p in PIDFILES)
    before = _slurm_conf()
    USERS.mkdir(parents=True, exist_ok=True)
    me = USERS / str(os.getpid())
    me.touch()
    r = subprocess.run(["bash", str(SCRIPTS / "start_cluster.sh")], capture_output=True, text=True, timeout=900)
    if r.returncode == 3:
        pytest.skip(f"SLURM packages could not be installed: {r.stderr.strip()[-500:]}")
    if r.returncode != 0:
        pytest.fail(
            f"tests/workflow/slurm/start_cluster.sh failed (exit {r.returncode}):\n"
            f"{r.stdout[-2000:]}\n{r.stderr[-3000:]}",
            pytrace=False,
        )
    print(r.stdout)
    try:
        yield not was_running, before
    finally:
        me.unlink(missing_ok=True)
        if _last_user() and (not was_running or STATE.exists()):
            subprocess.run(["bash", str(SCRIPTS / "stop_cluster.sh")], timeout=120)


def _last_user() -> bool:
    """Whether no other live test session uses the cluster (stale entries are removed)."""
    others = False
    for f in USERS.glob("*"):
        if f.name == str(os.getpid()):
            continue
        if _running_pid(f.name):
            others = True
        else:
            f.unlink(missing_ok=True)
    return not others


def _running_pid(pid: str) -> bool:
    try:
        os.kill(int(pid), 0)
        return True
    except (OSError, ValueError):
        return False


def _copy(tmp: Path) -> Path:
    shutil.copy(ROOT / "Snakefile", tmp)
    shutil.copytree(ROOT / "workflow", tmp / "workflow")
    shutil.copytree(ROOT / "config", tmp / "config")
    return tmp


def _snakemake(wd: Path, *args: str, timeout: float, env: dict | None = None) -> str:
    cmd = SNAKEMAKE + TARGETS + list(args) + ["--configfile", str(ROOT / "tests/workflow/tiny.yaml")]
    try:
        r = subprocess.run(cmd, cwd=wd, capture_output=True, text=True, timeout=timeout, env=env)
    except subprocess.TimeoutExpired as e:
        out = (e.stdout or b"").decode() if isinstance(e.stdout, bytes) else (e.stdout or "")
        err = (e.stderr or b"").decode() if isinstance(e.stderr, bytes) else (e.stderr or "")
        pytest.fail(f"{' '.join(args)}: no result after {timeout} s\n{(out + err)[-3000:]}")
    assert r.returncode == 0, f"{' '.join(args)}:\n{(r.stdout + r.stderr)[-3000:]}"
    return r.stdout + r.stderr


@pytest.fixture(scope="module")
def runs(cluster, plugin_env, tmp_path_factory, tiny):
    """(SLURM scratch copy, its Snakemake output, the local run: the session's tiny run, which
    made every target of the SLURM run with the same configuration)."""
    slurm = _copy(tmp_path_factory.mktemp("slurm"))
    # the relative profile path, from the scratch copy, as a user types it from the repo root
    log = _snakemake(slurm, "--workflow-profile", "workflow/profiles/slurm", timeout=600, env=plugin_env)
    return slurm, log, tiny


def test_jobs_went_through_slurm(runs):
    slurm, log, _ = runs
    submitted = {int(j): rule for j, rule in SUBMIT_LINE.findall(log)}
    assert collections.Counter(submitted.values()) == SUBMITTED, log[-3000:]
    # slurmctld keeps finished jobs for MinJobAge = 300 s, so squeue still lists them
    ids = ",".join(map(str, submitted))
    q = subprocess.run(
        ["squeue", "-h", "-t", "all", "-j", ids, "-o", "%i %T %C"], capture_output=True, text=True, check=True
    ).stdout.split("\n")
    seen = {int(i): (state, int(cpus)) for i, state, cpus in (line.split() for line in q if line)}
    assert set(seen) == set(submitted), q
    for job, rule in submitted.items():
        assert seen[job][0] == "COMPLETED", (job, rule, seen[job])
    # a rule's threads reach sbatch as --cpus-per-task (gravity: 2 by the profile's set-threads,
    # sweep: 1)
    assert {seen[j][1] for j, rule in submitted.items() if rule == "gravity"} == {2}
    assert {seen[j][1] for j, rule in submitted.items() if rule == "sweep"} == {1}


def test_slurm_gives_the_same_datasets_as_local(runs):
    slurm, _, local = runs
    files = sorted(p.relative_to(slurm) for p in (slurm / "results").rglob("*.nc"))
    # sweeps, nominal, curves, workspace, gravity-aware workspace, two-pair sweeps and workspace
    assert len(files) == 2 * 5 + 2 + 2 + 1 + 1 + 2 + 1
    for f in files:
        with xr.open_dataset(slurm / f) as a, xr.open_dataset(local / f) as b:
            # data, coordinates and attributes (the provenance config) alike
            assert a.identical(b), f
    for json in ("results/curves/curves.json", "results/curves/two_pair.json"):
        assert (slurm / json).read_bytes() == (local / json).read_bytes(), json


# Design studies (issue 12): the tiny study (tests/studies/tiny_study.yaml, two chunk jobs) through
# the cluster and locally, after the workflow runs above (their files are counted first).
STUDY = ROOT / "tests" / "studies" / "tiny_study.yaml"
STUDY_FILES = ["chunks/chunk0000.nc", "chunks/chunk0001.nc", "designs.nc", "analysis.nc"]


def _study(wd: Path, *args: str, env: dict | None = None) -> str:
    shutil.copy(STUDY, wd / "config" / "studies" / "tiny_study.yaml")
    cmd = SNAKEMAKE + [
        "study",
        *args,
        "--config",
        "study=tiny_study",
        "--configfile",
        str(ROOT / "tests/workflow/tiny.yaml"),
    ]
    r = subprocess.run(cmd, cwd=wd, capture_output=True, text=True, timeout=600, env=env)
    assert r.returncode == 0, f"{' '.join(args)}:\n{(r.stdout + r.stderr)[-3000:]}"
    return r.stdout + r.stderr


def test_a_design_study_runs_through_slurm_as_locally(runs, plugin_env, study_run):
    slurm, local = runs[0], study_run  # the same study run locally (conftest.py)
    log = _study(slurm, "--workflow-profile", "workflow/profiles/slurm", env=plugin_env)
    submitted = collections.Counter(rule for _, rule in SUBMIT_LINE.findall(log))
    assert submitted == {"study_chunk": 2}, log[-3000:]  # merge and analysis are local rules
    for f in STUDY_FILES:
        a, b = (wd / "results/studies/tiny_study" / f for wd in (slurm, local))
        assert a.read_bytes() == b.read_bytes(), f  # same bytes: deterministic, wherever it ran


def test_stop_cluster_puts_the_machine_back(cluster, runs):
    """Run last: stop_cluster.sh leaves no test slurm.conf behind (it made every later
    `scontrol`, and with it the SLURM plugin at Snakemake's start, wait ~10 s for a controller)."""
    started, before = cluster
    if not started:
        pytest.skip("the cluster was running before this module: not stopped here")
    if not _last_user():
        pytest.skip("another test session uses the cluster: not stopped here")
    r = subprocess.run(["bash", str(SCRIPTS / "stop_cluster.sh")], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr
    assert not any(_running(p) for p in PIDFILES)
    # the machine's own slurm.conf as it was, none written by a (possibly older) start_cluster.sh
    assert _slurm_conf() == tuple(f for f in before if not _ours(f)), _slurm_conf()
    assert not Path("/var/lib/tensegrity-slurm-test").exists()
    if Path("/etc/slurm/slurm.conf").exists():
        return  # the machine's own configuration, put back: its controller is not ours to test
    t0 = time.perf_counter()
    subprocess.run(["scontrol", "show", "config"], capture_output=True, timeout=60)
    assert time.perf_counter() - t0 < 5, "scontrol still waits for a controller"
