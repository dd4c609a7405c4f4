#!/usr/bin/env bash
# Print the folder of the Debian source package of an installed binary package, at the
# installed version, fetched once with `apt-get source` into the cache outside the work tree
#   ${PEPPER_PLATFORM_CACHE:-$HOME/.cache/pepper_interface_tests}/debian-src/
#   tools/platform/debian-source.sh python3-roslz4   ->  .../debian-src/ros-ros-comm-1.15.15+ds
# Used by the Noetic tier to build Debian's compiled ROS modules for another Python. When apt
# has no deb-src entry, one is added for the same archive and suites as the deb entries
# (/etc/apt/sources.list.d/pepper-interface-tests-src.sources) and apt's lists are updated.
# When the archive no longer serves the installed version's source files, the upstream tarball
# of the same source package in trixie (else sid) is used, checked against that suite's Sources
# index (its sha256); the folder then holds that upstream tree.
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
  if ! (cd "$cache" && apt-get source -qq "$source=$version" >/dev/null 2>&1); then
    # the archive may no longer serve an old version's files (bookworm's ros-geometry2 0.7.6
    # answers 404): the same source's upstream tarball from the next suite that serves it,
    # checked against that suite's Sources index
    found=""
    for suite in trixie sid; do
      base=http://deb.debian.org/debian
      entry=$(curl -fsS -m 60 "$base/dists/$suite/main/source/Sources.xz" | xz -dc \
        | awk -v p="$source" '$0 == "Package: " p {on=1} /^$/ {on=0} on') || continue
      pool=$(printf '%s\n' "$entry" | awk '/^Directory:/ {print $2}')
      read -r sum _ orig < <(printf '%s\n' "$entry" | awk '/^Checksums-Sha256:/ {on=1; next} /^[^ ]/ {on=0} on && /orig\.tar/ {print $1, $2, $3}') || true
      [ -n "$pool" ] && [ -n "${orig:-}" ] || continue
      curl -fsS -m 120 "$base/$pool/$orig" -o "$cache/$orig" 2>/dev/null || continue
      echo "[source] $source $version is not served; using $suite's upstream tarball $orig" >&2
      echo "$sum  $cache/$orig" | sha256sum -c --quiet - >&2 || { rm -f "$cache/$orig"; continue; }
      found="$cache/$orig"; break
    done
    [ -n "$found" ] || { echo "[source] apt-get source $source=$version failed, and no later suite serves $source" >&2; exit 1; }
    mkdir -p "$dir.tmp" && tar xf "$found" -C "$dir.tmp" --strip-components=1 && mv "$dir.tmp" "$dir"
    echo "$found" > "$dir/.upstream-tarball"
  fi
  touch "$dir/.fetched"
fi
echo "$dir"
