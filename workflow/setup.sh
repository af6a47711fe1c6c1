#!/usr/bin/env bash
# Set up the project's virtual environment in .venv from the pinned environment.txt (idempotent).
set -euo pipefail
cd "$(dirname "$0")/.."
PY=${PYTHON:-python3.11}
command -v "$PY" >/dev/null || PY=python3
if [ ! -x .venv/bin/python ]; then "$PY" -m venv .venv; fi
.venv/bin/python -m pip install -q --upgrade pip
.venv/bin/python -m pip install -q -r environment.txt
.venv/bin/python -m pip install -q --no-deps -e .
# the package's bytecode, once: where PYTHONDONTWRITEBYTECODE is set, every job would compile it
.venv/bin/python -m compileall -q tensegrity
# compile the simulator once (numba's cache), rather than in several of the first jobs at once
.venv/bin/python -c "from tensegrity.physics.dynamics import warm; warm()"
