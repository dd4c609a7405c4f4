#!/usr/bin/env bash
# The Noetic tier: the package on what a ROS Noetic user runs, Python 3.8 with Ubuntu 20.04's
# library versions (set up by tools/platform/noetic.sh in build/noetic/), every node and
# sensorTest itself on it. Run by tools/run-tests.sh after the main suite (make test, CI);
# NOETIC_TIER=0 leaves it out there. Extra arguments go to both pytest runs.
#   1. the unit tier (pytest -m unit);
#   2. the integration tests of what differs on 3.8 and focal's libraries: the demo's run
#      (every row PASS, no warning, six playable mp4 files, the WAV, the report with its plots),
#      the audio bridge both ways (websockets 8.1, libqi), recording (videos, WAV), sensorTest
#      --bag on ROS 1 bags (read in place under Noetic's rosbag: test_bag_chunks) and on ROS 2
#      recordings (refused with rosbags 0.9.23, exit 2), the
#      run history (sensorTestHistory), the report's plots (matplotlib 3.1) and template
#      (Jinja2 2.10) in a headless browser, a recording's frames placed by tf2 (tf2_py built
#      for 3.8 by tools/platform/noetic.sh).
# No Python 3.8 to run on (no python3.8 on PATH, no sources in $PEPPER_PYTHON_SOURCES): one line
# "[noetic] NOT RUN: <reason and fix>" and exit 3, which tools/run-tests.sh reports.
set -euo pipefail
cd "$(dirname "$0")/../.."
mkdir -p build
set +e
{ tools/platform/noetic.sh 2>&1; } | tee build/noetic-platform.err \
  | { grep --line-buffered -v '^\[python\] no python' >&2; true; }
trc=${PIPESTATUS[0]}
set -e
if [ $trc = 2 ] && grep -q '^\[python\] no python' build/noetic-platform.err; then
  echo "[noetic] NOT RUN: $(grep '^\[python\] no python' build/noetic-platform.err | tail -1 | sed 's/^\[python\] //')"
  exit 3
elif [ $trc != 0 ]; then
  exit 1
fi
export PEPPER_PLATFORM=noetic
source tools/env.sh
unset PYTHONDONTWRITEBYTECODE
export PYTHONPYCACHEPREFIX="$PWD/build/noetic/pycache"
export ROS_HOME="${ROS_HOME:-$PWD/build/noetic/ros_home}"
mkdir -p "$ROS_HOME"
echo "[noetic] $(python -V 2>&1), numpy $(python -c 'import numpy; print(numpy.__version__)'), websockets $(python -c 'import websockets; print(websockets.__version__)')"
start=$SECONDS
rc=0
python -m pytest -p no:cacheprovider -q -m unit "$@" || rc=1
# the demo beside the other workers: a healthy robot passes on a busy PC (issue 41)
python -m pytest -p no:cacheprovider -q -n "${PYTEST_WORKERS:-3}" --dist loadfile \
  --deselect test/audio_bridge/test_audio_bridge.py::test_chain_60s_realtime_no_lost_buffer \
  --deselect test/sources/test_bag.py::test_a_large_bag_is_streamed_not_loaded \
  --deselect test/sources/test_ros2_bags.py::test_a_large_ros2_recording_is_streamed_not_loaded \
  test/audio_bridge/test_audio_bridge.py test/emulator/test_naoqi_endpoint.py \
  test/media/test_recording.py test/sources/test_bag.py test/emulator/test_bags.py \
  test/sources/test_ros2_bags.py test/outputs/test_history.py test/outputs/report/test_page.py \
  test/sensors/test_tf_recordings.py test/sources/test_bag_chunks.py test/test_demo.py \
  "$@" || rc=1
echo "[noetic] the Noetic tier took $((SECONDS - start)) s"
exit $rc
