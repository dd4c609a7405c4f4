#!/usr/bin/env bash
# Print the path of a ROS 2 Humble core install (its setup.bash), building it when needed.
#   source "$(tools/platform/ros2.sh)"
# A machine with ROS 2 Humble installed (/opt/ros/humble/setup.bash, as from Ubuntu 22.04's ROS
# apt archive) uses it. Otherwise the core up to rclpy with rmw_cyclonedds_cpp and the common
# message packages is built with colcon from ros2-humble-core-src.tar.xz (looked for in
# $PEPPER_ROS2_SOURCES, default ../shared/ros2 next to the checkout; its README gives the
# build this follows, about 4 minutes on 2 cores) into the cache
#   ${PEPPER_PLATFORM_CACHE:-$HOME/.cache/pepper_interface_tests}/ros2-humble
# outside the work tree, stamped when the build finished, so a second run reuses it.
# Debian's apt packages it needs (cyclonedds-dev, colcon, ...) are installed when missing
# (root); the build runs at nice 19. Log: <cache>/ros2-humble.log. Progress goes to stderr;
# only the path goes to stdout.
set -euo pipefail
here="$(cd "$(dirname "$0")/../.." && pwd)"
if [ -z "${PEPPER_ROS2_BUILD:-}" ] && [ -f /opt/ros/humble/setup.bash ]; then
  echo /opt/ros/humble/setup.bash; exit 0
fi
cache="${PEPPER_PLATFORM_CACHE:-$HOME/.cache/pepper_interface_tests}"
prefix="$cache/ros2-humble"
APT=(cyclonedds-dev libspdlog-dev libyaml-cpp-dev libtinyxml2-dev libyaml-dev python3-lark
  python3-empy python3-catkin-pkg python3-numpy pybind11-dev python3-pybind11 libacl1-dev
  python3-yaml python3-setuptools colcon python3-colcon-ros python3-colcon-cmake
  python3-colcon-bash python3-colcon-python-setup-py python3-colcon-package-selection
  python3-colcon-parallel-executor python3-colcon-recursive-crawl python3-colcon-library-path
  python3-colcon-metadata python3-colcon-output python3-colcon-defaults
  python3-colcon-pkg-config python3-colcon-package-information)
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
mkdir -p "$cache"
exec 9>"$prefix.lock"   # one build at a time; a second caller waits for it and reuses it
flock 9
if [ ! -f "$prefix/.built" ]; then
  sources="${PEPPER_ROS2_SOURCES:-$(dirname "$here")/shared/ros2}"
  tarball="$sources/ros2-humble-core-src.tar.xz"
  [ -f "$tarball" ] || { echo "[ros2] no ROS 2 Humble in /opt/ros/humble and no $tarball to build it" \
    "from (set PEPPER_ROS2_SOURCES to the folder holding ros2-humble-core-src.tar.xz)" >&2; exit 2; }
  echo "[ros2] building ROS 2 Humble's core into $prefix (about 4 minutes; log: $prefix.log)" >&2
  rm -rf "$prefix"
  mkdir -p "$prefix"
  if ! (tar -xJf "$tarball" -C "$prefix" && cd "$prefix" \
        && PATH=/usr/sbin:/usr/bin:/sbin:/bin MAKEFLAGS=-j2 nice -n 19 colcon build --merge-install \
          --parallel-workers 2 --packages-up-to rclpy sensor_msgs std_msgs geometry_msgs nav_msgs \
          diagnostic_msgs --cmake-args -DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=OFF \
          -DPython3_EXECUTABLE=/usr/bin/python3) >"$prefix.log" 2>&1; then
    echo "[ros2] building ROS 2 Humble's core failed; last lines of $prefix.log:" >&2
    tail -20 "$prefix.log" >&2; exit 1
  fi
  rm -rf "$prefix/build" "$prefix/log"
  touch "$prefix/.built"
fi
echo "$prefix/install/setup.bash"
