#!/usr/bin/env bash
# The whole test suite: pytest over test/ (unit tests, integration tests against real roscore
# masters, the rostest files run through `rostest`). Extra arguments go to pytest.
# Test files run in 3 workers (pytest-xdist, one file per worker at a time): most tests wait on
# real-time listening windows, not on the CPU, and each starts its own master on a free port.
set -euo pipefail
cd "$(dirname "$0")/.."
source tools/env.sh
export PYTHONDONTWRITEBYTECODE=1
export ROS_HOME="${ROS_HOME:-$PWD/build/ros_home}"
mkdir -p "$ROS_HOME"
exec python -m pytest -p no:cacheprovider -n "${PYTEST_WORKERS:-3}" --dist loadfile "$@"
