#!/usr/bin/env bash
# The lint and type gates (configured in pyproject.toml): ruff, then mypy --check-untyped-defs.
# Run by tools/run-tests.sh before pytest and by `make lint`; exit 1 when either finds a problem.
set -uo pipefail
cd "$(dirname "$0")/.."
rc=0
.venv/bin/ruff check --quiet . || { echo "gates: ruff found problems (safe fixes: tools/lint-fix.sh)" >&2; rc=1; }
.venv/bin/mypy --no-error-summary || { echo "gates: mypy found problems" >&2; rc=1; }
exit $rc
