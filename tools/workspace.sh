#!/usr/bin/env bash
# Build a catkin workspace of this package with a venv's python (idempotent: skipped when the
# package's build files did not change since the stamp).
#   tools/workspace.sh WS VENV STAMP
# tools/setup.sh: build/ with .venv; the Noetic tier (tools/platform/noetic.sh): build/noetic/ws
# with its Python 3.8 venv. WS/src/pepper_interface_tests is a folder of links to this
# repository's top-level entries, all but build/ itself: tools that walk the package (rosrun,
# roslaunch, rostest) then never meet a workspace inside the package. Built with the venv's
# python (on PATH first, -DPYTHON_EXECUTABLE) so the scripts' devel-space relays and the message
# generators run in the venv. The build's output goes to STAMP.log, shown when it fails.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
WS=$1; VENV=$2; STAMP=$3
PKG="$WS/src/pepper_interface_tests"
[ -L "$PKG" ] && rm "$PKG"
mkdir -p "$PKG" "$(dirname "$STAMP")"
for entry in "$ROOT"/* "$ROOT"/.ci; do
  name=$(basename "$entry")
  [ "$name" = build ] && continue
  [ "$(readlink "$PKG/$name" 2>/dev/null)" = "$entry" ] || ln -sfn "$entry" "$PKG/$name"
done
for link in "$PKG"/* "$PKG"/.ci; do   # entries removed from the repository
  [ -L "$link" ] && [ ! -e "$link" ] && rm "$link"
done
build_hash=layout2-$(cat package.xml CMakeLists.txt setup.py msg/*.msg | sha1sum | cut -c1-12)$(ls scripts | sha1sum | cut -c1-6)-$("$VENV/bin/python" -c 'import sys; print("%d.%d" % sys.version_info[:2])')
if [ ! -f "$WS/devel/setup.bash" ] || [ "$(cat "$STAMP" 2>/dev/null)" != "$build_hash" ]; then
  echo "[setup] building the catkin workspace in ${WS#"$ROOT"/}/"
  ( cd "$WS" && PATH="$VENV/bin:$PATH" catkin_make -DPYTHON_EXECUTABLE="$VENV/bin/python" \
      -DCATKIN_ENABLE_TESTING=ON >"$STAMP.log" 2>&1 ) || { cat "$STAMP.log"; exit 1; }
  echo "$build_hash" > "$STAMP"
fi
