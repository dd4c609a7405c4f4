#!/usr/bin/env bash
# Print the folder of the Debian source package of an installed binary package, at the
# installed version, fetched once with `apt-get source` into the cache outside the work tree
#   ${PEPPER_PLATFORM_CACHE:-$HOME/.cache/pepper_interface_tests}/debian-src/
#   tools/platform/debian-source.sh python3-roslz4   ->  .../debian-src/ros-ros-comm-1.15.15+ds
# Used by the Noetic tier to build Debian's compiled ROS modules for another Python. When apt
# has no deb-src entry, one is added for the same archive and suites as the deb entries
# (/etc/apt/sources.list.d/pepper-interface-tests-src.sources) and apt's lists are updated.
set -euo pipefail
binary="${1:?usage: tools/platform/debian-source.sh BINARY_PACKAGE}"
cache="${PEPPER_PLATFORM_CACHE:-$HOME/.cache/pepper_interface_tests}/debian-src"
read -r source version < <(dpkg-query -W -f='${source:Package} ${source:Version}\n' "$binary")
upstream="${version#*:}"; upstream="${upstream%-*}"
dir="$cache/$source-$upstream"
mkdir -p "$cache"
exec 9>"$cache/.lock"; flock 9
if [ ! -f "$dir/.fetched" ]; then
  SUDO=""; [ "$(id -u)" = 0 ] || SUDO="sudo"
  if ! apt-get source --print-uris -qq "$source=$version" >/dev/null 2>&1; then
    list=/etc/apt/sources.list.d/pepper-interface-tests-src.sources
    echo "[source] adding deb-src entries to apt ($list) to fetch $source" >&2
    if ls /etc/apt/sources.list.d/*.sources >/dev/null 2>&1; then
      sed 's/^Types: deb$/Types: deb-src/' /etc/apt/sources.list.d/*.sources | grep -v '^#' \
        | $SUDO tee "$list" >/dev/null
    else
      grep -h '^deb ' /etc/apt/sources.list /etc/apt/sources.list.d/*.list 2>/dev/null \
        | sed 's/^deb /deb-src /' | $SUDO tee "${list%.sources}.list" >/dev/null
    fi
    $SUDO apt-get update -qq >&2
  fi
  echo "[source] fetching Debian's $source $version into $cache" >&2
  rm -rf "$dir"
  (cd "$cache" && apt-get source -qq "$source=$version" >/dev/null 2>&1) \
    || { echo "[source] apt-get source $source=$version failed" >&2; exit 1; }
  touch "$dir/.fetched"
fi
echo "$dir"
