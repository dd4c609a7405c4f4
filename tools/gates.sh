#!/usr/bin/env bash
# The lint and type gates: ruff, then mypy --check-untyped-defs (both configured in
# pyproject.toml), then vermin for the minimum Python versions (tools/vermin.sh: 3.8 for the
# package, 2.7 for the capture side). Run by tools/run-tests.sh before pytest and by
# `make lint`; exit 1 when any finds a problem.
set -uo pipefail
cd "$(dirname "$0")/.."
rc=0
.venv/bin/ruff check --quiet . || { echo "gates: ruff found problems (safe fixes: tools/lint-fix.sh)" >&2; rc=1; }
.venv/bin/mypy --no-error-summary || { echo "gates: mypy found problems" >&2; rc=1; }
tools/vermin.sh || { echo "gates: vermin found calls the minimum Python lacks (tools/vermin.sh)" >&2; rc=1; }
exit $rc
