#!/usr/bin/env bash
# The main job without a robot: start the Pepper emulator, the NAOqi endpoint and the audio
# bridge (pepperEmulator.launch) on free ports, wait for their topics, run sensorTest in
# parallel mode over every robot sensor (the touch sensors and bumpers in a guided check that
# the emulated operator answers), then stop everything. Exit code = sensorTest's
# (2 when the emulator could not start, or broke during the run: a node of it ended, named on
# the terminal with its last words). With --move (DEMO_MOVE=0 leaves it out) the emulator
# stands still (condition:=still) and the motion check turns its head and base first, without
# asking (--yes: nobody stands next to an emulator). Extra arguments go to sensorTest, e.g.
#   tools/demo.sh --quick   or   --duration 5
# Ports: three distinct free ports below the kernel's ephemeral range (rosmaster.free_ports);
# if one is taken anyway before its server binds it (or roslaunch finds somebody else's master
# there), the launch is stopped and started again on other ports, up to DEMO_ATTEMPTS (3)
# times. Any other start-up failure is reported at once with the dead process's own words.
# DEMO_PORTS="master naoqi websocket" fixes the first attempt's ports (used by the tests).
# DEMO_NETWORK=wifi runs the emulator on a busy WiFi (network:=wifi, docs/emulator.md);
# DEMO_FAULTS="frontCamera:frozen" injects emulator faults (faults:=..., the tests).
set -uo pipefail
cd "$(dirname "$0")/.."
source tools/env.sh
export ROS_IP=127.0.0.1
unset ROS_HOSTNAME
export ROS_HOME="${ROS_HOME:-$PWD/build/ros_home}"
LOG="$ROS_HOME/demo-emulator.log"
mkdir -p "$ROS_HOME"
LAUNCH=
stop() {  # Ctrl-C to the launch; after ${1:-10} s SIGKILL to it and to every process it started
    [ -n "$LAUNCH" ] || return 0
    # roslaunch starts each node in a session of its own: remember them, or a roslaunch killed
    # while shutting down would leave them running.
    local nodes
    nodes=$(ps -o pid= --ppid "$LAUNCH" 2>/dev/null | tr '\n' ' ')
    kill -INT -- "-$LAUNCH" 2>/dev/null
    for _ in $(seq $((${1:-10} * 5))); do
        kill -0 "$LAUNCH" 2>/dev/null || { LAUNCH=; return 0; }; sleep 0.2  # it stopped its nodes
    done
    kill -KILL -- "-$LAUNCH" 2>/dev/null
    for pid in $nodes; do kill -KILL "$pid" 2>/dev/null; done
    LAUNCH=
}
trap 'stop; exit 130' INT TERM

attempts=${DEMO_ATTEMPTS:-3}
MOVE=(--move --yes); CONDITION=still
if [ "${DEMO_MOVE:-1}" = 0 ]; then MOVE=(); CONDITION=normal; fi
for attempt in $(seq "$attempts"); do
    if [ "$attempt" = 1 ] && [ -n "${DEMO_PORTS:-}" ]; then
        read -r MASTER_PORT NAOQI_PORT WS_PORT <<<"$DEMO_PORTS"
    else
        read -r MASTER_PORT NAOQI_PORT WS_PORT < <(python -c \
            'from pepper_interface_tests.rosmaster import free_ports; print(*free_ports(3))')
    fi
    export ROS_MASTER_URI="http://127.0.0.1:$MASTER_PORT"
    # one short line each (80 columns): the log's path stands alone on its own line
    echo "demo: starting the Pepper emulator, NAOqi endpoint and audio bridge"
    echo "  ports: master $MASTER_PORT, NAOqi $NAOQI_PORT, websocket $WS_PORT; log:"
    echo "  $LOG"
    setsid roslaunch -p "$MASTER_PORT" pepper_interface_tests pepperEmulator.launch \
        realsense:=true touch:=true operator:=true condition:="$CONDITION" network:="${DEMO_NETWORK:-none}" faults:="${DEMO_FAULTS:-none}" naoqi_port:="$NAOQI_PORT" ws_port:="$WS_PORT" >"$LOG" 2>&1 &
    LAUNCH=$!
    disown "$LAUNCH"  # stop() reaps it; no "Killed" line from bash
    # Prints the failure's lines and exits 3 when a port was taken (retry), 2 for anything else.
    python - "$LAUNCH" "$LOG" "$ROS_MASTER_URI" <<'PY'
import sys
from pepper_interface_tests.rosmaster import port_taken, wait_for_launch
want = ['/naoqi_driver/audio', '/naoqi_driver/camera/front/image_raw', '/camera/color/image_raw',
        '/joint_states']
state, lines = wait_for_launch(int(sys.argv[1]), sys.argv[2], sys.argv[3], want, timeout=60)
for line in lines:
    print('demo:   ' + line)
sys.exit(0 if state == 'up' else 3 if port_taken(lines) else 2)
PY
    rc=$?
    [ "$rc" = 0 ] && break
    stop 3   # it failed to start: nothing to save
    if [ "$rc" = 3 ] && [ "$attempt" -lt "$attempts" ]; then
        echo "demo: a port was taken by another program (above); starting again on other ports"
        continue
    fi
    echo "demo: the emulator did not start (the reason is above; full log: $LOG)"
    exit 2
done

# While sensorTest runs, the launch is watched (launch/watch.py): a node of the emulator that
# ends mid-run is named at once with its own last words, said again after the summary, and the
# exit code is then 2: the verdicts of the sensors it fed say nothing about a robot.
# --sensors: every sensor the emulator's robot has (its launch's head: stereo), from the
# declaration (plan/declaration.py).
python -m pepper_interface_tests.launch.watch "$LAUNCH" "$LOG" -- \
    python scripts/sensorTest --platform robot --mode parallel \
    --sensors "$(python -m pepper_interface_tests.plan.declaration stereo)" \
    --guided --no-show "${MOVE[@]}" "$@"
rc=$?
stop
exit $rc
