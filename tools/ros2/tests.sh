#!/usr/bin/env bash
# The ROS 2 tier: the package on ROS 2 Humble's core (tools/platform/ros2.sh: /opt/ros/humble, or
# built from ../shared/ros2 into the cache), built with colcon (tools/ros2/workspace.sh), and
# the tests of test/ros2/ run through real rclpy with Cyclone DDS, each in a DDS domain of its
# own. Run by tools/run-tests.sh after the main suite (make test, CI); ROS2_TIER=0 leaves it out
# there. Extra arguments go to pytest.
set -euo pipefail
cd "$(dirname "$0")/../.."
ws=$(tools/ros2/workspace.sh)
# the ROS 1 environment, for the tests' side-by-side runs of the same data on ROS 1
mkdir -p build/ros2
( source tools/env.sh; env -0 ) > build/ros2/ros1.env
export PEPPER_ROS1_ENV="$PWD/build/ros2/ros1.env"
set +u
source "$ws"
set -u
export ROS_VERSION=2
export PEPPER_ROS2_PREFIX="${ws%/setup.bash}"     # the tests run the installed programs
export RMW_IMPLEMENTATION=${RMW_IMPLEMENTATION:-rmw_cyclonedds_cpp}
export ROS_LOCALHOST_ONLY=${ROS_LOCALHOST_ONLY:-1}
export PATH="$PWD/.venv/bin:$PATH"
unset PYTHONDONTWRITEBYTECODE
export PYTHONPYCACHEPREFIX="$PWD/build/ros2/pycache"
export ROS_HOME="${ROS_HOME:-$PWD/build/ros2/ros_home}"
mkdir -p "$ROS_HOME"
echo "[ros2] $(python -V 2>&1), rclpy from ${ws%/setup.bash}, $RMW_IMPLEMENTATION"
start=$SECONDS
rc=0
python -m pytest -p no:cacheprovider -q test/ros2 "$@" || rc=1
echo "[ros2] the ROS 2 tier took $((SECONDS - start)) s"
exit $rc
