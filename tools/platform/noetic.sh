#!/usr/bin/env bash
# Set up the Noetic tier's runtime on this (Debian) machine, in build/noetic/ (idempotent; a
# second run takes seconds): what a Noetic user's Ubuntu 20.04 runs the package on.
#   1. Python 3.8: the machine's own python3.8, else CPython 3.8.16 built once into a cache
#      outside the work tree (tools/platform/python.sh);
#   2. build/noetic/venv: a venv of it with focal's library versions
#      (tools/platform/focal-requirements.txt);
#   3. Debian's ROS 1 Python libraries (rospy, rosbag, roslaunch, genpy, the message modules,
#      catkin_pkg, rospkg, cv_bridge, diagnostic_updater, ...: every installed Debian package
#      whose homepage is ROS's) made importable from it: build/noetic/ros1 is a folder of links
#      to their top-level entries in /usr/lib/python3/dist-packages, on the venv's path by a
#      .pth file. Nothing else of Debian's dist-packages is visible (its numpy, matplotlib, ...
#      are compiled for Debian's 3.11 and newer than focal's), and the compiled modules inside
#      those packages are built for 3.11, which 3.8 does not load: roslz4's (rosbag's LZ4) is
#      built here for 3.8 from Debian's source (tools/platform/debian-source.sh) against
#      Debian's libroslz4; cv_bridge converts without its boost module (sensorTest reads images
#      without it); tf2_py (tf2_ros's core) is built the same way against Debian's libtf2;
#   4. the ROS commands written in Python (roslaunch, roscore, rosmaster, rostest, rosbag,
#      rostopic, catkin_make, ...) run by the venv's python through one-line wrappers in its
#      bin/, so the master and the launcher run on 3.8 too;
#   5. build/noetic/ws: the catkin workspace built with -DPYTHON_EXECUTABLE= the venv's python
#      (tools/workspace.sh), so every node of a launch file and sensorTest run on 3.8.
# Needs what `tools/setup.sh --test` installs (liblz4-dev for roslz4's extension, g++ and
# libtf2-dev for tf2_py's).
# Use it with PEPPER_PLATFORM=noetic (tools/env.sh); tools/platform/noetic-tests.sh runs the tier.
set -euo pipefail
cd "$(dirname "$0")/../.."
ROOT=$(pwd)
TIER="$ROOT/build/noetic"
VENV="$TIER/venv"
STAMPS="$ROOT/.stamps"
REQ=tools/platform/focal-requirements.txt
DIST=/usr/lib/python3/dist-packages
say() { printf '[noetic] %s\n' "$*"; }
mkdir -p "$TIER" "$STAMPS"

# 1-2. Python 3.8 and the venv
PY=$(tools/platform/python.sh 3.8.16)
req_hash=$( (cat "$REQ"; echo "$PY") | sha1sum | cut -c1-12)
if [ ! -x "$VENV/bin/python" ] || [ "$(cat "$STAMPS/noetic-venv" 2>/dev/null)" != "$req_hash" ]; then
  say "creating build/noetic/venv on $("$PY" -V 2>&1) and installing $REQ"
  rm -rf "$VENV"
  "$PY" -m venv "$VENV"
  "$VENV/bin/python" -m pip install -q --disable-pip-version-check -r "$REQ" >"$TIER/pip.log" 2>&1 \
    || { tail -30 "$TIER/pip.log"; exit 1; }
  echo "$req_hash" > "$STAMPS/noetic-venv"
fi

# 3-4. Debian's ROS 1 Python libraries and commands
ros_packages=$(dpkg-query -W -f='${db:Status-Abbrev} ${Package} ${Homepage}\n' \
  | awk '$1 == "ii" && $3 ~ /^https?:\/\/(wiki\.ros\.org|github\.com\/ros)/ {print $2}')
rm -rf "$TIER/ros1.new"; mkdir -p "$TIER/ros1.new"
# shellcheck disable=SC2086
dpkg -L $ros_packages | sort -u | while read -r f; do
  case "$f" in
    "$DIST"/*/*) ;;                          # inside a package folder: linked with its folder
    "$DIST"/*.so) ;;                         # a compiled top-level module (3.11 only)
    "$DIST"/*) ln -s "$f" "$TIER/ros1.new/${f##*/}" ;;
    /usr/bin/*)
      if [ -f "$f" ] && head -c 64 "$f" | head -1 | grep -qE '^#! ?(/usr/bin/python3|/usr/bin/env python3)'; then
        printf '#!/bin/sh\nexec "%s" "%s" "$@"\n' "$VENV/bin/python" "$f" > "$VENV/bin/${f##*/}"
        chmod +x "$VENV/bin/${f##*/}"
      fi ;;
  esac
done
# roslz4's extension built for this Python from Debian's source of it (ros-ros-comm), against
# Debian's libroslz4, as ROS's focal package builds it for 3.8 (rosbag reads LZ4 bags with it)
suffix=$("$VENV/bin/python" -c 'import sysconfig; print(sysconfig.get_config_var("EXT_SUFFIX"))')
lz4so="$TIER/compiled/_roslz4$suffix"
if [ ! -f "$lz4so" ]; then
  src="$(tools/platform/debian-source.sh python3-roslz4)/utilities/roslz4"
  say "building roslz4's extension for $("$VENV/bin/python" -V 2>&1) from $src"
  mkdir -p "$TIER/compiled"
  gcc -shared -fPIC -O2 -I"$src/include" \
    -I"$("$VENV/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["include"])')" \
    "$src/src/_roslz4module.c" /usr/lib/x86_64-linux-gnu/libroslz4.so.1d -o "$lz4so.tmp"
  mv "$lz4so.tmp" "$lz4so"
fi
rm "$TIER/ros1.new/roslz4"
mkdir "$TIER/ros1.new/roslz4"
ln -s "$DIST/roslz4/__init__.py" "$TIER/ros1.new/roslz4/__init__.py"
ln -s "$lz4so" "$TIER/ros1.new/roslz4/"
# tf2_py's extension (tf2_ros's BufferCore, sensorTest's frame checks) the same way, against
# Debian's libtf2 and its headers (libtf2-dev); its source is Debian's ros-geometry2
tf2so="$TIER/compiled/_tf2$suffix"
if [ ! -f "$tf2so" ]; then
  src="$(tools/platform/debian-source.sh python3-tf2)/tf2_py"
  say "building tf2_py's extension for $("$VENV/bin/python" -V 2>&1) from $src"
  mkdir -p "$TIER/compiled"
  g++ -shared -fPIC -O2 -std=c++14 -I"$src/src" \
    -I"$("$VENV/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["include"])')" \
    "$src/src/tf2_py.cpp" -ltf2 -o "$tf2so.tmp"
  mv "$tf2so.tmp" "$tf2so"
fi
rm "$TIER/ros1.new/tf2_py"
mkdir "$TIER/ros1.new/tf2_py"
ln -s "$DIST/tf2_py/__init__.py" "$TIER/ros1.new/tf2_py/__init__.py"
ln -s "$tf2so" "$TIER/ros1.new/tf2_py/"
rm -rf "$TIER/ros1"; mv "$TIER/ros1.new" "$TIER/ros1"
site=$("$VENV/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
echo "$TIER/ros1" > "$site/debian-ros1.pth"

# 5. The catkin workspace. Its top-level CMakeLists.txt is catkin's toplevel.cmake, which
#    catkin_make finds relative to its python module's file: a link in build/noetic/ros1 here.
mkdir -p "$TIER/ws/src"
[ -e "$TIER/ws/src/CMakeLists.txt" ] || ln -s /usr/share/catkin/cmake/toplevel.cmake "$TIER/ws/src/CMakeLists.txt"
tools/workspace.sh "$TIER/ws" "$VENV" "$STAMPS/noetic-build"
say "ready: PEPPER_PLATFORM=noetic source tools/env.sh"
