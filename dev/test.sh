#!/usr/bin/env bash
# The project's whole test command: lint, format, types, then every test (slow ones included).
# Extra arguments go to pytest, e.g. `bash dev/test.sh tests/sim`.
#
# `bash dev/test.sh --fast [PYTEST ARGS]`: what to run before a commit (docs/development.md):
# lint, format, types, validate motions/, then the tests not marked slow (none over 10 s);
# not the batch of motions/ nor dev/hostile.py (CI runs both).
set -euo pipefail
cd "$(dirname "$0")/.."
PY=${PYTHON:-.venv/bin/python}
# A Python process that crashes (SIGSEGV in a native library) prints its threads' stacks, so a
# test that sees a child die by a signal shows where (a batch driver on Ray died so, once).
export PYTHONFAULTHANDLER=1
FAST=0
if [[ "${1:-}" == "--fast" ]]; then
  FAST=1
  shift
fi

"$PY" -m ruff check .
"$PY" -m ruff format --check .
# mypy resolves `motiontool.*` through a link to the repository root (the package's source).
mkdir -p build/typecheck && ln -sfn ../.. build/typecheck/motiontool
"$PY" -m mypy -p motiontool.motionfmt -p motiontool.kinematics -p motiontool.sim -p motiontool.cli
# The project's own motion library must validate clean, warnings included.
"$(dirname "$PY")/motiontool" validate motions/ --strict
if ((FAST)); then
  exec "$PY" -m pytest -n 2 -q -m "not slow" "$@"
fi
# ... and play clean in MuJoCo (no fall, no self-collision, no simulator warning).
"$(dirname "$PY")/motiontool" batch motions/ --no-cache --jobs 2
# Hostile outputs and inputs: no traceback, no device, FIFO or symlink replaced.
"$PY" dev/hostile.py --jobs 2
"$PY" -m pytest -n 2 "$@"
