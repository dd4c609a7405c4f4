#!/usr/bin/env bash
# Record the golden ROS 2 recordings: what the real ros-naoqi/naoqi_driver2 (built by build.sh)
# publishes against the fake NAOqi (scripts/pepperFakeNaoqi), one short rosbag2 MCAP recording
# per world, into test/fixtures/real-driver2/<name>/ with manifest.json. Not part of `make test`;
# needs root (unshare).
#
#   tools/real-driver2/record-golden2.sh                  # every variant
#   tools/real-driver2/record-golden2.sh healthy_xtion
#
# Each variant runs in its own network namespace (unshare -n, loopback only): the fake NAOqi
# listens on 9559, which other runs on this machine use too, and the DDS traffic stays there.
set -euo pipefail
HERE="$(cd "$(dirname "$0")" && pwd)"
REPO="$(cd "$HERE/../.." && pwd)"
CACHE="${PEPPER_REAL_DRIVER2_CACHE:-/var/cache/pepper-real-driver2}"
OUT="${GOLDEN_DIR:-$REPO/test/fixtures/real-driver2}"
SECONDS_PER_REC="${GOLDEN_SECONDS:-4}"
# the logs of each process (GOLDEN_LOGS: elsewhere, when the cache is shared read-only)
LOGS="${GOLDEN_LOGS:-$CACHE/golden-logs}"
# naoqi_driver2's names: relative, and its node has no namespace (data/naoqi_driver2Topics.dat)
CAMERAS="/camera/front/image_raw /camera/bottom/image_raw /camera/depth/image_raw /camera/stereo/image_raw /camera/ir/image_raw"
BODY="/sonar/front /sonar/back /laser /odom /imu/base /imu/torso /joint_states /tf /diagnostics"
TOUCH="/head_touch /hand_touch /bumper"
# the microphone only in the audio variant, whose fake runs with --audio-relay (as the ROS 1
# audio bag): naoqi_driver2's processRemote reads its buffer as Raw (src/event/audio.cpp:183 at
# 2.1.2), which a Python NAOqi cannot send, so relay/audio_relay.cpp (built by build.sh) calls it.
# With it: each camera's camera_info (image_transport's camera publisher beside the image,
# src/publishers/camera.cpp:44-47, sent only while the image has a subscriber: camera.hpp:57-64,
# so the images are subscribed, not recorded) and the latched URDF (robot_description.cpp:64-76)
INFOS="/camera/front/camera_info /camera/bottom/camera_info /camera/depth/camera_info /camera/stereo/camera_info /camera/ir/camera_info"

# name | fake NAOqi arguments | topics
VARIANTS=(
  "healthy_stereo||$CAMERAS $BODY $TOUCH"
  "healthy_xtion|--head xtion|$CAMERAS $BODY $TOUCH"
  # +topic: subscribed, not recorded (record2.py): the images the camera_info is sent with
  "audio|--audio-relay|/audio $INFOS /robot_description +${CAMERAS// / +}"
  # the robot moves while recorded (tools/real-driver/move.py with ROS_VERSION=2, as the ROS 1
  # `move` bag: stop, head +0.5 rad and back, base +0.5 rad): the motion witnesses
  "move||/odom /imu/base /laser /joint_states /tf /sonar/front /sonar/back /camera/front/image_raw /camera/bottom/image_raw /camera/depth/image_raw"
)
MOVE_SECONDS=10    # move.py's commands end ~8.5 s after it starts, 1 s into the recording
# the microphone's 48 kHz x 4 channels of noise barely compress: 3 s (~35 buffers) keep it < 1 MB
AUDIO_SECONDS=3
# the driver's parameters (src/external_registration.cpp:63-76 at 2.1.2)
DRIVER_ARGS="--ros-args -p nao_ip:=127.0.0.1 -p nao_port:=9559 -p network_interface:=lo -p qi_listen_url:=tcp://127.0.0.1:0"

[ -f "$CACHE/install/setup.bash" ] || { echo "record-golden2: no driver in $CACHE (run build.sh first)" >&2; exit 2; }
[ "$(id -u)" = 0 ] || { echo "record-golden2: needs root for unshare -n" >&2; exit 2; }
mkdir -p "$OUT" "$LOGS"
wanted=("$@")
known=" $(for v in "${VARIANTS[@]}"; do printf '%s ' "${v%%|*}"; done)"
for w in "${wanted[@]}"; do
  [[ "$known" == *" $w "* ]] || { echo "record-golden2: no variant '$w' (the variants:$known)" >&2; exit 2; }
done
done_now=()

record_one() {   # name fake-args topics (run inside the namespace)
  local name="$1" fake="$2" topics="$3" log="$LOGS/$1"
  ip link set lo up
  export RMW_IMPLEMENTATION=rmw_cyclonedds_cpp ROS_LOCALHOST_ONLY=1 ROS_DOMAIN_ID=0
  export ROS_HOME="$(mktemp -d)"
  set +u      # ROS's setup scripts read unset variables
  # shellcheck disable=SC1091
  source "$CACHE/install/setup.bash"
  set -u
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
  # shellcheck disable=SC2086
  "$CACHE/install/lib/naoqi_driver/naoqi_driver_node" $DRIVER_ARGS >"$log.driver" 2>&1 &
  local driver=$!
  for _ in $(seq 150); do grep -q 'Starting ROS loop' "$log.driver" && break; sleep 0.2; done
  if ! kill -0 "$driver" 2>/dev/null; then
    echo "[golden2] the driver stopped: $log.driver" >&2; tail -5 "$log.driver" >&2
    kill -INT "$fake_pid" "$relay" $audio 2>/dev/null; wait 2>/dev/null; return 1
  fi
  rm -rf "${OUT:?}/$name"
  local seconds="$SECONDS_PER_REC"
  [ "$name" != move ] || seconds="$MOVE_SECONDS"
  [ "$name" != audio ] || seconds="$AUDIO_SECONDS"
  local on_signal=0
  [ "$name" != move ] || on_signal=1
  # shellcheck disable=SC2086
  RECORD2_ON_SIGNAL=$on_signal "$REPO/.venv/bin/python" "$HERE/record2.py" "$OUT/$name" "$seconds" $topics >"$log.record" 2>&1 &
  local recorder=$!
  if [ "$name" = move ]; then
    # The recording starts 1 s after move.py's stop (SIGUSR1 to record2.py), 1 s before its
    # head command: the fake robot's idle drive (a circle at ~0.15 rad/s until the stop) stays
    # out of the recording, and no base motion is near the head's yaw (recorded.py leaves out
    # a head move that overlaps a stretch where the base moved). move.py's own start on ROS 2
    # (rclpy, the graph, the driver's subscribers) takes a second or more here, so its stop is
    # waited for rather than timed.
    for _ in $(seq 300); do grep -q 'record2: subscribed' "$log.record" && break; sleep 0.1; done
    ROS_VERSION=2 PYTHONPATH="$REPO/src:${PYTHONPATH:-}" "$REPO/.venv/bin/python" \
      "$REPO/tools/real-driver/move.py" >"$log.move" 2>&1 &
    local mover=$!
    for _ in $(seq 300); do grep -q ' s stop ' "$log.move" && break; sleep 0.05; done
    sleep 1
    kill -USR1 "$recorder"
    wait "$mover" || true
  fi
  wait "$recorder" || true
  kill -INT "$driver" 2>/dev/null || true     # the driver first: it aborts if NAOqi goes first
  for _ in $(seq 30); do kill -0 "$driver" 2>/dev/null || break; sleep 0.1; done
  kill -INT "$relay" $audio "$fake_pid" 2>/dev/null || true
  sleep 1
  kill -KILL "$driver" "$relay" $audio "$fake_pid" 2>/dev/null || true
  wait 2>/dev/null || true
}
export -f record_one
export OUT CACHE LOGS REPO SECONDS_PER_REC HERE DRIVER_ARGS MOVE_SECONDS AUDIO_SECONDS

for entry in "${VARIANTS[@]}"; do
  IFS='|' read -r name fake topics <<<"$entry"
  if [ ${#wanted[@]} -gt 0 ] && [[ ! " ${wanted[*]} " == *" $name "* ]]; then continue; fi
  echo "[golden2] $(date -u +%H:%M:%S) $name (fake NAOqi: ${fake:-defaults})"
  unshare -n bash -c "record_one '$name' '$fake' '$topics'"
  cat "$LOGS/$name.record"
  du -sb "$OUT/$name"
  done_now+=("$entry")
done

"$REPO/.venv/bin/python" - "$OUT" "$CACHE/sources.txt" "$SECONDS_PER_REC" "${done_now[@]}" <<'EOF'
import datetime, json, os, sys
out, sources, seconds, variants = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
path = os.path.join(out, 'manifest.json')
old = json.load(open(path)) if os.path.exists(path) else {}
commits = {}
for line in open(sources):
    repo, tag, commit = line.split()
    commits[repo] = {'tag': tag, 'commit': commit}
recs = old.get('recordings', {})
# what each recording shows (naoqi_driver2 2.1.2's source: src/naoqi_driver.cpp, src/helpers/)
SHOWS = {
    'healthy_stereo': 'a healthy Pepper 1.8 (stereo head: "CameraStereo" in ALMotion.getSensorNames, '
                      'driver_helpers.cpp:357-367) on the fake\'s idle drive (a slow circle), nobody touching it: '
                      'every sensor row PASS, the touch rows SKIPPED (not touched); no /camera/ir/image_raw '
                      '(naoqi_driver.cpp:666-667 turns the IR camera off on a stereo head)',
    'healthy_xtion': 'a healthy Pepper 1.7 (Xtion head: no "CameraStereo", driver_helpers.cpp:357-367) on the '
                     'fake\'s idle drive, nobody touching it: every sensor row PASS (irCamera too), stereoCamera '
                     'SKIPPED (this head has none: no /camera/stereo/image_raw, naoqi_driver.cpp:791), the touch '
                     'rows SKIPPED (not touched)',
    'audio': 'the microphone with the fake\'s --audio-relay (as the ROS 1 audio bag): /audio, naoqi_driver2\'s '
             'AudioBuffer (src/event/audio.cpp:171-181: frequency 48000, channel map [3, 5, 0, 2] for a '
             'Micro/Version head, audio.cpp:55-64, data = the int16 samples NAOqi sent, stamp the receive time, frame id ""), the '
             'microphone row PASS as on the ROS 1 audio bag; each camera\'s camera_info (image_transport\'s camera '
             'publisher, publishers/camera.cpp:44-47: sent while the image has a subscriber, camera.hpp:57-64, so '
             'the images were subscribed and not recorded; the stereo head\'s: no /camera/ir/camera_info, '
             'naoqi_driver.cpp:666-667); the URDF once, transient-local (tools/robot_description.cpp:64-76, '
             'published at start: naoqi_driver.cpp:144)',
    'move': 'the robot commanded through naoqi_driver2\'s subscribers (motion): the motion witnesses (odometry, '
            'gyro, laser, wheels, head cameras) record one base turn of +0.5 rad and the head\'s yaw +0.5 rad and '
            'back; every recorded row PASS, the turn and the two head yaws found (the bottom camera, which sees '
            'the fake\'s nearly plain floor, may be left unjudged on a yaw: a warning, rules.MIN_TEXTURE)',
}
for v in variants:
    name, fake, topics = v.split('|')
    folder = os.path.join(out, name)
    if os.path.isdir(folder):
        recs[name] = {'fake_naoqi': ('pepperFakeNaoqi --port 9559 --video-relay ' + fake).strip(),
                      'topics': [t for t in topics.split() if not t.startswith('+')],
                      'seconds': float({'move': os.environ['MOVE_SECONDS'],
                                        'audio': os.environ['AUDIO_SECONDS']}.get(name, seconds)),
                      'size_bytes': sum(os.path.getsize(os.path.join(folder, f)) for f in os.listdir(folder)),
                      'recorded': datetime.datetime.utcnow().strftime('%Y-%m-%dT%H:%M:%SZ')}
        unwritten = [t[1:] for t in topics.split() if t.startswith('+')]
        if unwritten:   # record2.py's +topic
            recs[name]['subscribed_not_recorded'] = unwritten
for name in recs:     # the descriptions are the script's: kept true for every recording listed
    recs[name]['shows'] = SHOWS[name]
    if name == 'move':
        recs[name]['motion'] = ('tools/real-driver/move.py (ROS_VERSION=2); the recording starts 1 s after its '
                                'first command, a zero /cmd_vel (teleop.cpp:59 ALMotion.move: the fake robot\'s idle '
                                'drive stops before the recording), then '
                                'HeadYaw +0.5 rad at 2 s and back to 0 at 4 s (speed 0.1, /joint_angles, '
                                'teleop.cpp:66 setAngles), base turn +0.5 rad at 6 s (/move_base_simple/goal in '
                                'base_footprint, moveto.cpp:108-120 moveTo); the times are move.py\'s, 1 s less '
                                'into the recording')
json.dump({'sources': commits,
           'driver_command': 'naoqi_driver_node ' + os.environ['DRIVER_ARGS'],
           'video_relay': 'video_relay tcp://127.0.0.1:9559 (tools/real-driver/relay/video_relay.cpp)',
           'audio_relay': ('audio_relay tcp://127.0.0.1:9559 (tools/real-driver/relay/audio_relay.cpp), with the '
                           'fake\'s --audio-relay'),
           'record_command': 'tools/real-driver2/record2.py <out> %s <topics> (rosbag2, MCAP)' % seconds,
           'remake': 'tools/real-driver2/record-golden2.sh [variant ...]',
           'recordings': recs}, open(path, 'w'), indent=1, sort_keys=True)
print('[golden2] manifest: %s' % path)
EOF
echo "[golden2] logs of each process: $LOGS/"
