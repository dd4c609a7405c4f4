"""ROS side of the audio bridge: websocket frames -> pepper_interface_tests/AudioCustomMsg.

A rospy node running a websocket server of plain threads, one per connection (wsserver.py:
websockets' sync server, or on websockets before 11.0 its asyncio server behind the same API).
Every binary message is validated with ``decode_frame``; bad ones are dropped with at most one
warning per cause every 5 s (with the count) and the node carries on.
Good 4-channel frames are published with channel 0..3 in rearLeft, rearRight, frontLeft,
frontRight, whatever the layout (planar or interleaved) of the frame.

Sequence accounting: within a stream (same stream id) a jump of the sequence number counts the
missing buffers in ``lost_in_gaps``; a new stream id (capture restarted) counts a stream reset,
not a loss; a jump of more than ``MAX_GAP`` buffers (years of audio) is not a loss but a bad
frame (``implausible sequence``), dropped. The last stream id and sequence are kept in
``~stats``, so a restarted publisher also counts what was lost while it was down (after a hard
kill that snapshot may be up to one second old, so the count may then include up to a second of
buffers the dead process did publish).

One capture at a time: a second websocket connection while another one is streaming (a frame
in the last ``ACTIVE_WINDOW`` s) is refused (HTTP 409 at the handshake, or closed if it got in
at the same moment), counted and logged; its frames are never published.

Layout: each frame says whether its samples are planar or interleaved; ``layout.py`` checks
that the data looks like the declared layout and frames of a stream proven mislabelled are
dropped (``layout mismatch``), never published with mixed channels.

Start-up order: the websocket port is bound first and the ROS topic advertised only once it
listens, so "the topic is published" means "the bridge is up" to whoever watches the launch
(rosmaster.wait_for_launch); a port that cannot be bound ends the node (exit 1, "cannot listen
on HOST:PORT" with the fix) without the topic ever being advertised.

Options (command line wins over the private parameter of the same name):
  --host / ~host (127.0.0.1)  --port / ~port (9090; 0 = any free port, the log says which)
  --topic / ~topic (/naoqi_driver/audio)
  token: $PEPPER_AUDIO_TOKEN_FILE (a file holding it; the way under roslaunch) or
  $PEPPER_AUDIO_TOKEN, kept out of ``ps`` and of the parameter server; --token-file FILE;
  --token and ~token still work but warn, and ~token is deleted once read.
``~stats`` (dict, updated once a second): received, published, dropped_bad, lost_in_gaps,
connections, rejected_connections, stream_resets, bad_causes, stream_id, last_sequence (a
decimal string: sequence numbers are 64-bit, XML-RPC ints 32-bit), latency_ms_mean,
latency_ms_max (buffer end to publish, last second; -1 when no data).
"""
import hmac
import http
import logging
import sys
import threading
import time
from typing import TYPE_CHECKING, Any, Callable, Dict, List, Optional, Protocol, Sequence, Tuple, Union

import numpy as np

from pepper_interface_tests.audio_bridge import OneLineParser, RateLimiter, listen_port_arg, read_token
from pepper_interface_tests.audio_bridge.frame import MAX_FRAME_BYTES, TOKEN_HEADER, Frame, FrameError, decode_frame
from pepper_interface_tests.audio_bridge.layout import LayoutGuard
from pepper_interface_tests.audio_bridge.wsserver import closed_oversized, serve

if TYPE_CHECKING:
    import argparse
    from types import ModuleType

    import genpy
    from websockets.http11 import Request, Response
    from websockets.sync.server import ServerConnection

NODE = 'naoqiAudioPublisher'
DEFAULTS = {'host': '127.0.0.1', 'port': 9090, 'token': '', 'topic': '/naoqi_driver/audio'}
WARN_INTERVAL = 5.0
STATS_INTERVAL = 1.0
# s a restarted publisher (one that continues the ~stats of a previous one) waits for its first
# subscriber before it takes capture connections: the capture sends the backlog it queued while
# the publisher was down in one burst as soon as it reconnects, and what is published before a
# subscriber's TCPROS connection to the new publisher is made (the master's publisherUpdate,
# then a connect: a few hundred ms) reaches nobody and is counted by no one; a test saw 6
# buffers lost that way. Bounded: with nobody subscribed the publisher goes on after this long
RESUBSCRIBE_WAIT = 3.0
# A jump of the sequence number beyond this many buffers is not a loss: at NAOqi's ~12 buffers/s
# 2**31 buffers are 5.8 years of audio, so such a frame is corrupt or forged.
MAX_GAP = 2 ** 31
# A connection that published a frame within this many seconds is "streaming"; NAOqi sends a
# buffer every 85 ms (4096 samples at 48 kHz; ~170 ms on a robot), so 2 s is >10 missed buffers.
ACTIVE_WINDOW = 2.0
XMLRPC_INT_MAX = 2 ** 31 - 1


class Log(Protocol):
    """Where the bridge logs: rospy's loggers in the node (_RosLog), a logging.Logger in tests."""

    def info(self, text: str) -> None: ...

    def warning(self, text: str) -> None: ...


class SequenceTracker:
    """Counts buffers missing from sequence gaps; tells capture restarts from losses."""

    def __init__(self, stream_id: Optional[int] = None, last_sequence: Optional[int] = None) -> None:
        self.stream_id, self.last = stream_id, last_sequence
        self.lost = 0
        self.resets = 0

    def observe(self, stream_id: int, sequence: int) -> Tuple[int, Optional[str]]:
        """Account one frame. Returns (missing_before_it, event) with event None, 'start',
        'reset' (new stream id: capture restarted) or 'backwards' (sequence went back)."""
        if self.stream_id is None or self.last is None:     # both are set together
            event, missing = 'start', 0
        elif stream_id != self.stream_id:
            event, missing = 'reset', 0
            self.resets += 1
        elif sequence <= self.last:
            event, missing = 'backwards', 0
            self.resets += 1
        else:
            event, missing = None, sequence - self.last - 1
        self.stream_id, self.last = stream_id, sequence
        self.lost += missing
        return missing, event

    def implausible(self, stream_id: int, sequence: int) -> bool:
        """True for a jump of more than MAX_GAP buffers within the current stream."""
        return stream_id == self.stream_id and self.last is not None and sequence - self.last > MAX_GAP


class Stats:
    """Counters shared by the connection threads, published as ``~stats``."""

    FIELDS = ('received', 'published', 'dropped_bad', 'lost_in_gaps', 'connections',
              'rejected_connections', 'stream_resets')

    def __init__(self) -> None:
        self.lock = threading.Lock()
        self.counts = dict((f, 0) for f in self.FIELDS)
        self.bad_causes: Dict[str, int] = {}
        self._latencies: List[float] = []

    def add(self, field: str, n: int = 1) -> None:
        with self.lock:
            self.counts[field] += n

    def bad(self, cause: str) -> None:
        with self.lock:
            self.counts['dropped_bad'] += 1
            self.bad_causes[cause] = self.bad_causes.get(cause, 0) + 1

    def latency(self, ms: float) -> None:
        with self.lock:
            self._latencies.append(ms)

    def snapshot(self, tracker: SequenceTracker) -> Dict[str, Any]:
        with self.lock:
            lat, self._latencies = self._latencies, []
            out: Dict[str, Any] = dict(self.counts)
            out['bad_causes'] = dict(self.bad_causes)
        out['lost_in_gaps'] = tracker.lost
        out['stream_resets'] = tracker.resets
        out['stream_id'] = '' if tracker.stream_id is None else '%08x' % tracker.stream_id
        out['last_sequence'] = '' if tracker.last is None else str(tracker.last)
        out['latency_ms_mean'] = round(float(np.mean(lat)), 2) if lat else -1.0
        out['latency_ms_max'] = round(float(np.max(lat)), 2) if lat else -1.0
        return xmlrpc_safe(out)


def xmlrpc_safe(value: Any) -> Any:
    """``value`` with every int outside XML-RPC's 32-bit range turned into a float, so a
    rospy.set_param of it can never fail (it did: one sequence of 10**12 stopped ~stats)."""
    if isinstance(value, dict):
        return dict((k, xmlrpc_safe(v)) for k, v in value.items())
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) > XMLRPC_INT_MAX:
        return float(value)
    return value


def to_message(frame: Frame, msg_class: type) -> 'genpy.Message':
    """AudioCustomMsg from a 4-channel frame (planar or interleaved)."""
    samples = np.frombuffer(frame.payload, dtype='<i2')
    if frame.planar:
        chans = samples.reshape(frame.channels, frame.samples_per_channel)
    else:
        chans = samples.reshape(frame.samples_per_channel, frame.channels).T
    return msg_class(rearLeft=chans[0].tolist(), rearRight=chans[1].tolist(),
                     frontLeft=chans[2].tolist(), frontRight=chans[3].tolist())


class Bridge:
    """Websocket connection handler: validate, account, publish."""

    def __init__(self, publish: Callable[['genpy.Message'], None], msg_class: type, token: str, log: Log,
                 clock: Callable[[], float] = time.monotonic,
                 build: Optional[Callable[[Frame, type], 'genpy.Message']] = None) -> None:
        self.publish, self.msg_class, self.token, self.log = publish, msg_class, token, log
        self.build = build or to_message        # the message of a frame (publisher2.py: AudioBuffer too)
        self.stats = Stats()
        self.tracker = SequenceTracker()
        self.layout = LayoutGuard()
        self._track_lock = threading.Lock()
        self._limiter = RateLimiter(WARN_INTERVAL)
        self._clock = clock
        # (peer, connection id, time of its last published frame)
        self._owner: Optional[Tuple[str, Optional[int], float]] = None
        self._open: Dict[int, ServerConnection] = {}   # the connections being handled

    def warn_limited(self, key: str, text: str) -> None:
        n = self._limiter.hit(key)
        if n:
            self.log.warning('%s (%d in the last %.0f s)' % (text, n, WARN_INTERVAL))

    def check_token(self, connection: 'ServerConnection', request: 'Request') -> Optional['Response']:
        """websockets process_request hook: 401 unless the handshake carries the token; 409
        while another capture connection is streaming."""
        if self.token:
            given = request.headers.get(TOKEN_HEADER)
            # websockets keeps non-ASCII header bytes as surrogate escapes: back to the raw
            # bytes, compared with the UTF-8 token (a plain .encode() raised: HTTP 500).
            raw = None if given is None else given.encode('ascii', 'surrogateescape')
            if raw is None or not hmac.compare_digest(raw, self.token.encode('utf-8')):
                cause = 'no token' if given is None else 'wrong token'
                self.stats.add('rejected_connections')
                self.stats.bad(cause)
                self.warn_limited(cause, 'rejected websocket connection from %s: %s'
                                  % (_peer(connection), cause))
                return connection.respond(http.HTTPStatus.UNAUTHORIZED,
                                          'missing or wrong token\n')
        owner = self._streaming_owner()
        if owner is not None:
            self._refuse_second(_peer(connection), owner)
            return connection.respond(http.HTTPStatus.CONFLICT, 'another capture (%s) is '
                                      'streaming to this publisher\n' % owner)
        return None

    def _streaming_owner(self, exclude: Optional[int] = None) -> Optional[str]:
        """Peer of the connection that published within ACTIVE_WINDOW s (not ``exclude``)."""
        with self._track_lock:
            owner = self._owner
        if owner is None or owner[1] == exclude or self._clock() - owner[2] > ACTIVE_WINDOW:
            return None
        return owner[0]

    def _refuse_second(self, peer: str, owner: str) -> None:
        self.stats.add('rejected_connections')
        self.stats.bad('second capture')
        self.warn_limited('second capture', 'refused a second capture connection from %s: %s '
                          'is already streaming to this publisher, and two streams would be '
                          'published interleaved. Fix: run one naoqiAudio per publisher (stop '
                          'the other one, e.g. a naoqi_driver audio bridge), or give each its '
                          'own publisher --port and --topic' % (peer, owner))

    def handle(self, connection: 'ServerConnection') -> None:
        """One capture connection: runs in its own thread until the peer goes away."""
        from websockets.exceptions import ConnectionClosed
        peer = _peer(connection)
        self.stats.add('connections')
        self.log.info('capture connected from %s' % peer)
        self._open[id(connection)] = connection
        try:
            for message in connection:
                try:
                    if self.on_message(message, peer, id(connection)) == 'second capture':
                        connection.close(1008, 'another capture is streaming')
                except Exception as exc:  # e.g. publishing during shutdown: never kill the node
                    self.warn_limited('internal', 'frame from %s not published: %s: %s'
                                      % (peer, type(exc).__name__, exc))
        except ConnectionClosed as exc:
            if closed_oversized(exc):
                self.stats.bad('oversized')
                self.warn_limited('oversized', 'closed connection from %s: message larger than'
                                  ' %d bytes' % (peer, MAX_FRAME_BYTES))
        finally:
            self._open.pop(id(connection), None)
        self.log.info('capture connection from %s closed' % peer)

    def close_all(self, timeout: float = 2.0) -> None:
        """Close every capture connection (1001, going away) and wait up to ``timeout`` s for
        their handlers to finish the frames they read. At shutdown this comes first: a
        connection left open while rospy shuts down swallowed the frames sent meanwhile, about
        2.5 s of audio that the capture never resent; closed, the capture keeps them queued for
        the next publisher, and the ~stats written next count every frame published. Each close
        waits for its peer's answer, so they run in threads: a silent peer (half-open after a
        WiFi drop) holds up the shutdown ``timeout`` s, not the library's close timeout."""
        for connection in list(self._open.values()):
            threading.Thread(target=_close_going_away, args=(connection,), name='close',
                             daemon=True).start()
        deadline = time.monotonic() + timeout
        while self._open and time.monotonic() < deadline:
            time.sleep(0.01)

    def on_message(self, message: Union[str, bytes], peer: str, conn: Optional[int] = None) -> Optional[str]:
        """Validate, account and publish one message; returns the drop cause or None."""
        self.stats.add('received')
        if isinstance(message, str):
            self.stats.bad('text message')
            self.warn_limited('text message', 'dropped a text message from %s: only binary frames '
                              'are expected' % peer)
            return 'text message'
        try:
            frame = decode_frame(message)
            if frame.channels != 4:
                raise FrameError('not 4 channels', 'frame has %d channel(s); AudioCustomMsg '
                                 'needs the 4 of ALAudioDevice ALL' % frame.channels)
        except FrameError as exc:
            self.stats.bad(exc.cause)
            self.warn_limited(exc.cause, 'dropped bad frame from %s: %s' % (peer, exc))
            return exc.cause
        owner = self._streaming_owner(exclude=conn)
        if owner is not None:  # got past the handshake check at the same moment
            self._refuse_second(peer, owner)
            return 'second capture'
        problem = self.layout.check(frame)
        if problem:
            kind, why = problem
            self.stats.bad('layout mismatch')
            text = 'dropped frame %d of stream %08x from %s: %s' % (frame.sequence,
                                                                   frame.stream_id, peer, why)
            if kind == 'confirmed':
                self.log.warning(text)
            else:
                self.warn_limited('layout ' + kind, text)
            return 'layout mismatch'
        msg = self.build(frame, self.msg_class)
        event: Optional[str]
        with self._track_lock:  # publish first: a frame that failed to publish counts as lost
            previous = self.tracker.last
            if previous is not None and self.tracker.implausible(frame.stream_id, frame.sequence):
                event, jump = 'implausible', frame.sequence - previous
            else:
                self.publish(msg)
                missing, event = self.tracker.observe(frame.stream_id, frame.sequence)
                self._owner = (peer, conn, self._clock())
        if event == 'implausible':
            self.stats.bad('implausible sequence')
            self.warn_limited('implausible sequence', 'dropped frame from %s: implausible sequence %d '
                              'jumps %d buffers past %s in stream %08x (more than %d: corrupt '
                              'or forged)' % (peer, frame.sequence, jump, previous,
                                              frame.stream_id, MAX_GAP))
            return 'implausible sequence'
        self.stats.add('published')
        end = frame.ts_sec + frame.ts_usec / 1e6 + frame.samples_per_channel / float(
            frame.sample_rate)
        if frame.ts_sec:
            self.stats.latency((time.time() - end) * 1000.0)
        self._report(frame, missing, event, previous)
        return None

    def _report(self, frame: Frame, missing: int, event: Optional[str], previous: Optional[int]) -> None:
        if event == 'start':
            self.log.info('stream %08x: %d ch x %d samples @ %d Hz, %s, first sequence %d'
                          % (frame.stream_id, frame.channels, frame.samples_per_channel,
                             frame.sample_rate, 'planar' if frame.planar else 'interleaved',
                             frame.sequence))
        elif event == 'reset':
            self.log.warning('new stream %08x from sequence %d: the capture side restarted'
                             % (frame.stream_id, frame.sequence))
        elif event == 'backwards':
            self.log.warning('stream %08x: sequence went back from %s to %d'
                             % (frame.stream_id, previous, frame.sequence))
        if missing:
            self.warn_limited('gap', 'lost %d buffer(s) before sequence %d; %d lost in total'
                              % (missing, frame.sequence, self.tracker.lost))


def _close_going_away(connection: 'ServerConnection') -> None:
    try:
        connection.close(1001, 'publisher shutting down')
    except Exception:  # already closing: nothing left to do
        pass


def _peer(connection: 'ServerConnection') -> str:
    try:
        host, port = connection.remote_address[:2]
        return '%s:%d' % (host, port)
    except (TypeError, ValueError, AttributeError):
        return 'unknown peer'


def parse_args(argv: Sequence[str]) -> 'argparse.Namespace':
    p = OneLineParser(prog=NODE, description='Publish NAOqi audio frames received '
                                'over a websocket as AudioCustomMsg.')
    for name in ('host', 'port', 'token', 'topic'):
        p.add_argument('--' + name, default=None,
                       help='overrides ~%s (default %r)' % (name, DEFAULTS[name]))
    p.add_argument('--token-file', default=None,
                   help='file holding the token (default: $PEPPER_AUDIO_TOKEN_FILE)')
    return p.parse_args(argv)


def _options(args: 'argparse.Namespace', rospy: 'ModuleType') -> Dict[str, Any]:
    """Options from the command line, else the private params, else DEFAULTS. The token: see
    read_token (--token, --token-file, $PEPPER_AUDIO_TOKEN_FILE, $PEPPER_AUDIO_TOKEN); a ~token
    param still works but is readable by every node: it gets a warning and is deleted once
    read. Raises ValueError (TokenError, PortError) with the fix."""
    opts = {}
    for name, default in DEFAULTS.items():
        if name != 'token':
            cli = getattr(args, name)
            opts[name] = cli if cli is not None else rospy.get_param('~' + name, default)
    opts['port'] = listen_port_arg(opts['port'])
    token, where, warning = read_token(args.token, args.token_file)
    if rospy.has_param('~token'):
        param = str(rospy.get_param('~token'))
        rospy.delete_param('~token')
        if not token and param:
            token, warning = param, ('token taken from the ~token param, readable by every '
                                     'node (now deleted); use $PEPPER_AUDIO_TOKEN_FILE')
    if warning:
        rospy.logwarn(warning)
    if where == '$PEPPER_AUDIO_TOKEN' and any(a.startswith('__log:=') for a in sys.argv):
        rospy.logwarn('token taken from $PEPPER_AUDIO_TOKEN under roslaunch, which writes every '
                      'process\'s environment into its log file; use $PEPPER_AUDIO_TOKEN_FILE')
    opts['token'] = token
    return opts


def _wait_for_master(log: Callable[[str], Any]) -> None:
    import rosgraph
    master, warned = rosgraph.Master('/' + NODE), False
    while not master.is_online():
        if not warned:
            log('ROS master %s not reachable yet; waiting' % rosgraph.get_master_uri())
            warned = True
        time.sleep(1.0)


def _resume(bridge: Bridge, rospy: 'ModuleType') -> bool:
    """Continue sequence accounting from the previous run's ``~stats``, if any; whether it did
    (this publisher replaces one that ran)."""
    old = rospy.get_param('~stats', None)
    if not isinstance(old, dict) or not old.get('stream_id'):
        return False
    try:
        stream_id, last = int(old['stream_id'], 16), int(old.get('last_sequence', ''))
    except (TypeError, ValueError):
        return False
    if last < 0:
        return False
    bridge.tracker = SequenceTracker(stream_id, last)
    rospy.loginfo('continuing sequence accounting of stream %s after sequence %d (from '
                  'the previous ~stats)', old['stream_id'], last)
    return True


def _wait_for_subscriber(publisher: Any, timeout: float) -> None:
    """Up to `timeout` s until `publisher` has a subscriber (RESUBSCRIBE_WAIT)."""
    deadline = time.monotonic() + timeout
    while publisher.get_num_connections() == 0 and time.monotonic() < deadline:
        time.sleep(0.05)


def _stats_loop(bridge: Bridge, stop: threading.Event, rospy: 'ModuleType') -> None:
    while not stop.wait(STATS_INTERVAL):
        _write_stats(bridge, rospy)


_STATS_LIMITER = RateLimiter(60.0)


def _write_stats(bridge: Bridge, rospy: 'ModuleType') -> None:
    with bridge._track_lock:
        snap = bridge.stats.snapshot(bridge.tracker)
    try:
        rospy.set_param('~stats', snap)
    except Exception as exc:  # master gone (restarting, or shutting down first)
        n = _STATS_LIMITER.hit('stats')
        if n:
            sys.stderr.write('%s: could not update ~stats (%d time(s) in the last minute): %s\n'
                             % (NODE, n, exc))


def main(argv: Optional[Sequence[str]] = None) -> int:
    import rospy

    from pepper_interface_tests.msg import AudioCustomMsg

    args = parse_args(rospy.myargv(sys.argv)[1:] if argv is None else argv)
    _wait_for_master(lambda text: sys.stderr.write('%s: %s\n' % (NODE, text)))
    rospy.init_node(NODE)
    try:
        opts = _options(args, rospy)
    except ValueError as exc:
        rospy.logerr(str(exc))
        return 2
    # The port first, the topic only once it listens: a watcher of the launch (tools/demo.sh,
    # rosmaster.wait_for_launch) takes the topic for "the bridge is up"; advertised before a
    # bind that fails, it declared the emulator up just before the bridge died. Nothing is
    # published before serve_forever starts accepting, so `publish` is set in time.
    bridge = Bridge(_not_advertised, AudioCustomMsg, opts['token'], _RosLog(rospy))
    resumed = _resume(bridge, rospy)
    quiet = logging.getLogger(NODE + '.websockets')
    quiet.setLevel(logging.CRITICAL + 1)
    quiet.propagate = False
    try:
        server = serve(bridge.handle, opts['host'], opts['port'], MAX_FRAME_BYTES,
                       bridge.check_token, quiet)
    except OSError as exc:
        rospy.logerr('cannot listen on %s:%d: %s (fix: another --port / ~port, or 0 for any '
                     'free port)' % (opts['host'], opts['port'], exc.strerror or exc))
        return 1
    ros_publisher = rospy.Publisher(opts['topic'], AudioCustomMsg, queue_size=50)
    bridge.publish = ros_publisher.publish
    if resumed:     # a restart: the subscribers of the one before come back first
        _wait_for_subscriber(ros_publisher, RESUBSCRIBE_WAIT)
    stop = threading.Event()
    threading.Thread(target=server.serve_forever, name='websocket', daemon=True).start()
    threading.Thread(target=_stats_loop, args=(bridge, stop, rospy), name='stats',
                     daemon=True).start()
    port = server.socket.getsockname()[1]  # the real one when --port 0 let the system choose
    rospy.loginfo('listening on ws://%s:%d%s, publishing %s' % (
        opts['host'], port, ' (token required)' if opts['token'] else '',
        rospy.resolve_name(opts['topic'])))

    def shutdown() -> None:
        stop.set()
        server.shutdown()
        bridge.close_all()
        _write_stats(bridge, rospy)
    rospy.on_shutdown(shutdown)
    rospy.spin()
    return 0


def _not_advertised(msg: 'genpy.Message') -> None:
    raise RuntimeError('the topic is not advertised yet (the websocket port is bound first)')


class _RosLog:
    """Bridge's log sink: rospy's loggers (they reach stderr and /rosout)."""

    def __init__(self, rospy: 'ModuleType') -> None:
        self.info, self.warning = rospy.loginfo, rospy.logwarn
