#!/usr/bin/env bash
# Build the real ros-naoqi/naoqi_driver (ROS 1) with Debian 12's ROS packages,
# into a cache outside the repository. Not part of `make test`.
#
#   tools/real-driver/build.sh            # clone from GitHub, build
#   NAOQI_SOURCES=/work/.mirror tools/real-driver/build.sh
#
# NAOQI_SOURCES names a directory holding local copies: either <name>/ (a
# clone) or ros-naoqi+<name>/repo (a bare git dir) for each of libqi,
# libqicore, naoqi_bridge_msgs, naoqi_driver.
# PEPPER_REAL_DRIVER_CACHE (default /var/cache/pepper-real-driver) is where
# the sources, the build and the install go. JOBS (default 2) parallel jobs,
# run under `nice -n 19` (the machine is shared). SKIP_APT=1 skips apt-get.
# Every step prints its wall time; the whole log goes to $CACHE/build.log.
set -euo pipefail
HERE="$(cd "$(dirname "$0")" && pwd)"
CACHE="${PEPPER_REAL_DRIVER_CACHE:-/var/cache/pepper-real-driver}"
JOBS="${JOBS:-2}"
mkdir -p "$CACHE"
exec > >(tee -a "$CACHE/build.log") 2>&1

# name  branch  repository
SOURCES=(
  "libqi ros https://github.com/ros-naoqi/libqi.git"
  "libqicore ros https://github.com/ros-naoqi/libqicore.git"
  "naoqi_bridge_msgs master https://github.com/ros-naoqi/naoqi_bridge_msgs.git"
  "naoqi_driver master https://github.com/ros-naoqi/naoqi_driver.git"
)

step_start=0
step() { step_start=$(date +%s); echo "[real-driver] $(date -u +%H:%M:%S) step: $*"; }
done_step() { echo "[real-driver] $(date -u +%H:%M:%S) done in $(( $(date +%s) - step_start )) s"; }

step "1/5 Debian packages (debian-packages.txt)"
if [ "${SKIP_APT:-0}" != 1 ]; then
  mapfile -t pkgs < <(grep -v '^\s*#' "$HERE/debian-packages.txt" | grep -v '^\s*$')
  missing=()
  for p in "${pkgs[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'ok installed' || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    SUDO=""; [ "$(id -u)" = 0 ] || SUDO=sudo
    $SUDO apt-get install -y --no-install-recommends "${missing[@]}"
  fi
fi
done_step

step "2/5 sources into $CACHE/ws/src (patched)"
mkdir -p "$CACHE/ws/src"
: > "$CACHE/sources.txt"
for entry in "${SOURCES[@]}"; do
  read -r name branch url <<<"$entry"
  dest="$CACHE/ws/src/$name"
  if [ ! -d "$dest/.git" ]; then
    src="$url"
    if [ -n "${NAOQI_SOURCES:-}" ]; then
      if [ -d "$NAOQI_SOURCES/ros-naoqi+$name/repo" ]; then src="$NAOQI_SOURCES/ros-naoqi+$name/repo"
      elif [ -d "$NAOQI_SOURCES/$name" ]; then src="$NAOQI_SOURCES/$name"
      else echo "[real-driver] $name not found under NAOQI_SOURCES=$NAOQI_SOURCES" >&2; exit 2; fi
    fi
    git clone -q --branch "$branch" "$src" "$dest"
    for patch in "$HERE"/patches/"$name"-*.patch; do
      [ -e "$patch" ] || continue
      echo "[real-driver] applying $(basename "$patch")"
      git -C "$dest" apply "$patch"
    done
  fi
  echo "$name $branch $(git -C "$dest" rev-parse HEAD)" | tee -a "$CACHE/sources.txt"
done
done_step

step "3/5 catkin_make_isolated (-j$JOBS, nice 19, Release): libqi alone takes ~30 min on 2 cores"
cd "$CACHE/ws"
# Debian's catkin runs its helpers with the python that owns catkin_pkg: the
# system one, whatever python3 comes first on PATH (pyenv, a venv).
export PATH="/usr/bin:$PATH"
nice -n 19 catkin_make_isolated --install \
  --install-space "$CACHE/install" \
  -DCMAKE_BUILD_TYPE=Release -DCATKIN_ENABLE_TESTING=OFF -DBUILD_TESTING=OFF \
  -DQI_WITH_TESTS=OFF -DPYTHON_EXECUTABLE=/usr/bin/python3 \
  -j"$JOBS"
done_step

step "4/5 relays (relay/*.cpp: ALVideoDevice and ALAudioDevice as NAOqi answers them)"
mkdir -p "$CACHE/install/bin"
for relay in video_relay audio_relay; do
  nice -n 19 g++ -O1 -std=gnu++11 -DBOOST_BIND_GLOBAL_PLACEHOLDERS -include boost/bind.hpp \
    -I"$CACHE/install/include" "$HERE/relay/$relay.cpp" -o "$CACHE/install/bin/$relay" \
    -L"$CACHE/install/lib" -Wl,-rpath,"$CACHE/install/lib" -lqi -lboost_system -lboost_thread \
    -lboost_chrono -lboost_filesystem -lboost_program_options -lboost_regex -lpthread
done
done_step

step "5/5 check the node runs"
set +u      # ROS's setup scripts read unset variables
# shellcheck disable=SC1091
source "$CACHE/install/setup.bash"
set -u
ls -l "$CACHE/install/lib/naoqi_driver/naoqi_driver_node"
done_step
echo "[real-driver] ready: source $CACHE/install/setup.bash"
