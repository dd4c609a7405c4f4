#!/usr/bin/env bash
# The whole test suite: pytest over test/ (unit tests, integration tests against real roscore
# masters, the rostest files run through `rostest`). Extra arguments go to pytest.
set -euo pipefail
cd "$(dirname "$0")/.."
source tools/env.sh
export PYTHONDONTWRITEBYTECODE=1
export ROS_HOME="${ROS_HOME:-$PWD/build/ros_home}"
mkdir -p "$ROS_HOME"
exec python -m pytest -p no:cacheprovider "$@"
