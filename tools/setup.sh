#!/usr/bin/env bash
# Idempotent set-up: Debian packages, the venv, the catkin workspace.
# Usage: tools/setup.sh [--test]   (--test also installs what the test suite needs: chromium,
#                                    the Noetic tier's compilers and headers, and builds
#                                    CPython 2.7.12 for the capture side's test)
# Each step is skipped when already done, so a second run takes a few seconds.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
WS="$ROOT/build"
STAMPS="$ROOT/.stamps"
mkdir -p "$STAMPS"
say() { printf '[setup] %s\n' "$*"; }

# 1. Debian packages (ROS 1 from Debian's own archive).
pkgs=$(grep -v '^#' tools/debian-packages.txt | xargs)
# --test: chromium for the report test; for the Noetic tier's roslz4 and tf2_py extensions
# (tools/platform/noetic.sh): g++, liblz4-dev, libtf2-dev, and curl and xz-utils to fetch a
# source tarball the archive serves only in a later suite (tools/platform/debian-source.sh)
if [ "${1:-}" = "--test" ]; then pkgs="$pkgs chromium g++ liblz4-dev libtf2-dev curl xz-utils"; fi
missing=""
for p in $pkgs; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
  SUDO=""; [ "$(id -u)" = 0 ] || SUDO="sudo"
  say "installing Debian packages:$missing"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends $missing >/dev/null
fi

# 2. The venv on Debian's python3 (the ROS modules live there).
req_hash=$(sha1sum tools/requirements.txt | cut -c1-12)
if [ ! -x .venv/bin/python ] || [ "$(cat "$STAMPS/venv" 2>/dev/null)" != "$req_hash" ]; then
  say "creating .venv and installing tools/requirements.txt"
  [ -x .venv/bin/python ] || /usr/bin/python3 -m venv --system-site-packages .venv
  .venv/bin/python -m pip install -q --disable-pip-version-check -r tools/requirements.txt 2>&1 | { grep -v "is ignored: it is neither" || true; }
  echo "$req_hash" > "$STAMPS/venv"
fi

# 3. The catkin workspace in build/, built with the venv's python (tools/workspace.sh).
tools/workspace.sh "$WS" "$ROOT/.venv" "$STAMPS/build"

# 4. --test: CPython 2.7.12 with websocket-client 0.59, the Python of NAOqi on the robot, for the
#    test that runs the audio bridge's capture side on it (test/audio_bridge/test_capture_py27.py).
#    Built once (a few minutes) into a cache outside the work tree, shared by every checkout of
#    this machine; a second run only checks its stamps (tools/platform/python27.sh).
#    Without it (no CPython source, a failed build: said above) that test is skipped, NOT RUN with
#    the reason and the fix (on CI, CI=true, it fails instead).
if [ "${1:-}" = "--test" ]; then
  tools/platform/python27.sh >/dev/null || say "no Python 2.7 for test_capture_py27.py (see above)"
fi
say "ready (source tools/env.sh to use the package in a shell)"
