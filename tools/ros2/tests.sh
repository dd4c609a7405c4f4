#!/usr/bin/env bash
# The ROS 2 tier: the package on ROS 2 Humble's core (tools/platform/ros2.sh: /opt/ros/humble, or
# built from ../shared/ros2 into the cache), built with colcon (tools/ros2/workspace.sh), and
# the tests of test/ros2/ (and test/sources/test_tf_buffer.py: the tree's answers from ROS 2's
# own tf2) run through real rclpy with Cyclone DDS, each in a DDS domain of its own, every
# program started as users start it (`ros2 run`, `ros2 launch`). Run by tools/run-tests.sh
# after the main suite (make test, CI); ROS2_TIER=0 leaves it out there. Extra arguments go to
# pytest. No ROS 2 to run on (no /opt/ros/humble, no sources in $PEPPER_ROS2_SOURCES): one
# line "[ros2] NOT RUN: <reason and fix>" and exit 3, which tools/run-tests.sh reports.
set -euo pipefail
cd "$(dirname "$0")/../.."
mkdir -p build/ros2
# the build's progress on stderr as it goes; the reason there is no ROS 2 (exit 2) said once below
set +e
{ tools/ros2/workspace.sh 2>&1 >build/ros2/ws.path; } | tee build/ros2/platform.err \
  | { grep --line-buffered -v '^\[ros2\] \(no ROS 2\|missing Debian\)' >&2; true; }
trc=${PIPESTATUS[0]}
set -e
if [ $trc = 2 ]; then
  echo "[ros2] NOT RUN: $(tail -1 build/ros2/platform.err | sed 's/^\[ros2\] //')"
  exit 3
elif [ $trc != 0 ]; then
  exit 1
fi
ws=$(cat build/ros2/ws.path)
# the ROS 1 environment, for the tests' side-by-side runs of the same data on ROS 1
( source tools/env.sh; env -0 ) > build/ros2/ros1.env
export PEPPER_ROS1_ENV="$PWD/build/ros2/ros1.env"
set +u
source "$ws"
set -u
# ros_environment's hooks set these on every ROS 2 install, as for a user (not this script)
if [ "${ROS_VERSION:-}" != 2 ] || [ -z "${ROS_DISTRO:-}" ]; then
  echo "[ros2] $ws did not set ROS_VERSION=2 and ROS_DISTRO (no ros_environment in that install)" >&2
  exit 1
fi
export PEPPER_ROS2_PREFIX="${ws%/setup.bash}"     # the tests run the installed programs
export RMW_IMPLEMENTATION=${RMW_IMPLEMENTATION:-rmw_cyclonedds_cpp}
export ROS_LOCALHOST_ONLY=${ROS_LOCALHOST_ONLY:-1}
export PATH="$PWD/.venv/bin:$PATH"
unset PYTHONDONTWRITEBYTECODE
export PYTHONPYCACHEPREFIX="$PWD/build/ros2/pycache"
export ROS_HOME="${ROS_HOME:-$PWD/build/ros2/ros_home}"
mkdir -p "$ROS_HOME"
echo "[ros2] $(python -V 2>&1), ROS 2 $ROS_DISTRO, $(command -v ros2), $RMW_IMPLEMENTATION"
start=$SECONDS
rc=0
# launch_testing's, launch_testing_ros' and launch_pytest's pytest plugins (the tools overlay, as
# on every Humble install) import each test file to look for launch tests: not this suite's
python -m pytest -p no:cacheprovider -p no:launch_testing -p no:launch_ros -p no:launch_pytest -q \
  test/ros2 test/sources/test_tf_buffer.py "$@" || rc=1
echo "[ros2] the ROS 2 tier took $((SECONDS - start)) s"
exit $rc
