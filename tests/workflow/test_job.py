"""stages.job, the body of every workflow script: the log gets the output, a success ends the
process at once with status 0 and everything written, a failure exits non-zero with the
traceback in the log."""

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

BODY = """
import atexit, sys
from tensegrity import stages
atexit.register(lambda: open(sys.argv[1] + ".teardown", "w").close())  # skipped on success
with stages.job(sys.argv[1] + ".log"):
    print("working")
    with open(sys.argv[1] + ".out", "w") as f:
        f.write("done")
    if sys.argv[2] == "fail":
        raise ValueError("the stage failed")
print("never reached", file=sys.stderr)
"""


def _run(tmp_path: Path, how: str) -> tuple[subprocess.CompletedProcess, Path]:
    base = tmp_path / how
    p = subprocess.run(
        [sys.executable, "-c", BODY, str(base), how], capture_output=True, text=True, cwd=ROOT, timeout=120
    )
    return p, base


def test_a_job_that_succeeds_ends_at_once_with_its_output_written(tmp_path):
    p, base = _run(tmp_path, "ok")
    assert p.returncode == 0, p.stderr
    assert Path(str(base) + ".out").read_text() == "done"
    assert Path(str(base) + ".log").read_text() == "working\n"
    assert "never reached" not in p.stderr
    assert not Path(str(base) + ".teardown").exists()  # the interpreter's teardown was skipped


def test_a_job_that_fails_exits_nonzero_with_the_traceback_in_its_log(tmp_path):
    p, base = _run(tmp_path, "fail")
    assert p.returncode == 1
    log = Path(str(base) + ".log").read_text()
    assert log.startswith("working\n") and "ValueError: the stage failed" in log
    assert "ValueError: the stage failed" in p.stderr
