"""naoqiAudioPublisher on ROS 2 (ROS_VERSION=2): the same bridge as on ROS 1 (publisher.py's
Bridge: the websocket, the token, the framing, the sequence accounting and the one-capture rule
are that code, unchanged), publishing through rclpy (rosapi.publisher on the process's node,
sources/live2.Ros2Graph). The capture side on the robot (scripts/naoqiAudio) does not change.

What it publishes, by --message:
  AudioBuffer     naoqi_bridge_msgs/AudioBuffer as naoqi_driver2 publishes the microphones
                  (src/event/audio.cpp, AudioEventRegister: channel_map [3, 5, 0, 2] on
                  Pepper's head; processRemote: header.stamp now, frequency 48000, data the
                  buffer's int16 samples interleaved): the default, on /audio;
  AudioCustomMsg  as the ROS 1 bridge (pepper_interface_tests/AudioCustomMsg: rearLeft,
                  rearRight, frontLeft, frontRight).
Channels 0..3 of a frame are rear left, rear right, front left, front right (publisher.py), the
channel codes 3, 5, 0, 2 (naoqi_msgs.PEPPER_CHANNEL_MAP), so both forms carry the same samples.

Options come from the command line only (as pepperEmulator's on ROS 2): --host, --port, --topic
(default /audio), --message, and the token as on ROS 1 ($PEPPER_AUDIO_TOKEN_FILE, --token-file).
No parameter server: the counters (publisher.py's ~stats) are logged once when the node ends,
and every STATS_LOG_S seconds while frames were lost or dropped. Ends on SIGINT or SIGTERM (0).
"""
import logging
import signal
import sys
import threading
from typing import Any, Callable, Optional, Sequence

import numpy as np

from .. import rosapi
from . import OneLineParser, listen_port_arg, read_token
from .frame import MAX_FRAME_BYTES, Frame
from .publisher import NODE, Bridge, _not_advertised, to_message
from .wsserver import serve

MESSAGES = {'AudioBuffer': 'naoqi_bridge_msgs/AudioBuffer',
            'AudioCustomMsg': 'pepper_interface_tests/AudioCustomMsg'}
DEFAULTS = {'host': '127.0.0.1', 'port': 9090, 'topic': '/audio', 'message': 'AudioBuffer'}
FREQUENCY = 48000       # naoqi_driver2 processRemote: msg.frequency = 48000
STATS_LOG_S = 10.0


def parse_args(argv: Sequence[str]) -> Any:
    p = OneLineParser(prog=NODE, description='Publish NAOqi audio frames received over a websocket '
                      'on ROS 2, as naoqi_driver2\'s AudioBuffer or as AudioCustomMsg.')
    for name in ('host', 'port', 'topic', 'token'):
        p.add_argument('--' + name, default=DEFAULTS.get(name), help='default %r' % DEFAULTS.get(name, ''))
    p.add_argument('--message', choices=sorted(MESSAGES), default=DEFAULTS['message'],
                   help='AudioBuffer (as naoqi_driver2, default) or AudioCustomMsg (as the ROS 1 bridge)')
    p.add_argument('--token-file', default=None,
                   help='file holding the token (default: $PEPPER_AUDIO_TOKEN_FILE)')
    return p.parse_args(argv)


def audio_buffer(frame: Frame, cls: type, stamp: Any) -> Any:
    """naoqi_bridge_msgs/AudioBuffer of a 4-channel frame, as naoqi_driver2's processRemote
    fills it: interleaved samples in channel_map order."""
    from ..sources.naoqi_msgs import PEPPER_CHANNEL_MAP
    samples = np.frombuffer(frame.payload, dtype='<i2')
    if frame.planar:
        samples = samples.reshape(frame.channels, frame.samples_per_channel).T
    msg = cls()
    msg.header.stamp = stamp
    msg.frequency = FREQUENCY
    msg.channelMap = bytes(PEPPER_CHANNEL_MAP)      # uint8[]: genpy serialises it from bytes
    msg.data = samples.reshape(-1).tolist()
    return msg


def builder(message: str) -> Callable[[Frame, type], Any]:
    """to_message for --message: Bridge calls it with each good frame."""
    if message == 'AudioBuffer':
        return lambda frame, cls: audio_buffer(frame, cls, rosapi.now())
    return to_message


class _Log:
    def __init__(self) -> None:
        self.info, self.warning = rosapi.loginfo, rosapi.logwarn


def main2(argv: Optional[Sequence[str]] = None) -> int:
    from ..ros2run import split_ros_args
    from ..sources.live2 import Ros2Graph
    args = parse_args(split_ros_args(list(sys.argv[1:] if argv is None else argv))[0])
    try:
        port = listen_port_arg(args.port)
        token, _, warning = read_token(args.token, args.token_file)
    except ValueError as exc:
        print('%s: error: %s' % (NODE, exc), file=sys.stderr)
        return 2
    stop = threading.Event()
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, lambda *_: stop.set())
    graph = Ros2Graph(NODE)
    type_name = MESSAGES[args.message]
    bridge = Bridge(_not_advertised, rosapi.msg(type_name), token, _Log(), build=builder(args.message))
    if warning:
        rosapi.logwarn(warning)
    try:
        server = serve(bridge.handle, args.host, port, MAX_FRAME_BYTES, bridge.check_token, _quiet())
    except OSError as exc:
        rosapi.logerr('cannot listen on %s:%d: %s (fix: another --port, or 0 for any free port)'
                      % (args.host, port, exc.strerror or exc))
        graph.shutdown()
        return 1
    out = rosapi.publisher(args.topic, type_name, queue_size=50)
    bridge.publish = out.publish
    threading.Thread(target=server.serve_forever, name='websocket', daemon=True).start()
    rosapi.loginfo('listening on ws://%s:%d%s, publishing %s (%s)' % (
        args.host, server.socket.getsockname()[1], ' (token required)' if token else '', args.topic, type_name))
    try:
        while not stop.wait(STATS_LOG_S) and graph.ok:
            _log_losses(bridge)
    finally:
        server.shutdown()
        bridge.close_all()
        with bridge._track_lock:
            rosapi.loginfo('stats: %s' % bridge.stats.snapshot(bridge.tracker))
        graph.shutdown()
    return 0


def _quiet() -> logging.Logger:
    """websockets' own logger, silenced as on ROS 1 (Bridge logs what matters)."""
    quiet = logging.getLogger(NODE + '.websockets')
    quiet.setLevel(logging.CRITICAL + 1)
    quiet.propagate = False
    return quiet


def _log_losses(bridge: Bridge) -> None:
    with bridge._track_lock:
        snap = bridge.stats.snapshot(bridge.tracker)
    if snap.get('lost_in_gaps') or snap.get('dropped_bad'):
        rosapi.logwarn('stats: %s' % snap)
