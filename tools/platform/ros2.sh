#!/usr/bin/env bash
# Print the path of a ROS 2 Humble install's setup.bash, building it when needed:
#   source "$(tools/platform/ros2.sh)"
# A machine with ROS 2 Humble installed (/opt/ros/humble/setup.bash, as from Ubuntu 22.04's ROS
# apt archive) uses it. Otherwise two colcon workspaces are built from the sources in
# $PEPPER_ROS2_SOURCES (default ../shared/ros2 next to the checkout; its README gives both
# builds, which this follows) into the cache ${PEPPER_PLATFORM_CACHE:-$HOME/.cache/pepper_interface_tests}:
#   ros2-humble        the core up to rclpy, rmw_cyclonedds_cpp with Debian's Cyclone DDS, the
#                      common message packages and ros_environment (so its setup.bash sets
#                      ROS_VERSION, ROS_DISTRO and ROS_PYTHON_VERSION as a real install's does);
#                      about 4 minutes on 2 cores
#   ros2-humble-tools  on top of it, what every Humble install has besides: ros2cli (`ros2 run`,
#                      `ros2 topic`, ...), launch and launch_ros (`ros2 launch`), geometry2's
#                      tf2, tf2_msgs, tf2_py and tf2_ros_py; about 1.5 minutes
# each stamped when its build finished, so a second run reuses it; the path printed is the
# tools overlay's setup.bash (colcon chains the core's). A core built before ros_environment was
# part of it gets that package alone (seconds). Debian's apt packages the builds need are
# installed when missing (root); the builds run at nice 19. Logs: <cache>/ros2-humble*.log.
# Progress goes to stderr; only the path goes to stdout. Exit 2, with the reason and the fix on
# stderr, when there is neither an install nor the sources.
set -euo pipefail
here="$(cd "$(dirname "$0")/../.." && pwd)"
if [ -z "${PEPPER_ROS2_BUILD:-}" ] && [ -f /opt/ros/humble/setup.bash ]; then
  echo /opt/ros/humble/setup.bash; exit 0
fi
cache="${PEPPER_PLATFORM_CACHE:-$HOME/.cache/pepper_interface_tests}"
prefix="$cache/ros2-humble"
tools="$cache/ros2-humble-tools"
sources="${PEPPER_ROS2_SOURCES:-$(dirname "$here")/shared/ros2}"
core_tar="$sources/ros2-humble-core-src.tar.xz"
tools_tar="$sources/ros2-humble-tools-src.tar.xz"
if [ ! -f "$tools/.built" ] && { [ ! -f "$core_tar" ] || [ ! -f "$tools_tar" ]; }; then
  echo "[ros2] no ROS 2 Humble: no /opt/ros/humble and no ros2-humble-core-src.tar.xz and" \
    "ros2-humble-tools-src.tar.xz in $sources to build it from (install ros-humble-ros-base," \
    "or set PEPPER_ROS2_SOURCES to the folder holding both tarballs)" >&2
  exit 2
fi
APT=(cyclonedds-dev libspdlog-dev libyaml-cpp-dev libtinyxml2-dev libyaml-dev python3-lark
  python3-empy python3-catkin-pkg python3-numpy pybind11-dev python3-pybind11 libacl1-dev
  python3-yaml python3-setuptools colcon python3-colcon-ros python3-colcon-cmake
  python3-colcon-bash python3-colcon-python-setup-py python3-colcon-package-selection
  python3-colcon-parallel-executor python3-colcon-recursive-crawl python3-colcon-library-path
  python3-colcon-metadata python3-colcon-output python3-colcon-defaults
  python3-colcon-pkg-config python3-colcon-package-information
  python3-osrf-pycommon libconsole-bridge-dev python3-netifaces python3-argcomplete
  python3-packaging python3-pkg-resources python3-pytest)
mkdir -p "$cache"
missing=()
for p in "${APT[@]}"; do dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p"); done
if [ ${#missing[@]} -gt 0 ]; then
  if [ "$(id -u)" != 0 ]; then
    echo "[ros2] missing Debian packages: ${missing[*]} (install them as root)" >&2; exit 2
  fi
  echo "[ros2] installing ${#missing[@]} Debian packages for the ROS 2 build" >&2
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}" \
    >"$cache/ros2-apt.log" 2>&1 || { tail -20 "$cache/ros2-apt.log" >&2; exit 1; }
fi
COLCON=(colcon build --merge-install --parallel-workers 2)
CMAKE=(--cmake-args -DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=OFF -DPython3_EXECUTABLE=/usr/bin/python3)
build() {  # build <what> <log> <command...>: run in a clean PATH at nice 19, the log's tail on failure
  local what=$1 log=$2; shift 2
  if ! (PATH=/usr/sbin:/usr/bin:/sbin:/bin MAKEFLAGS=-j2 nice -n 19 "$@") >"$log" 2>&1; then
    echo "[ros2] building $what failed; last lines of $log:" >&2
    tail -20 "$log" >&2; exit 1
  fi
}
exec 9>"$prefix.lock"   # one build at a time; a second caller waits for it and reuses it
flock 9
if [ ! -f "$prefix/.built" ]; then
  echo "[ros2] building ROS 2 Humble's core into $prefix (about 4 minutes; log: $prefix.log)" >&2
  rm -rf "$prefix" "$tools"
  mkdir -p "$prefix"
  tar -xJf "$core_tar" -C "$prefix"
  (cd "$prefix" && build "ROS 2 Humble's core" "$prefix.log" "${COLCON[@]}" \
    --packages-up-to rclpy sensor_msgs std_msgs geometry_msgs nav_msgs diagnostic_msgs \
    ros_environment "${CMAKE[@]}")
  rm -rf "$prefix/build" "$prefix/log"
  touch "$prefix/.built"
fi
if [ ! -d "$prefix/install/share/ros_environment" ]; then   # a core built without it
  echo "[ros2] adding ros_environment to $prefix (log: $prefix-env.log)" >&2
  (cd "$prefix" && build ros_environment "$prefix-env.log" "${COLCON[@]}" --packages-select ros_environment "${CMAKE[@]}")
  rm -rf "$prefix/build" "$prefix/log"
  rm -rf "$tools"       # the overlay's setup files are regenerated on the completed core
fi
if [ ! -f "$tools/.built" ]; then
  echo "[ros2] building the tools overlay (ros2cli, launch, launch_ros, tf2_py, tf2_ros_py) into" \
    "$tools (about 1.5 minutes; log: $tools.log)" >&2
  rm -rf "$tools"
  mkdir -p "$tools"
  tar -xJf "$tools_tar" -C "$tools"
  (set +u; source "$prefix/install/setup.bash"; set -u
   cd "$tools" && build "the ROS 2 tools overlay" "$tools.log" "${COLCON[@]}" "${CMAKE[@]}")
  rm -rf "$tools/build" "$tools/log"
  touch "$tools/.built"
fi
echo "$tools/install/setup.bash"
