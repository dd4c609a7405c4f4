#!/usr/bin/env bash
# The minimum Python versions, checked by vermin on the source (library calls, syntax and
# evaluated annotations that ruff's target-version does not see): run by tools/gates.sh.
#   tools/vermin.sh              the whole project: the package, its scripts, tools/benchmark and
#                                the tests on Python 3.8 (Ubuntu 20.04's, ROS Noetic's; the Noetic
#                                tier runs them there); the capture side
#                                (audio_bridge/capture.py, the two modules it imports,
#                                scripts/naoqiAudio), which runs on the robot under NAOqi's
#                                Python 2.7, on 2.7 and 3.7
#   tools/vermin.sh FILE...      those files on Python 3.8
# Exit 1 on a violation, with vermin's report: each file, what in it needs a newer Python, which.
set -uo pipefail
cd "$(dirname "$0")/.."
vermin=.venv/bin/vermin
PY3=(-t=3.8- --no-tips --violations --eval-annotations --no-config-file --quiet -v)
PY27=(-t=2.7- -t=3.7- --no-tips --violations --no-config-file --quiet -v)
if [ $# -gt 0 ]; then exec "$vermin" "${PY3[@]}" "$@"; fi
capture=(src/pepper_interface_tests/audio_bridge/capture.py src/pepper_interface_tests/audio_bridge/frame.py
         src/pepper_interface_tests/audio_bridge/__init__.py scripts/naoqiAudio)
mapfile -t rest < <( { find src tools/benchmark test -name '*.py'; ls -d scripts/*; } | sort \
  | grep -vxF -f <(printf '%s\n' "${capture[@]}"))
rc=0
"$vermin" "${PY3[@]}" "${rest[@]}" || rc=1
"$vermin" "${PY27[@]}" "${capture[@]}" || rc=1
exit $rc
