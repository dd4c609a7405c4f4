#!/usr/bin/env bash
# The main job without a robot: start the Pepper emulator, the NAOqi endpoint and the audio
# bridge (pepperEmulator.launch) on free ports, wait for their topics, run sensorTest in
# parallel mode over every robot sensor, then stop everything. Exit code = sensorTest's.
# Extra arguments go to sensorTest, e.g.  tools/demo.sh --quick   or   --duration 5
set -uo pipefail
cd "$(dirname "$0")/.."
source tools/env.sh
free_port() { python -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])'; }
MASTER_PORT=$(free_port); NAOQI_PORT=$(free_port); WS_PORT=$(free_port)
export ROS_MASTER_URI="http://127.0.0.1:$MASTER_PORT" ROS_IP=127.0.0.1
unset ROS_HOSTNAME
export ROS_HOME="${ROS_HOME:-$PWD/build/ros_home}"
LOG="$ROS_HOME/demo-emulator.log"
mkdir -p "$ROS_HOME"

echo "demo: starting the Pepper emulator, NAOqi endpoint and audio bridge (log: $LOG)"
setsid roslaunch -p "$MASTER_PORT" pepper_interface_tests pepperEmulator.launch \
    realsense:=true naoqi_port:="$NAOQI_PORT" ws_port:="$WS_PORT" >"$LOG" 2>&1 &
LAUNCH=$!
stop() { kill -INT -- "-$LAUNCH" 2>/dev/null; for _ in $(seq 50); do kill -0 "$LAUNCH" 2>/dev/null || return; sleep 0.2; done; kill -KILL -- "-$LAUNCH" 2>/dev/null; }
trap 'stop; exit 130' INT TERM

python - <<'PY' || { echo "demo: the emulator did not come up; see $LOG"; tail -20 "$LOG"; stop; exit 2; }
import sys, time, rosgraph
want = {'/naoqi_driver/audio', '/naoqi_driver/camera/front/image_raw', '/camera/color/image_raw', '/joint_states'}
deadline = time.time() + 60
while time.time() < deadline:
    try:
        topics = {t for t, _ in rosgraph.Master('/demo').getPublishedTopics('')}
        if want <= topics:
            sys.exit(0)
    except Exception:
        pass
    time.sleep(0.3)
sys.exit(1)
PY

python scripts/sensorTest --platform robot --mode parallel \
    --sensors backSonar,frontSonar,frontCamera,bottomCamera,depthCamera,stereoCamera,realsenseRGBCamera,realsenseDepthCamera,laser,microphone,jointState,odometry,imu,speech \
    --no-show "$@"
rc=$?
stop
exit $rc
