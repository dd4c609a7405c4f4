#!/usr/bin/env bash
# Print the path of a CPython 2.7.12 interpreter with websocket-client 0.59.0, building it when
# it is not there yet: the Python line of NAOqi 2.5 on Pepper, on which the audio bridge's
# capture side (scripts/naoqiAudio) runs on the robot. test/audio_bridge/test_capture_py27.py
# runs that side on it. Usage:
#   tools/platform/python27.sh               ->  /path/to/python2.7 (built first if need be)
#   tools/platform/python27.sh --installed   ->  the path if it is ready, else exit 3 (no build)
#
# CPython is built from Python-2.7.12.tar.xz (looked for in $PEPPER_PYTHON_SOURCES, default
# ../shared/python next to the checkout) with `./configure --prefix=P && make && make install`
# into the cache outside the work tree
#   P = ${PEPPER_PLATFORM_CACHE:-$HOME/.cache/pepper_interface_tests}/python2.7.12
# and stamped (P/.built) when `make install` finished; the wheels below are stamped apart
# (P/.wheels holds their list), so a second run only checks the two stamps and the imports.
# 2.7.12 builds no `ssl` module against Debian 12's OpenSSL 3, so it has no pip of its own
# (ensurepip needs ssl): this checkout's .venv pip downloads pure-Python wheels for 2.7
# (`pip download --python-version 2.7 --only-binary=:all: --no-deps`) and they are unpacked
# into P's site-packages (a pure wheel is its files at the site-packages root). Build log:
# P.log. Progress goes to stderr, only the path to stdout. Two runs at once wait for each other.
set -euo pipefail
version=2.7.12
# websocket-client 0.59.0 is the last release for Python 2.7 (1.x is Python 3 only); it
# imports six (its setup.py install_requires).
wheels="websocket-client==0.59.0 six==1.16.0"
here="$(cd "$(dirname "$0")/../.." && pwd)"
cache="${PEPPER_PLATFORM_CACHE:-$HOME/.cache/pepper_interface_tests}"
prefix="$cache/python$version"
python="$prefix/bin/python2.7"
say() { echo "[python27] $*" >&2; }

if [ "${1:-}" = "--installed" ]; then
  if [ -f "$prefix/.built" ] && [ "$(cat "$prefix/.wheels" 2>/dev/null)" = "$wheels" ]; then
    echo "$python"; exit 0
  fi
  say "no CPython $version in $prefix yet; fix: tools/setup.sh --test (or $0) builds it from" \
    "Python-$version.tar.xz in \$PEPPER_PYTHON_SOURCES (default: ../shared/python)"
  exit 3
fi

mkdir -p "$cache"
exec 9>"$prefix.lock"
flock 9

if [ ! -f "$prefix/.built" ]; then
  sources="${PEPPER_PYTHON_SOURCES:-$(dirname "$here")/shared/python}"
  tarball="$sources/Python-$version.tar.xz"
  [ -f "$tarball" ] || { say "no $tarball to build CPython $version from (set" \
    "PEPPER_PYTHON_SOURCES to the folder holding Python-$version.tar.xz)"; exit 2; }
  say "building CPython $version into $prefix (a few minutes; log: $prefix.log)"
  work="$(mktemp -d "$cache/build-$version.XXXXXX")"
  trap 'rm -rf "$work"' EXIT
  rm -rf "$prefix"
  if ! (tar -xJf "$tarball" -C "$work" && cd "$work/Python-$version" \
        && ./configure --prefix="$prefix" --without-ensurepip && make -j2 && make install) \
        >"$prefix.log" 2>&1; then
    say "building CPython $version failed; last lines of $prefix.log:"
    tail -20 "$prefix.log" >&2; exit 1
  fi
  touch "$prefix/.built"
fi

if [ "$(cat "$prefix/.wheels" 2>/dev/null)" != "$wheels" ]; then
  pip_python="$here/.venv/bin/python"
  [ -x "$pip_python" ] || pip_python=python3
  site="$("$python" -c 'import distutils.sysconfig as s; print(s.get_python_lib())')"
  download="$cache/wheels-py27"
  say "installing $wheels into $site"
  # shellcheck disable=SC2086  # the list is words on purpose
  "$pip_python" -m pip download -q --disable-pip-version-check --dest "$download" \
    --python-version 2.7 --only-binary=:all: --no-deps $wheels >&2
  for spec in $wheels; do
    name="${spec%%==*}"; name="${name//-/_}"
    whl="$(ls "$download/$name-${spec##*==}-"*.whl)"
    "$pip_python" -m zipfile -e "$whl" "$site"
  done
  rm -rf "$site"/*.data    # scripts (wsdump.py) the capture side does not use
  echo "$wheels" > "$prefix/.wheels"
fi

"$python" -c 'import websocket, six, struct, zlib' \
  || { say "$python cannot import its packages; delete $prefix and run again"; exit 1; }
echo "$python"
