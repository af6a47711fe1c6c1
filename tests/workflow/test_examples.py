"""Every code block of README.md and config/README.md, and every benchmark, runs (Warp's
test_examples habit), so that the documentation cannot drift from the code.

Where the real thing is too slow for the suite it runs on the tiny configuration: `tensegrity`
commands and Python blocks run for real inside a workflow copy that ran on
tests/workflow/tiny.yaml. A block with a `snakemake` command that starts a run RUNS it, in a
fresh scratch copy of the workflow of its own that starts from the tiny run's results and
Snakemake's records of them (so Snakemake re-runs every job whose configuration, code or inputs the
example changes, and what depends on them, and nothing else), with the
example's `--config`/`--configfile` merged over the tiny configuration and every output as the
target except the run's GIF (`locomotion.animation_run: null` before the example's own
configuration: 2 s each, and it does not depend on what the examples change; the smoke test
makes it) and the gravity-aware workspace with the slope limit (unless the example changes the
section `gravity`; the smoke test makes them); it must exit 0, and a run that did not
arrive must be named at the end and fail check 6. The grounded examples also leave out the
curves (`fit` and after: curves.json and the figures of `render`), which the tiny levels cannot give in
the grounded mode (see `_snakemake_argv`). A block whose command repeats an earlier one (config/README
repeats README's subset, finer levels and grounded mode) is not run twice.
README's two set-up commands are what CI itself runs, so they are not repeated.

The workflow runs of the examples (each a chain of jobs that keeps about one core busy) and the
benchmarks' tiny runs (single-threaded) are started two at a time, the first time a test asks for
them (`pipeline_runs`, `benchmark_runs`); each test then checks its own run's outcome.
"""

import os
import re
import shlex
import shutil
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[2]
TINY = ROOT / "tests" / "workflow" / "tiny.yaml"
NO_GIF = ROOT / "tests" / "workflow" / "no_gif.yaml"  # the examples' runs make no GIF
DOCS = ("README.md", "config/README.md")


def _blocks(doc: str) -> list[tuple[str, str, int]]:
    """(language, text, line) of every fenced code block of `doc`."""
    text = (ROOT / doc).read_text()
    out = []
    for m in re.finditer(r"^```(\w*)\n(.*?)^```", text, flags=re.S | re.M):
        out.append((m.group(1), m.group(2), text[: m.start()].count("\n") + 1))
    return out


def _commands(block: str) -> list[str]:
    """Shell commands of a block: continuation lines joined, comments dropped."""
    joined = re.sub(r"\\\n\s*", " ", block)
    return [
        line.split(" #")[0].strip()
        for line in joined.splitlines()
        if line.strip() and not line.lstrip().startswith("#")
    ]


EXAMPLES = [(doc, lang, text, line) for doc in DOCS for lang, text, line in _blocks(doc)]


def test_the_docs_have_examples_of_every_kind():
    kinds = {lang for _, lang, _, _ in EXAMPLES}
    assert {"bash", "python", "sh", "yaml"} <= kinds
    assert len(EXAMPLES) >= 15


def _env():
    return {**os.environ, "MPLBACKEND": "Agg"}


def _is_run(cmd: str) -> bool:
    """A snakemake command that starts a workflow run (not the report)."""
    argv = shlex.split(cmd)
    return bool(argv) and Path(argv[0]).name == "snakemake" and "--report" not in argv


def _snakemake_argv(argv: list[str]) -> list[str]:
    """The example's snakemake arguments with tests/workflow/tiny.yaml first among the config
    files (so that the example's own files and `--config` win), a run without the GIF."""
    args, files, i = [], [], 1
    while i < len(argv):
        if argv[i] in ("--configfile", "--configfiles"):
            i += 1
            while i < len(argv) and not argv[i].startswith("-"):
                files.append(argv[i])
                i += 1
            continue
        args.append(argv[i])
        i += 1
    # a design study (README "Design studies") runs its first 2 designs only
    args = [a for b in args for a in ([b, "study_limit=2"] if b.startswith("study=") else [b])]
    out = [
        sys.executable,
        "-m",
        "snakemake",
        *args,
        "--configfile",
        str(TINY),
        *([] if "--report" in argv else [str(NO_GIF)]),
        *files,
    ]
    if "--report" not in argv:
        omit = []
        if "mode: grounded" in " ".join(argv):
            # the tiny levels start at 1.2 MPa, where the grounded robot on #4 and #10 has already
            # rolled off: fit needs two standing levels and Fig. 6 one level of #10 before the
            # roll (with the default levels from 0.4 MPa they have them)
            omit += ["fit"]  # and the figures of `render` with it (Figs. 1 and 4-7, two-pair regions)
        # the gravity-aware workspace and the slope limit (the tiny run makes them) are left
        # out unless the example changes the section `gravity`
        if not re.search(r"\bgravity=|\bgravity:", " ".join(argv)):
            omit += ["gravity"]  # and what follows from it: slope_limit (with the gravity checks)
        out += ["--omit-from", *omit] if omit else []
        # the tiny run's records name its own copy's scripts: the code is the same checkout
        out += ["--rerun-triggers", "mtime", "params", "input", "software-env"]
    return out


def _run_shell(cmd: str, cwd: Path) -> tuple[int, str]:
    argv = shlex.split(cmd)
    exe = Path(argv[0]).name
    if exe == "snakemake":
        argv = _snakemake_argv(argv)
    elif exe == "tensegrity":
        argv = [sys.executable, "-m", "tensegrity.cli", *argv[1:]]
    else:  # printf ... > file and the like
        r = subprocess.run(cmd, shell=True, cwd=cwd, capture_output=True, text=True, env=_env())
        return r.returncode, r.stdout + r.stderr
    r = subprocess.run(argv, cwd=cwd, capture_output=True, text=True, env=_env(), timeout=900)
    return r.returncode, r.stdout + r.stderr


def _with_tiny_results(wd: Path, tiny: Path) -> Path:
    """`wd`, a fresh copy of the workflow, given the results of the tiny run and Snakemake's
    records of them (`.snakemake/metadata`: each output's params, code and inputs; mtimes kept),
    so that an example's run re-runs exactly the jobs its configuration changes (Snakemake's
    default rerun triggers) and what depends on them."""
    shutil.copytree(tiny / "results", wd / "results", symlinks=True)
    shutil.copytree(tiny / ".snakemake" / "metadata", wd / ".snakemake" / "metadata")
    return wd


def _run_key(text: str) -> tuple | None:
    """What a block's workflow runs depend on (its commands, --cores left out); None if it runs
    no workflow."""
    cmds = _commands(text)
    if not any(_is_run(c) for c in cmds):
        return None
    return tuple(" ".join(re.sub(r"--cores \d+", "", re.sub(r"^\S*snakemake", "snakemake", c)).split()) for c in cmds)


_FIRST_RUN: dict = {}
for _doc, _lang, _text, _line in EXAMPLES:
    if _lang in ("bash", "sh") and _run_key(_text) is not None:
        _FIRST_RUN.setdefault(_run_key(_text), f"{_doc}:{_line}")


def _runs_pipeline(text: str) -> bool:
    """A block that runs the workflow in a scratch copy of its own (not README's set-up line)."""
    return _run_key(text) is not None and not text.lstrip().startswith("bash workflow/setup.sh")


def _allowed(cmd: str, out: str) -> tuple[int, ...]:
    """Exit codes a command may end with: `roll` exits 1 when the robot did not arrive
    (documented); the tiny workspace has only five pairs, so a goal may be out of its reach: that
    is an outcome, not a crash."""
    return (0, 1) if " roll " in f" {cmd} " and "Traceback" not in out else (0,)


@pytest.fixture(scope="module")
def pipeline_runs(tiny, tmp_path_factory) -> dict:
    """{"doc:line": (scratch copy, [(command, exit code, output), ...])} of every block that runs
    the workflow (the first of equal ones), two at a time, each in a fresh copy of the workflow
    that starts from the tiny run's results (`_with_tiny_results`); a block stops at its first
    command that fails."""
    from workflow_copy import copy_workflow

    todo = [
        f"{d}:{n}"
        for d, lang, text, n in EXAMPLES
        if lang in ("bash", "sh") and _runs_pipeline(text) and _FIRST_RUN[_run_key(text)] == f"{d}:{n}"
    ]
    texts = {f"{d}:{n}": text for d, _, text, n in EXAMPLES}

    def run(name: str):
        cwd = _with_tiny_results(copy_workflow(tmp_path_factory.mktemp("example")), tiny)
        done = []
        for cmd in _commands(texts[name]):
            if cmd.startswith("bash workflow/setup.sh"):
                continue  # the README's set-up commands: CI runs them (see module docstring)
            code, out = _run_shell(cmd, cwd)
            done.append((cmd, code, out))
            if code not in _allowed(cmd, out):
                break
        return name, (cwd, done)

    with ThreadPoolExecutor(2) as pool:
        return dict(pool.map(run, todo))


@pytest.mark.parametrize("doc, lang, text, line", EXAMPLES, ids=[f"{d}:{n}" for d, _, _, n in EXAMPLES])
def test_example_runs(request, doc, lang, text, line):
    if lang == "text":  # sample output, not a command
        return
    if lang == "yaml":  # a configuration fragment: it must validate
        from tensegrity.io import config

        config.validate(yaml.safe_load(text))
        return
    if lang == "python":
        # the config/README snippets name a file and Snakemake's dict without making them
        prelude = (
            (
                "import yaml, types; open('my.yaml', 'w').write('sweep: {hold: 0.5}\\n')\n"
                "snakemake_config_dict = {}\nconfig = {}\n"
                "workflow = types.SimpleNamespace(configfiles=['my.yaml'])\n"
            )
            if doc.startswith("config/")
            else ""
        )
        r = subprocess.run(
            [sys.executable, "-c", prelude + text],
            cwd=request.getfixturevalue("tiny"),
            capture_output=True,
            text=True,
            env=_env(),
            timeout=300,
        )
        assert r.returncode == 0, f"{doc}:{line}\n{r.stderr[-3000:]}"
        return
    if _runs_pipeline(text):
        if _FIRST_RUN[_run_key(text)] != f"{doc}:{line}":
            pytest.skip(f"the same run as {_FIRST_RUN[_run_key(text)]}")
        cwd, done = request.getfixturevalue("pipeline_runs")[f"{doc}:{line}"]
    else:
        cwd = request.getfixturevalue("tiny")  # the workflow copy that ran on tiny.yaml
        done = ((cmd, *_run_shell(cmd, cwd)) for cmd in _commands(text) if not cmd.startswith("bash workflow/setup.sh"))
    for cmd, code, out in done:
        assert code in _allowed(cmd, out), f"{doc}:{line}: {cmd}\n{out[-3000:]}"
        if _is_run(cmd):  # a run that did not arrive is named at the end (and fails check 6)
            from tensegrity.io.formats.run import not_arrived

            bad = not_arrived(sorted((cwd / "results" / "locomotion").glob("*.nc")))
            for name, outcome, _ in bad:
                assert f"  {name}: {outcome} (" in out, f"{doc}:{line}: {name} did not arrive, unnamed"
            if (cwd / "results" / "validation" / "summary.md").exists():
                md = (cwd / "results" / "validation" / "summary.md").read_text()
                assert bool(bad) == bool(re.search(r"^\| 6 \| .* \| FAIL \|$", md, re.M)), md


BENCHMARKS = {
    "bench_step.py": ["--seconds", "0.01"],
    "bench_prototype.py": [
        "--drive",
        "0.05",
        "--settle",
        "0.01",
        "--rounds",
        "1",
        "--points",
        "2",
        "--names",
        "damping",
    ],
    "bench_locomotion.py": [
        "--workspace",
        "{tiny}/results/workspace.nc",
        "--two-pair",
        "{tiny}/results/workspace_two_pair.nc",
        "--tiny",
        "--steps",
        "--world",
        "friction=0.7",
    ],
    "bench_foresee.py": [
        "--workspace",
        "{tiny}/results/workspace.nc",
        "--two-pair",
        "{tiny}/results/workspace_two_pair.nc",
        "--grounds",
        "terrain0.07",
        "--repeat",
        "1",
    ],
    "bench_actuation.py": ["--slopes", "0", "--headings", "0", "--max-pressure", "3"],
    "bench_slope_multi.py": [
        "--gravity",
        "{tiny}/results/workspace_gravity.nc",
        "--workspace",
        "{tiny}/results/workspace.nc",
        "--contacts",
        "isosceles",
        "--iterations",
        "1",
    ],
    "bench_cable_actions.py": ["--tiny", "--ours"],
    "bench_slope_reach.py": [
        "--workspace",
        "{tiny}/results/workspace.nc",
        "--slopes",
        "20",
        "--headings",
        "1",
        "--no-combos",
    ],
    "calibration.py": ["--quick"],
    "bench_calibration.py": ["--seconds", "0.3", "--initial", "data", "--check", "0.3"],
    "bench_calibration_volts.py": ["--seeds", "1", "--seconds", "0.5", "--budget", "2", "--starts", "1"],
    "bench_calibration_independent.py": ["--tiny", "--coverage", "2"],
    "bench_calibration_intervals.py": ["--tiny", "--seeds", "1", "--windows", "2"],
    "bench_study.py": ["--designs", "2", "--hold", "0.05"],
    "bench_mujoco.py": ["--seconds", "0.01", "--batch", "2", "--repeat", "1"],
    "bench_env.py": ["--sizes", "1", "2", "--steps", "2", "--mujoco-steps", "2", "--repeat", "1"],
    "bench_pipeline.py": ["--runs", "1", "--configfile", "tests/workflow/tiny.yaml", "--until", "nominal"],
    "bench_surfaces.py": ["{tiny}/results/two_pair/isosceles.nc", "--statics", "1", "--folds", "4"],
    "bench_creep.py": ["{tiny}/results/sweeps", "--top", "2", "--history", "1"],
    "bench_averaging.py": ["--holds", "0.4", "--steps", "4.8", "--pairs", "10", "--contacts", "isosceles"],
    "bench_two_pair_averaging.py": ["--levels", "2.4", "4.8", "--pairs", "10", "11", "--hold", "0.5", "--no-statics"],
}


def test_every_benchmark_is_listed():
    assert sorted(p.name for p in (ROOT / "benchmarks").glob("*.py")) == sorted(BENCHMARKS)


@pytest.fixture(scope="module")
def benchmark_runs(tiny) -> dict:
    """{name: finished process} of every benchmark with its tiny arguments, two at a time."""

    def run(name: str):
        args = [a.format(tiny=tiny) for a in BENCHMARKS[name]]
        return name, subprocess.run(
            [sys.executable, str(ROOT / "benchmarks" / name), *args],
            cwd=ROOT,
            capture_output=True,
            text=True,
            env=_env(),  # MuJoCo (bench_mujoco.py, bench_env.py) is a test dependency in environment.txt
            timeout=600,
        )

    with ThreadPoolExecutor(2) as pool:
        return dict(pool.map(run, sorted(BENCHMARKS)))


@pytest.mark.parametrize("name", sorted(BENCHMARKS))
def test_benchmark_runs_with_tiny_arguments(benchmark_runs, name):
    r = benchmark_runs[name]
    assert r.returncode == 0, r.stderr[-3000:]
    assert r.stdout.strip(), "a benchmark prints figures"
    if name == "bench_mujoco.py":  # the same scheme in MuJoCo: free-mode nodes agree to round-off
        diff = float(re.search(r"largest node-trajectory difference .*?: (\S+) mm", r.stdout).group(1))
        assert diff < 1e-6, r.stdout  # (3e-13 mm; another scheme, RK4 or implicit damping: > 0.09 mm)


def test_bench_mujoco_without_mujoco_says_what_to_install():
    """Without MuJoCo the benchmark stops at once, non-zero, naming the requirements file."""
    script = str(ROOT / "benchmarks" / "bench_mujoco.py")
    code = (
        "import runpy, sys; sys.modules['mujoco'] = None; sys.argv = [sys.argv[0]]; "
        f"runpy.run_path({script!r}, run_name='__main__')"
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=_env(), timeout=120)
    assert r.returncode != 0 and not r.stdout
    assert "pip install -r benchmarks/requirements-mujoco.txt" in r.stderr, r.stderr
