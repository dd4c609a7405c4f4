#!/usr/bin/env bash
# sensorTest live on ROS 2 against the real ros-naoqi/naoqi_driver2 (built by build.sh) and the
# fake NAOqi, compared with sensorTest on ROS 1 against the real naoqi_driver of the same world
# (its golden recordings, test/fixtures/real-driver/, judged with --bag). Not part of `make
# test` (test/ros2/test_real_driver2_ros2.py runs it with PEPPER_REAL_DRIVER2_LIVE=1); needs root
# (unshare -n).
#
#   tools/real-driver2/live.sh                    # both heads: stereo (with --move), xtion
#   tools/real-driver2/live.sh xtion
#   tools/real-driver2/live.sh --signal INT       # Ctrl-C during the --move base turn (or TERM)
#   tools/real-driver2/live.sh launch             # the stereo head through the package's launch:
#       sensorTestLaunchRobot.launch.py run_test:=true move:=true, which includes the driver's
#
# Each run has a network namespace of its own (unshare -n, loopback only): the fake NAOqi on
# port 9559 (as on a robot), video_relay and audio_relay (tools/real-driver/relay), the driver
# with the parameters a user gives it (docs/ros2.md), and sensorTest as a user starts it (`ros2
# run`, the ROS 2 workspace of tools/ros2/workspace.sh), every sensor of the fake's world. The
# outputs, the logs of every process and each exit code go to $LIVE_OUT/<run>/ (default
# build/real-driver2-live); the comparison is printed by compare_live.py (exit 1: a difference).
set -euo pipefail
HERE="$(cd "$(dirname "$0")" && pwd)"
REPO="$(cd "$HERE/../.." && pwd)"
CACHE="${PEPPER_REAL_DRIVER2_CACHE:-/var/cache/pepper-real-driver2}"
OUT="${LIVE_OUT:-$REPO/build/real-driver2-live}"
DURATION="${LIVE_DURATION:-10}"
GOLDEN1="$REPO/test/fixtures/real-driver"
# the driver's parameters (src/external_registration.cpp:63-76 at 2.1.2): the robot's address,
# and qi_listen_url, where NAOqi calls the driver's audio module back (:111-113)
DRIVER_ARGS="--ros-args -p nao_ip:=127.0.0.1 -p nao_port:=9559 -p network_interface:=lo -p qi_listen_url:=tcp://127.0.0.1:0"
# LIVE_DRIVER: another way to start it, in its environment (docs/ros2.md: its launch file, the
# default qi_listen_url, a namespace)
DRIVER="${LIVE_DRIVER:-$CACHE/install/lib/naoqi_driver/naoqi_driver_node $DRIVER_ARGS}"
# LIVE_NICE (default -5): the niceness of the robot's side (the fake NAOqi, the relays, the driver),
# which on a robot has a CPU of its own, ahead of the PC's other work (sensorTest stays at 0);
# a starved driver stamps /tf late and samples the gyro unevenly (tf and imu FAIL, rightly)
ROBOT_NICE="nice -n ${LIVE_NICE:--5}"

die() { echo "live: $*" >&2; exit 2; }
[ -x "$CACHE/install/lib/naoqi_driver/naoqi_driver_node" ] || \
  die "no naoqi_driver2 in $CACHE (build it: tools/real-driver2/build.sh, README.md there)"
[ "$(id -u)" = 0 ] || die "needs root for unshare -n (a network namespace per run: port 9559, DDS)"
command -v unshare >/dev/null || die "no unshare (util-linux)"
# sensorTest's ROS 2 workspace: the tier's when run from it, else built (idempotent)
if [ -n "${PEPPER_ROS2_PREFIX:-}" ]; then WS="$PEPPER_ROS2_PREFIX/setup.bash"
else WS="$("$REPO/tools/ros2/workspace.sh")" || die "the ROS 2 workspace did not build (tools/ros2/workspace.sh)"; fi

sensors_of() {   # head: every sensor of the fake's world (no RealSense: not a Pepper head)
  PYTHONPATH="$REPO/src" "$REPO/.venv/bin/python" -c "
from pepper_interface_tests.plan import declaration as d
print(','.join(n for n in d.SENSORS if n != 'motion' and n not in d.sensors_of(camera='realsense')))"
}

wait_for() {     # file words tenths
  for _ in $(seq "$3"); do grep -q "$2" "$1" 2>/dev/null && return 0; sleep 0.1; done
  return 1
}

run_sensor_test() {   # dir signal sensorTest-args...: sensorTest's exit code
  local dir="$1" sig="$2" t0=$SECONDS rc=0; shift 2
  # sensorTest as a user starts it, in a process group of its own (Ctrl-C signals the group);
  # or the launch that starts the driver (its package next: its naoqi_bridge_msgs, not the
  # workspace's generated one, for the driver's libraries)
  local run="ros2 run pepper_interface_tests sensorTest --output-dir '$dir/out' --no-history --no-show --no-record $*"
  [ -z "${LIVE_LAUNCH:-}" ] || run="source $CACHE/install/local_setup.bash; ros2 launch pepper_interface_tests \
    sensorTestLaunchRobot.launch.py robot_ip:=127.0.0.1 network_interface:=lo run_test:=true output_dir:='$dir/out' $*"
  setsid bash -c "set +u; source '$WS'; export PATH='$REPO/.venv/bin':\$PATH; cd '$dir'; $run" \
    </dev/null >"$dir/sensorTest.log" 2>&1 &
  local st=$!
  if [ -n "$sig" ]; then
    # mid base turn: the fake's ALMotion got the turn (moveTo), as Ctrl-C / `kill PID` would
    if wait_for "$dir/fake.log" 'ALMotion.moveTo' 1200; then
      sleep 0.3
      if [ "$sig" = INT ]; then kill -INT -- "-$st"
      else kill -TERM "$(cat "/proc/$st/task/$st/children")"; fi   # the program `ros2 run` started
      echo "SIG$sig sent $((SECONDS - t0)) s into the run" >>"$dir/times.txt"
    else echo "live: the base turn never reached the fake's ALMotion" >&2; fi
  fi
  wait "$st" || rc=$?
  echo "sensorTest took $((SECONDS - t0)) s, exit $rc" >>"$dir/times.txt"
  return $rc
}

run_one() {      # dir head signal sensorTest-args... (inside the namespace)
  local dir="$1" head="$2" sig="$3"; shift 3
  ip link set lo up
  export RMW_IMPLEMENTATION=rmw_cyclonedds_cpp ROS_LOCALHOST_ONLY=1 ROS_DOMAIN_ID=0
  export ROS_HOME="$dir/ros_home"
  mkdir -p "$ROS_HOME"
  local drv="source $CACHE/install/setup.bash"
  PYTHONPATH="$REPO/src" $ROBOT_NICE "$REPO/.venv/bin/python" "$REPO/scripts/pepperFakeNaoqi" --port 9559 \
    --video-relay --audio-relay --head "$head" >"$dir/fake.log" 2>&1 &
  local fake=$!
  wait_for "$dir/fake.log" 'fake NAOqi ready' 200 || { echo "live: the fake NAOqi did not start" >&2; return 1; }
  bash -c "set +u; $drv; exec $ROBOT_NICE $CACHE/install/bin/video_relay tcp://127.0.0.1:9559" >"$dir/video_relay.log" 2>&1 &
  local vrelay=$!
  bash -c "set +u; $drv; exec $ROBOT_NICE $CACHE/install/bin/audio_relay tcp://127.0.0.1:9559" >"$dir/audio_relay.log" 2>&1 &
  local arelay=$!
  wait_for "$dir/video_relay.log" 'video relay ready' 200 && wait_for "$dir/audio_relay.log" 'audio relay ready' 200 \
    || { echo "live: a relay did not start" >&2; return 1; }
  local t0=$SECONDS rc=0 driver
  if [ -n "${LIVE_LAUNCH:-}" ]; then     # the launch starts the driver
    run_sensor_test "$dir" "$sig" "$@" || rc=$?
    echo "$rc" >"$dir/sensorTest.rc"
    echo "in the launch's log" >"$dir/driver.rc"
    kill -INT "$vrelay" "$arelay" "$fake" 2>/dev/null || true
    sleep 1
    kill -KILL "$vrelay" "$arelay" "$fake" 2>/dev/null || true
    wait 2>/dev/null || true
    return 0
  fi
  bash -c "set +u; $drv; exec $ROBOT_NICE $DRIVER" >"$dir/driver.log" 2>&1 &
  driver=$!
  for _ in $(seq 400); do   # up, or ended (it aborts on a qi_listen_url it cannot listen on)
    grep -q 'Starting ROS loop' "$dir/driver.log" && break
    kill -0 "$driver" 2>/dev/null || break
    sleep 0.1
  done
  if ! grep -q 'Starting ROS loop' "$dir/driver.log" || ! kill -0 "$driver" 2>/dev/null; then
    echo "live: the driver did not start (no sensorTest run): $dir/driver.log" >&2
    tail -3 "$dir/driver.log" >&2
    rc=2
  else
    echo "driver up in $((SECONDS - t0)) s" >"$dir/times.txt"
    run_sensor_test "$dir" "$sig" "$@" || rc=$?
  fi
  echo "$rc" >"$dir/sensorTest.rc"
  sleep 0.5      # a command still in flight reaches the fake
  # the driver first (it aborts if NAOqi goes first): SIGINT as Ctrl-C, then SIGTERM, then
  # SIGKILL, 5 s apart, as `ros2 launch` escalates: 2.1.2 ends in a SIGSEGV on SIGINT, or at
  # times hangs in its shutdown and ignores SIGTERM too (rclcpp logs it, the node goes on)
  local how=SIGINT s
  for s in TERM KILL; do
    kill "-$([ "$how" = SIGINT ] && echo INT || echo "${how#SIG}")" "$driver" 2>/dev/null || true
    for _ in $(seq 50); do kill -0 "$driver" 2>/dev/null || break; sleep 0.1; done
    kill -0 "$driver" 2>/dev/null || break
    how="SIG$s"
  done
  [ "$how" != SIGKILL ] || kill -KILL "$driver" 2>/dev/null || true
  local drc=0
  wait "$driver" || drc=$?
  echo "$drc (ended by $how)" >"$dir/driver.rc"
  kill -INT "$vrelay" "$arelay" "$fake" 2>/dev/null || true
  sleep 1
  kill -KILL "$vrelay" "$arelay" "$fake" 2>/dev/null || true
  wait 2>/dev/null || true
}
export -f run_one run_sensor_test wait_for
export REPO CACHE DRIVER WS LIVE_LAUNCH ROBOT_NICE

live() {         # name head signal sensorTest-args...
  local dir="$OUT/$1"
  rm -rf "$dir"; mkdir -p "$dir"
  unshare -n bash -c 'run_one "$@"' run_one "$dir" "${@:2}"
  cat "$dir/times.txt" 2>/dev/null || true
  [ -f "$dir/out/sensorTestResults.json" ]     # sensorTest ran
}

ros1_reference() {   # dir bags...: sensorTest --bag on ROS 1 (tools/env.sh), one output per bag
  local dir="$1"; shift
  local bag
  for bag in "$@"; do
    env -i HOME="$HOME" PATH=/usr/sbin:/usr/bin:/sbin:/bin ROS_MASTER_URI=http://127.0.0.1:1 bash -c \
      "source '$REPO/tools/env.sh' && python '$REPO/scripts/sensorTest' --bag '$GOLDEN1/$bag.bag' --platform robot \
       --sensors '$(sensors_of)' --output-dir '$dir/ros1-$bag' --no-history --no-report" \
      >"$dir/ros1-$bag.log" 2>&1 || true
  done
}

if [ "${1:-}" = --signal ]; then
  sig="${2:-INT}"
  [ "$sig" = INT ] || [ "$sig" = TERM ] || die "--signal INT or TERM, not $sig"
  # a quick plan: the head not moved, the turn as shipped; the witnesses given 4 s (DDS discovery)
  expect="$OUT/expect-signal.yaml"
  mkdir -p "$OUT"
  "$REPO/.venv/bin/python" - "$REPO/config/sensorExpectations.yaml" "$expect" <<'PY'
import sys
text = open(sys.argv[1]).read()
start, end = text.index('  motion:\n'), text.index('\n  tf:\n')
block = '  motion:\n    head_yaw: 0.0\n    head_speed: 0.1\n    base_turn: 0.5\n    step_timeout: 8.0\n    witness_wait: 4.0'
open(sys.argv[2], 'w').write(text[:start] + block + text[end:])
PY
  live "signal-$sig" stereo "$sig" --move --yes --mode parallel --duration 1 --wait 8 --no-report \
    --no-diagnostics --sensors jointState,odometry,imu,laser --expectations "$expect"
  echo "sensorTest exit: $(cat "$OUT/signal-$sig/sensorTest.rc"); the driver's exit: $(cat "$OUT/signal-$sig/driver.rc")"
  echo "what the fake's ALMotion received, in order:"
  grep -o 'ALMotion\.[a-zA-Z]*(.*)' "$OUT/signal-$sig/fake.log" || true
  exit 0
fi

heads=("$@")
[ ${#heads[@]} -gt 0 ] || heads=(stereo xtion)
rc=0
for head in "${heads[@]}"; do
  case "$head" in stereo|xtion|launch) ;; *) die "a head is stereo or xtion (or launch), not $head" ;; esac
  echo "[live] $(date -u +%H:%M:%S) $head: sensorTest on ROS 2 against naoqi_driver2"
  move=(--move --yes)     # the ROS 1 move recording is of the stereo head
  args=(--mode parallel --duration "$DURATION")
  [ "$head" != launch ] || { move=(move:=true); args=(mode:=parallel duration:="$DURATION"); }
  [ "$head" != xtion ] || move=()
  if ! LIVE_LAUNCH="$([ "$head" != launch ] || echo 1)" live "$head" "${head/launch/stereo}" "" "${args[@]}" \
     "${move[@]}" $([ "$head" = launch ] || echo --sensors "$(sensors_of)"); then
    echo "[live] $head: no results (the logs: $OUT/$head/)"; rc=1; continue
  fi
  echo "sensorTest exit: $(cat "$OUT/$head/sensorTest.rc"); the driver's exit: $(cat "$OUT/$head/driver.rc")"
  bags=("healthy_${head/launch/stereo}" audio)
  [ "$head" = xtion ] || bags+=(move)
  ros1_reference "$OUT/$head" "${bags[@]}"
  refs=()
  for bag in "${bags[@]}"; do refs+=("$bag=$OUT/$head/ros1-$bag/sensorTestResults.json"); done
  "$REPO/.venv/bin/python" "$HERE/compare_live.py" "$OUT/$head/out/sensorTestResults.json" "${refs[@]}" || rc=1
done
exit $rc
