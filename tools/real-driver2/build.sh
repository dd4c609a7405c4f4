#!/usr/bin/env bash
# Build the real ros-naoqi/naoqi_driver2 (ROS 2, tag 2.1.2) on the ROS 2 Humble core the
# ROS 2 tier builds (tools/platform/ros2.sh) plus the tools overlay, into a cache outside the
# repository. Not part of `make test`. See README.md beside this file (times measured here).
#
#   tools/real-driver2/build.sh                     # clone from GitHub, build
#   NAOQI_SOURCES=/work/.mirror tools/real-driver2/build.sh
#
# NAOQI_SOURCES names a directory holding local copies: either <name>/ (a clone) or
# <owner>+<name>/repo (a bare git dir) for each repository of SOURCES below.
# PEPPER_REAL_DRIVER2_CACHE (default /var/cache/pepper-real-driver2): sources, build, install.
# PEPPER_ROS2_SOURCES (default ../shared/ros2): the core and tools tarballs.
# JOBS (default 2): compile jobs at once, all under `nice -n 19` (the machine is shared).
# SKIP_APT=1 skips apt-get. Every step prints its wall time; the log goes to $CACHE/build.log.
set -euo pipefail
HERE="$(cd "$(dirname "$0")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
CACHE="${PEPPER_REAL_DRIVER2_CACHE:-/var/cache/pepper-real-driver2}"
ROS2_SOURCES="${PEPPER_ROS2_SOURCES:-$(dirname "$ROOT")/shared/ros2}"
JOBS="${JOBS:-2}"
mkdir -p "$CACHE"
exec > >(tee -a "$CACHE/build.log") 2>&1

# owner/name  commit (the tag or branch it is)  -- the packages naoqi_driver 2.1.2 needs
# (its package.xml and CMakeLists.txt) and theirs, at Humble's released versions.
SOURCES=(
  "ros-naoqi/naoqi_driver2 10c4ca969642ff8298495f8116ab880890624acd 2.1.2"
  "ros-naoqi/libqi 63ffe7cb4962f4b1f05f32b515ef255754d5e7c9 ros2(3.0.2+1)"
  "ros-naoqi/libqicore b3b8e96bb2058eb89728ebf15cf2469350e13354 ros2(3.0.0+1)"
  "ros-naoqi/naoqi_bridge_msgs2 7181df72474464595db06136189c385b82e72f8e 2.1.0"
  "ros2/rclcpp e9edc3fda0ec9fbdcb64669e7c6dfbb60924feab 16.0.11"
  "ros2/message_filters fc93cd991ffbb4be67db57ae91f1cde3a8719fc0 4.3.5"
  "ros2/geometry2 d0dbd516d1748cfe1b293e0f7d5b2f82ddd3438a 0.25.8"
  "ros2/urdf a76814dc40d7b20a12db56f2ab623989eae3bda9 2.5.2"
  "ros2/orocos_kdl_vendor d390ba45a77d8d49746a784d10a88cb77e86f703 0.2.5"
  "ros2/eigen3_cmake_module 526c6c745da360fe78fb727aa8a1f6daa8199abd 0.1.1"
  "ros/class_loader b59bce93380b73ac9061fba28e96bba540e2befe 2.2.0"
  "ros/pluginlib fc2d015a594bb582c1143a9e2b8b8d9f6f8c75fc 5.1.0"
  "ros/kdl_parser a4ad6b3c1dbf3730a579b250be81e4a74e838b94 2.6.4"
  "ros/robot_state_publisher 8b5af4f31e0f754c7c262eb487ccd3956cb788cc 3.0.3"
  "ros/diagnostics e3e5842152c07ed0970ac9d350b3bd72a6fdf933 3.1.2"
  "ros-perception/image_common d118138d5a2232acdf617c9b4f8348bfa823e2e2 3.1.9"
  "ros-perception/vision_opencv 066793a23e5d06d76c78ca3d69824a501c3554fd 3.2.1"
)

step_start=0
step() { step_start=$(date +%s); echo "[real-driver2] $(date -u +%H:%M:%S) step: $*"; }
done_step() { echo "[real-driver2] $(date -u +%H:%M:%S) done in $(( $(date +%s) - step_start )) s"; }
colcon_build() {  # colcon in $1 (a workspace), into $2 (its install), more arguments after
  local ws="$1" install="$2"; shift 2
  (cd "$ws" && PATH=/usr/sbin:/usr/bin:/sbin:/bin nice -n 19 colcon build --merge-install \
    --install-base "$install" "$@" --cmake-args -DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=OFF \
    -DPython3_EXECUTABLE=/usr/bin/python3)
}

step "1/8 Debian packages (debian-packages.txt)"
if [ "${SKIP_APT:-0}" != 1 ]; then
  mapfile -t pkgs < <(grep -v '^\s*#' "$HERE/debian-packages.txt" | grep -v '^\s*$')
  missing=()
  for p in "${pkgs[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'ok installed' || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    SUDO=""; [ "$(id -u)" = 0 ] || SUDO=sudo
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
  fi
fi
done_step

step "2/8 the ROS 2 Humble core (tools/platform/ros2.sh: waits for its lock, ~4 min if not built)"
CORE_SETUP="$("$ROOT/tools/platform/ros2.sh")"
echo "[real-driver2] core: $CORE_SETUP"
done_step

step "3/8 the tools overlay ($ROS2_SOURCES/ros2-humble-tools-src.tar.xz) into $CACHE/tools"
if [ ! -f "$CACHE/tools/.built" ]; then
  rm -rf "$CACHE/tools" && mkdir -p "$CACHE/tools/ws"
  tar -xJf "$ROS2_SOURCES/ros2-humble-tools-src.tar.xz" -C "$CACHE/tools/ws"
  set +u; source "$CORE_SETUP"; set -u   # shellcheck disable=SC1090
  MAKEFLAGS=-j1 colcon_build "$CACHE/tools/ws" "$CACHE/tools/install" --parallel-workers "$JOBS"
  rm -rf "$CACHE/tools/ws/build" "$CACHE/tools/ws/log"
  touch "$CACHE/tools/.built"
fi
done_step

step "4/8 sources into $CACHE/ws/src at the pinned commits (patched)"
set +u; source "$CACHE/tools/install/setup.bash"; set -u   # shellcheck disable=SC1091
mkdir -p "$CACHE/ws/src"
: > "$CACHE/sources.txt"
for entry in "${SOURCES[@]}"; do
  read -r repo commit tag <<<"$entry"
  owner="${repo%%/*}"; name="${repo##*/}"
  dest="$CACHE/ws/src/$name"
  if [ ! -d "$dest/.git" ]; then
    src="https://github.com/$repo.git"
    if [ -n "${NAOQI_SOURCES:-}" ]; then
      if [ -d "$NAOQI_SOURCES/$owner+$name/repo" ]; then src="$NAOQI_SOURCES/$owner+$name/repo"
      elif [ -d "$NAOQI_SOURCES/$name" ]; then src="$NAOQI_SOURCES/$name"
      else echo "[real-driver2] $repo not found under NAOQI_SOURCES=$NAOQI_SOURCES" >&2; exit 2; fi
    fi
    git clone -q --no-checkout "$src" "$dest"
    git -C "$dest" -c advice.detachedHead=false checkout -q "$commit"
    for patch in "$HERE"/patches/"$name"-*.patch; do
      [ -e "$patch" ] || continue
      echo "[real-driver2] applying $(basename "$patch")"
      git -C "$dest" apply "$patch"
    done
  fi
  echo "$repo $tag $(git -C "$dest" rev-parse HEAD)" | tee -a "$CACHE/sources.txt"
done
# The core's packages that tools/platform/ros2.sh does not build (trajectory_msgs,
# composition_interfaces, libstatistics_collector...): from the same tarball, same commits.
if [ ! -d "$CACHE/ws/src/core" ]; then
  mkdir -p "$CACHE/ws/src/core"
  tar -xJf "$ROS2_SOURCES/ros2-humble-core-src.tar.xz" -C "$CACHE/ws/src/core"
fi
# A package the underlay already installs is not built again: every prefix of the sourced
# environment (this cache's tools overlay, the platform's tools overlay, the core; ros2.sh may
# print any of their setup files, so the prefixes are read from AMENT_PREFIX_PATH).
IFS=: read -r -a UNDERLAY <<<"${AMENT_PREFIX_PATH:-}"
while IFS= read -r xml; do
  dir="$(dirname "$xml")"
  pkg="$(sed -n 's:.*<name>\(.*\)</name>.*:\1:p' "$xml" | head -1)"
  for prefix in "${UNDERLAY[@]}"; do
    if [ -f "$prefix/share/$pkg/package.xml" ]; then touch "$dir/COLCON_IGNORE"; break; fi
  done
done < <(find "$CACHE/ws/src" -name package.xml -not -path '*/.git/*')
done_step

# (rclcpp_lifecycle is built: message_filters 4.3.5 names it as a test_depend, and colcon
# sources every dependency's environment, tests built or not)
step "5/8 colcon: what naoqi_driver needs ($JOBS packages at once, -j1 each, nice 19, Release)"
MAKEFLAGS=-j1 colcon_build "$CACHE/ws" "$CACHE/install" --parallel-workers "$JOBS" \
  --packages-up-to naoqi_driver --packages-skip naoqi_driver
done_step

step "6/8 colcon: naoqi_driver (-j$JOBS, nice 19, Release)"
MAKEFLAGS=-j"$JOBS" colcon_build "$CACHE/ws" "$CACHE/install" --packages-select naoqi_driver
done_step

step "7/8 relays (../real-driver/relay/*.cpp: ALVideoDevice and ALAudioDevice as NAOqi answers)"
mkdir -p "$CACHE/install/bin"
for relay in video_relay audio_relay; do
  nice -n 19 g++ -O1 -DBOOST_BIND_GLOBAL_PLACEHOLDERS -include boost/bind.hpp \
    -I"$CACHE/install/include" "$ROOT/tools/real-driver/relay/$relay.cpp" -o "$CACHE/install/bin/$relay" -L"$CACHE/install/lib" -Wl,-rpath,"$CACHE/install/lib" -lqi \
    -lboost_system -lboost_thread -lboost_chrono -lboost_filesystem -lboost_program_options \
    -lboost_regex -lpthread
done
done_step

step "8/8 check the node is there"
ls -l "$CACHE/install/lib/naoqi_driver/naoqi_driver_node"
done_step
echo "[real-driver2] ready: source $CACHE/install/setup.bash"
