#!/usr/bin/env bash
# ruff's SAFE auto-fixes (import order, unused imports, pyupgrade, ...) over the whole tree, or
# over the files given; then the gates (tools/gates.sh) list what is left for hand fixing.
# Unsafe fixes are never applied.
set -uo pipefail
cd "$(dirname "$0")/.."
.venv/bin/ruff check --fix --exit-zero --quiet "${@:-.}"
exec tools/gates.sh
