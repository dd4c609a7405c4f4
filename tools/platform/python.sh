#!/usr/bin/env bash
# Print the path of a CPython VERSION (X.Y.Z) interpreter, building it when the machine has none.
#   tools/platform/python.sh 3.8.16   ->  /path/to/python3.8
# The machine's own pythonX.Y is used when it runs and reports X.Y (Ubuntu 20.04's python3.8);
# a wrapper that does not run (a pyenv shim without that version selected) is not. Otherwise
# CPython is built from Python-VERSION.tar.xz (looked for in $PEPPER_PYTHON_SOURCES, default
# ../shared/python next to the checkout) into the cache
#   ${PEPPER_PLATFORM_CACHE:-$HOME/.cache/pepper_interface_tests}/pythonVERSION
# outside the work tree, stamped when `make install` finished, so a second run reuses it.
# Build log: <cache>/pythonVERSION.log. Progress goes to stderr; only the path goes to stdout.
set -euo pipefail
version="${1:?usage: tools/platform/python.sh X.Y.Z}"
short="${version%.*}"
here="$(cd "$(dirname "$0")/../.." && pwd)"
cache="${PEPPER_PLATFORM_CACHE:-$HOME/.cache/pepper_interface_tests}"
prefix="$cache/python$version"

# the machine's own interpreter, if it really is one of that line
if own="$(command -v "python$short" 2>/dev/null)"; then
  if got="$("$own" -c 'import sys; print("%d.%d" % sys.version_info[:2])' 2>/dev/null)" \
      && [ "$got" = "$short" ]; then
    echo "$own"; exit 0
  fi
  echo "[python] $own does not run a Python $short (a shim?): not used" >&2
fi

mkdir -p "$cache"
exec 9>"$prefix.lock"   # one build at a time; a second caller waits for it and reuses it
flock 9
if [ ! -f "$prefix/.built" ]; then
  sources="${PEPPER_PYTHON_SOURCES:-$(dirname "$here")/shared/python}"
  tarball="$sources/Python-$version.tar.xz"
  [ -f "$tarball" ] || { echo "[python] no python$short on PATH and no $tarball to build it from" \
    "(set PEPPER_PYTHON_SOURCES to the folder holding Python-$version.tar.xz)" >&2; exit 2; }
  echo "[python] building CPython $version into $prefix (a few minutes; log: $prefix.log)" >&2
  work="$(mktemp -d "$cache/build-$version.XXXXXX")"
  trap 'rm -rf "$work"' EXIT
  rm -rf "$prefix"
  if ! (tar -xJf "$tarball" -C "$work" && cd "$work/Python-$version" \
        && ./configure --prefix="$prefix" && make -j"$(nproc)" && make install) \
        >"$prefix.log" 2>&1; then
    echo "[python] building CPython $version failed; last lines of $prefix.log:" >&2
    tail -20 "$prefix.log" >&2; exit 1
  fi
  touch "$prefix/.built"
fi
echo "$prefix/bin/python$short"
