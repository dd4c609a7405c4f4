#!/usr/bin/env bash
# Record the golden bags: what the real ros-naoqi/naoqi_driver (built by build.sh) publishes
# against the fake NAOqi (scripts/pepperFakeNaoqi), one short bag per world, into
# test/fixtures/real-driver/ with manifest.json. Not part of `make test`; needs root (unshare).
#
#   tools/real-driver/record-golden.sh            # every variant
#   tools/real-driver/record-golden.sh healthy_xtion touch
#
# Each variant runs in its own network namespace (unshare -n, loopback only): the driver's
# roscore port is fixed to 11311 (src/external_registration.cpp: "http://"+roscore_ip+":11311"),
# and nothing there can collide with another master on this machine.
set -euo pipefail
HERE="$(cd "$(dirname "$0")" && pwd)"
REPO="$(cd "$HERE/../.." && pwd)"
CACHE="${PEPPER_REAL_DRIVER_CACHE:-/var/cache/pepper-real-driver}"
OUT="${GOLDEN_DIR:-$REPO/test/fixtures/real-driver}"
SECONDS_PER_BAG="${GOLDEN_SECONDS:-4}"
NS=/naoqi_driver
# the driver's topics this package checks (data/pepperTopics.dat); the microphone only in the
# audio variant, whose fake runs with --audio-relay: the driver's processRemote reads its buffer
# as Raw (src/event/audio.cpp:182), which a Python NAOqi cannot send as an argument (qi 3.1.5
# hands a bytes argument over as its str() text), so relay/audio_relay.cpp calls it
CAMERAS="$NS/camera/front/image_raw $NS/camera/bottom/image_raw $NS/camera/depth/image_raw $NS/camera/stereo/image_raw $NS/camera/ir/image_raw"
# /tf: the driver's tree with every joint state (src/converters/joint_state.cpp:147-201; docs/tf.md)
BODY="$NS/sonar/front $NS/sonar/back $NS/laser $NS/odom $NS/imu/base $NS/imu/torso /joint_states /tf /diagnostics"
TOUCH="$NS/head_touch $NS/hand_touch $NS/bumper"

# name | fake NAOqi arguments | topics
VARIANTS=(
  "healthy_stereo||$CAMERAS $BODY $TOUCH"
  "healthy_xtion|--head xtion|$CAMERAS $BODY $TOUCH"
  "camera_fails|--fault camera-fails|$NS/camera/front/image_raw $NS/camera/bottom/image_raw"
  "missing_key|--fault missing-key|$NS/sonar/front $NS/sonar/back"
  "stuck_laser|--fault stuck-laser|$NS/laser"
  "touch|--fault touch|$TOUCH"
  "hot_joint|--fault hot-joint|/diagnostics"
  "low_battery|--fault low-battery|/diagnostics"
  "naoqi29|--naoqi 2.9.5.172|$BODY $NS/audio"
  "audio|--audio-relay|$NS/audio"
  # the robot moves while recorded (tools/real-driver/move.py: head +0.5 rad and back, then
  # the base +0.5 rad): the motion witnesses and the head cameras at the driver's defaults
  "move||$NS/odom $NS/imu/base $NS/laser /joint_states /tf $NS/sonar/front $NS/sonar/back $NS/camera/front/image_raw $NS/camera/bottom/image_raw $NS/camera/depth/image_raw"
)
MOVE_SECONDS=10    # the move variant: its commands end ~8.5 s in (move.py PLAN)

[ -f "$CACHE/install/setup.bash" ] || { echo "record-golden: no driver in $CACHE (run build.sh first)" >&2; exit 2; }
[ "$(id -u)" = 0 ] || { echo "record-golden: needs root for unshare -n" >&2; exit 2; }
mkdir -p "$OUT" "$CACHE/golden-logs"
wanted=("$@")
done_now=()

record_one() {   # name fake-args topics (run inside the namespace)
  local name="$1" fake="$2" topics="$3" log="$CACHE/golden-logs/$1"
  ip link set lo up
  export ROS_MASTER_URI=http://127.0.0.1:11311 ROS_IP=127.0.0.1 ROS_HOME="$(mktemp -d)"
  set +u      # ROS's setup scripts read unset variables
  # shellcheck disable=SC1091
  source "$CACHE/install/setup.bash"
  roscore -p 11311 >"$log.roscore" 2>&1 &
  local core=$!
  PYTHONPATH="$REPO/src${PYTHONPATH:+:$PYTHONPATH}" \
    "$REPO/.venv/bin/python" "$REPO/scripts/pepperFakeNaoqi" --port 9559 --video-relay $fake >"$log.fake" 2>&1 &
  local fake_pid=$!
  for _ in $(seq 100); do grep -q 'fake NAOqi ready' "$log.fake" && break; sleep 0.1; done
  "$CACHE/install/bin/video_relay" tcp://127.0.0.1:9559 >"$log.relay" 2>&1 &
  local relay=$!
  for _ in $(seq 100); do grep -q 'video relay ready' "$log.relay" && break; sleep 0.1; done
  local audio=""
  if [[ " $fake " == *" --audio-relay "* ]]; then
    "$CACHE/install/bin/audio_relay" tcp://127.0.0.1:9559 >"$log.audio-relay" 2>&1 &
    audio=$!
    for _ in $(seq 100); do grep -q 'audio relay ready' "$log.audio-relay" && break; sleep 0.1; done
  fi
  for _ in $(seq 100); do rostopic list >/dev/null 2>&1 && break; sleep 0.2; done
  "$CACHE/install/lib/naoqi_driver/naoqi_driver_node" --nao_ip 127.0.0.1 --nao_port 9559 \
    --roscore_ip 127.0.0.1 --network_interface lo --namespace naoqi_driver \
    --password no_password >"$log.driver" 2>&1 &
  local driver=$!
  for _ in $(seq 150); do rostopic list 2>/dev/null | grep -q "^$NS/laser\$" && break; sleep 0.2; done
  if ! kill -0 "$driver" 2>/dev/null; then
    echo "[golden] the driver stopped: $log.driver" >&2; tail -5 "$log.driver" >&2
    kill -INT "$fake_pid" "$relay" $audio "$core" 2>/dev/null; wait 2>/dev/null; return 1
  fi
  sleep 2     # the converters start once subscribed: let the cameras subscribe first
  local seconds="$SECONDS_PER_BAG" mover=
  if [ "$name" = move ]; then
    seconds="$MOVE_SECONDS"
    ( sleep 1; source "$REPO/tools/env.sh"; export ROS_MASTER_URI=http://127.0.0.1:11311
      "$REPO/.venv/bin/python" "$HERE/move.py" ) >"$log.move" 2>&1 &
    mover=$!
  fi
  # shellcheck disable=SC2086
  rosbag record --bz2 --duration="$seconds" -O "$OUT/$name.bag" $topics >"$log.record" 2>&1 || true
  [ -z "$mover" ] || wait "$mover" 2>/dev/null || true
  kill -INT "$driver" 2>/dev/null || true     # the driver first: it aborts if NAOqi goes first
  for _ in $(seq 30); do kill -0 "$driver" 2>/dev/null || break; sleep 0.1; done
  kill -INT "$relay" $audio "$fake_pid" 2>/dev/null || true
  sleep 1
  kill -KILL "$driver" "$relay" $audio "$fake_pid" 2>/dev/null || true
  kill -INT "$core" 2>/dev/null || true
  wait 2>/dev/null || true
}
export -f record_one
export OUT CACHE REPO SECONDS_PER_BAG NS HERE MOVE_SECONDS

for entry in "${VARIANTS[@]}"; do
  IFS='|' read -r name fake topics <<<"$entry"
  if [ ${#wanted[@]} -gt 0 ] && [[ ! " ${wanted[*]} " == *" $name "* ]]; then continue; fi
  echo "[golden] $(date -u +%H:%M:%S) $name (fake NAOqi: ${fake:-defaults})"
  unshare -n bash -c "record_one '$name' '$fake' '$topics'"
  ls -l "$OUT/$name.bag"
  done_now+=("$entry")
done

"$REPO/.venv/bin/python" - "$OUT" "$CACHE/sources.txt" "$SECONDS_PER_BAG" "${done_now[@]}" <<'EOF'
import datetime, json, os, sys
out, sources, seconds, variants = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
move_seconds = os.environ.get('MOVE_SECONDS', '10')
path = os.path.join(out, 'manifest.json')
old = json.load(open(path)) if os.path.exists(path) else {}
commits = {}
for line in open(sources):
    name, branch, commit = line.split()
    commits[name] = {'branch': branch, 'commit': commit}
bags = old.get('bags', {})
for v in variants:
    name, fake, topics = v.split('|')
    bag = os.path.join(out, name + '.bag')
    if os.path.exists(bag):
        bags[name] = {'fake_naoqi': ('pepperFakeNaoqi --port 9559 --video-relay ' + fake).strip(), 'topics': topics.split(),
                      'seconds': float(move_seconds if name == 'move' else seconds), 'size_bytes': os.path.getsize(bag),
                      'recorded': datetime.datetime.utcnow().strftime('%Y-%m-%dT%H:%M:%SZ')}
        if name == 'move':
            bags[name]['motion'] = ('tools/real-driver/move.py, started 1 s after rosbag record: '
                                    'a zero /cmd_vel at 1 s (stops the idle drive of the fake robot), HeadYaw +0.5 rad at 3 s, '
                                    'back to 0 at 5 s (speed 0.1, /joint_angles), base turn +0.5 rad at 7 s '
                                    '(/move_base_simple/goal, base_footprint)')
json.dump({'sources': commits,
           'driver_command': 'naoqi_driver_node --nao_ip 127.0.0.1 --nao_port 9559 --roscore_ip 127.0.0.1 '
                             '--network_interface lo --namespace naoqi_driver --password no_password',
           'video_relay': 'video_relay tcp://127.0.0.1:9559 (tools/real-driver/relay/video_relay.cpp)',
           'audio_relay': 'audio_relay tcp://127.0.0.1:9559 (tools/real-driver/relay/audio_relay.cpp), '
                          'with the fake\'s --audio-relay',
           'record_command': 'rosbag record --bz2 --duration=%s' % seconds,
           'remake': 'tools/real-driver/record-golden.sh [variant ...]',
           'bags': bags}, open(path, 'w'), indent=1, sort_keys=True)
print('[golden] manifest: %s' % path)
EOF
echo "[golden] logs of each process: $CACHE/golden-logs/"
