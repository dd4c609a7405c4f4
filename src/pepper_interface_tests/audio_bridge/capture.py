"""Capture side of the audio bridge: NAOqi ALAudioDevice buffers -> websocket frames.

Runs wherever ``qi`` reaches NAOqi, including on the robot under Python 2.7 with the NAOqi SDK
(keep this file Python 2.7 compatible: no f-strings, annotations, nonlocal, ``time.monotonic``,
``Thread(daemon=...)``; no ROS imports). It

- registers a service (``--module-name``, default SoundProcessingModule) whose ``processRemote``
  receives the buffers, then calls ``ALAudioDevice.setClientPreferences(name, 48000, 0, 0)``
  (all channels, interleaved: what naoqi_driver asks for, ros-naoqi/naoqi_driver
  src/event/audio.cpp:107-113; ``--planar`` asks for deinterleaved, 1) and ``subscribe(name)``;
  re-registers and re-subscribes whenever NAOqi goes away and comes back. When another process
  already holds that service name (a second capture, or the CSSR4Africa naoqi_driver's own
  naoqiAudio.py), it says so once, naming that process and the fix, and retries quietly;
- wraps every buffer in a frame (see frame.py) with a sequence number that grows by one per
  buffer and a random stream id per process start;
- sends the frames over one websocket client connection (websocket-client), reconnecting with
  backoff; while the link is down, frames wait in a queue bounded to ``--queue-seconds`` of
  audio (oldest dropped beyond that, counted and logged);
- on SIGINT/SIGTERM unsubscribes, flushes what it can for a second and exits 0.
"""
import collections
import logging
import os
import random
import select
import signal
import socket
import sys
import threading
import time

from pepper_interface_tests.audio_bridge import (
    TOKEN_FILE_ENV,
    OneLineParser,
    RateLimiter,
    TokenError,
    port_arg,
    read_token,
    without_remappings,
)
from pepper_interface_tests.audio_bridge.frame import TOKEN_HEADER, FrameError, encode_frame

LOG = logging.getLogger('naoqiAudio')
SAMPLE_RATE = 48000
CHANNELS_ALL = 0
SUMMARY_INTERVAL = 60.0


class UsageError(Exception):
    """Bad command-line value: reported as one line, exit code 2."""


class Backoff(object):
    """Exponential backoff delays: 0.5, 1, 2 ... capped at ``maximum`` seconds."""

    def __init__(self, first=0.5, maximum=8.0):
        self.first, self.maximum, self.delay = first, maximum, first

    def next(self):
        delay = self.delay
        self.delay = min(self.delay * 2, self.maximum)
        return delay

    def reset(self):
        self.delay = self.first


class FrameQueue(object):
    """Thread-safe FIFO of encoded frames holding at most ``seconds`` of audio.

    The bound is computed from each frame's duration, so it holds for any buffer size. When full,
    the oldest frames are dropped and counted in ``dropped``.
    """

    def __init__(self, seconds):
        self.seconds = seconds
        self.dropped = 0
        self._items = collections.deque()
        self._duration = 0.0
        self._cond = threading.Condition()

    def put(self, frame, duration, front=False):
        with self._cond:
            if front:
                self._items.appendleft((frame, duration))
            else:
                self._items.append((frame, duration))
            self._duration += duration
            dropped = 0
            while self._duration > self.seconds + 1e-9 and len(self._items) > 1:
                _, d = self._items.popleft()
                self._duration -= d
                dropped += 1
            self.dropped += dropped
            self._cond.notify()
            return dropped

    def get(self, timeout):
        """Oldest (frame, duration), or None after ``timeout`` seconds."""
        with self._cond:
            if not self._items:
                self._cond.wait(timeout)
            if not self._items:
                return None
            item = self._items.popleft()
            self._duration -= item[1]
            return item

    def __len__(self):
        with self._cond:
            return len(self._items)


REFUSALS = {
    401: 'HTTP 401, missing or wrong token (fix: the same token on both sides, e.g. one '
         '$%s for both)' % TOKEN_FILE_ENV,
    409: 'HTTP 409, another capture is already streaming to it (fix: stop the other naoqiAudio, '
         'or give this one its own naoqiAudioPublisher --port and --topic)',
}


class WebsocketSender(object):
    """Sends queued frames over a websocket, reconnecting with backoff; answers server pings."""

    def __init__(self, url, token, queue, stop):
        self.url, self.token, self.queue, self.stop = url, token, queue, stop
        self.sent = 0
        self.connections = 0
        self._ws = None
        self._backoff = Backoff(0.25, 2.0)
        self._limiter = RateLimiter(30.0)
        self._dropped_reported = 0
        self._thread = threading.Thread(target=self._run, name='websocket')
        self._thread.daemon = True

    def start(self):
        self._thread.start()

    def join(self, timeout):
        self._thread.join(timeout)

    def _connect(self):
        import websocket  # websocket-client; imported here so --help works without it
        header = [TOKEN_HEADER + ': ' + self.token] if self.token else []
        try:
            ws = websocket.create_connection(self.url, timeout=5, header=header)
        except Exception as exc:  # refused, unreachable, handshake rejected (401, 409) ...
            delay = self._backoff.next()
            status = getattr(exc, 'status_code', None)
            if status in (401, 409) and self._limiter.hit('status %d' % status):
                LOG.error('publisher at %s refuses this capture: %s; retrying every <= %.0f s',
                          self.url, REFUSALS[status], self._backoff.maximum)
            elif status not in (401, 409) and self._limiter.hit('connect'):
                LOG.warning('websocket %s not available (%s); retrying every <= %.0f s, '
                            '%d buffer(s) queued', self.url, _one_line(exc),
                            self._backoff.maximum, len(self.queue))
            self.stop.wait(delay)
            return None
        self._backoff.reset()
        self.connections += 1
        LOG.info('websocket connected to %s (%d buffer(s) queued)', self.url, len(self.queue))
        dropped = self.queue.dropped - self._dropped_reported
        if dropped:
            LOG.warning('dropped %d buffer(s) while the websocket was down (queue full); %d in '
                        'total', dropped, self.queue.dropped)
            self._dropped_reported = self.queue.dropped
        return ws

    def _drain_incoming(self, ws):
        """Handle pings (pong is automatic) and a close from the server, without blocking."""
        while select.select([ws.sock], [], [], 0)[0]:
            opcode, _ = ws.recv_data_frame(True)
            if opcode == 0x8:  # close
                raise IOError('server closed the connection')

    def _run(self):
        while not self.stop.is_set():
            if self._ws is None:
                self._ws = self._connect()
                continue
            item = self.queue.get(0.2)
            try:
                self._drain_incoming(self._ws)
                if item is not None:
                    self._ws.send_binary(item[0])
                    self.sent += 1
            except Exception as exc:  # peer gone: keep the frame for the next connection
                if item is not None:
                    self.queue.put(item[0], item[1], front=True)
                LOG.warning('websocket connection lost (%s); reconnecting', _one_line(exc))
                self._close()
        self._flush(1.0)
        self._close()

    def _flush(self, seconds):
        """On shutdown, send what is queued for up to ``seconds``."""
        deadline = time.time() + seconds
        while self._ws is not None and time.time() < deadline:
            item = self.queue.get(0)
            if item is None:
                return
            try:
                self._ws.send_binary(item[0])
                self.sent += 1
            except Exception:
                return

    def _close(self):
        if self._ws is not None:
            try:
                self._ws.close(timeout=1)
            except Exception:
                pass
            # and the socket: once the server's close frame has been answered (by
            # recv_data_frame, which marks the client not connected), websocket-client's close()
            # does nothing, so the TCP connection stayed open and the publisher waited its
            # close timeout (10 s) for it to end
            try:
                self._ws.shutdown()
            except Exception:
                pass
            self._ws = None


def _make_module(on_buffer):
    """The NAOqi service object. Python 3 qi needs a bound signature to receive raw bytes."""
    import qi

    class SoundProcessingModule(object):
        """Receives ALAudioDevice buffers."""

        def processRemote(self, nbOfChannels, nbOfSamplesByChannel, timeStamp, buffer):
            on_buffer(nbOfChannels, nbOfSamplesByChannel, timeStamp, buffer)

    if sys.version_info[0] >= 3 and hasattr(qi, 'bind'):
        # Without it qi 3.x hands a bytes argument from another Python process over as its
        # str() text. The NAOqi Python 2 SDK passes the buffer as str (bytes): no binding there.
        SoundProcessingModule.processRemote = qi.bind(
            qi.Void, (qi.Int32, qi.Int32, qi.Dynamic, qi.Buffer))(
            SoundProcessingModule.processRemote)
    return SoundProcessingModule()


class Capture(object):
    """Turns processRemote calls into frames on the queue."""

    def __init__(self, queue, planar=False):
        self.queue, self.planar = queue, planar
        self.stream_id = random.getrandbits(32)
        self.sequence = 0
        self.received = 0
        self._limiter = RateLimiter(5.0)
        self._lock = threading.Lock()

    def on_buffer(self, nch, nsamp, ts, buf):
        with self._lock:
            seq = self.sequence
            self.sequence += 1
            self.received += 1
        if sys.version_info[0] >= 3 and isinstance(buf, str):
            return self._bad('buffer arrived as text, not bytes (qi.bind signature missing?)')
        try:
            sec, usec = int(ts[0]), int(ts[1])
        except (TypeError, ValueError, IndexError):
            sec, usec = 0, 0
        try:
            frame = encode_frame(buf, int(nch), int(nsamp), SAMPLE_RATE, seq, sec, usec,
                                 planar=self.planar, stream_id=self.stream_id)
        except FrameError as exc:
            return self._bad(str(exc))
        dropped = self.queue.put(frame, float(nsamp) / SAMPLE_RATE)
        if dropped and self._limiter.hit('overflow'):
            LOG.warning('websocket down: queue full (%.1f s of audio), %d buffer(s) dropped '
                        'so far', self.queue.seconds, self.queue.dropped)

    def _bad(self, why):
        n = self._limiter.hit('bad')
        if n:
            LOG.warning('dropping unusable NAOqi buffer (%d in the last 5 s): %s', n, why)


class NaoqiLink(object):
    """Connects to NAOqi, registers the module and subscribes; redoes it after NAOqi restarts."""

    def __init__(self, url, name, module, stop, planar=False, listen_url=None):
        self.url, self.name, self.module, self.stop, self.planar = url, name, module, stop, planar
        self.listen_url = listen_url
        self._backoff = Backoff()
        self._limiter = RateLimiter(30.0)
        self._taken_limiter = RateLimiter(300.0)

    def run(self):
        """Blocks until ``stop`` is set; leaves NAOqi unsubscribed."""
        import qi
        while not self.stop.is_set():
            session = qi.Session()
            try:
                session.connect(self.url)
            except RuntimeError as exc:
                if self._limiter.hit('connect'):
                    LOG.warning('NAOqi not reachable at %s (%s); retrying every <= %.0f s',
                                self.url, _one_line(exc), self._backoff.maximum)
                self.stop.wait(self._backoff.next())
                continue
            if self._subscribe(session):
                self._backoff.reset()
                while not self.stop.wait(0.5):
                    if not session.isConnected():
                        LOG.warning('NAOqi connection lost; reconnecting')
                        break
                if self.stop.is_set():
                    self._unsubscribe(session)
            else:
                self.stop.wait(self._backoff.next())
            _close(session)

    def _subscribe(self, session):
        if self.listen_url:
            try:
                session.listen(self.listen_url)
            except RuntimeError as exc:
                LOG.warning('cannot listen on %s for NAOqi\'s calls: %s', self.listen_url,
                            _one_line(exc))
                return False
        try:
            self._sid = session.registerService(self.name, self.module)
        except RuntimeError as exc:
            holder = _service_holder(session, self.name)
            if holder is None and 'already registered' not in str(exc):
                LOG.warning('cannot register service %r on NAOqi (%s)', self.name, _one_line(exc))
            elif self._taken_limiter.hit('taken'):
                LOG.error('a module named %r is already registered on NAOqi at %s (%s), so this '
                          'capture gets no audio. It is another audio capture: a second '
                          'naoqiAudio, or the CSSR4Africa naoqi_driver\'s own naoqiAudio.py '
                          '(its naoqi_driver.launch starts it unless launch_audio:=false). '
                          'Fix: stop the other one, or give this one another --module-name. '
                          'Retrying quietly every <= %.0f s until the name is free.', self.name,
                          self.url, holder or 'owner unknown', self._backoff.maximum)
            return False
        try:
            device = session.service('ALAudioDevice')
            try:
                device.unsubscribe(self.name)  # a stale subscription from an earlier run
            except RuntimeError:
                pass
            device.setClientPreferences(self.name, SAMPLE_RATE, CHANNELS_ALL,
                                        1 if self.planar else 0)
            device.subscribe(self.name)
        except RuntimeError as exc:
            LOG.warning('ALAudioDevice subscription failed: %s', _one_line(exc))
            return False
        LOG.info('subscribed to ALAudioDevice at %s as %r (4 ch, %d Hz, %s)', self.url,
                 self.name, SAMPLE_RATE, 'planar' if self.planar else 'interleaved')
        return True

    def _unsubscribe(self, session):
        try:
            session.service('ALAudioDevice').unsubscribe(self.name)
            session.unregisterService(self._sid)
            LOG.info('unsubscribed from ALAudioDevice')
        except RuntimeError as exc:
            LOG.warning('could not unsubscribe cleanly: %s', _one_line(exc))


def _service_holder(session, name):
    """'process P on machine M (endpoints)' of the service ``name``, or None if not listed."""
    fields = ('name', 'serviceId', 'machineId', 'processId', 'endpoints')  # qi ServiceInfo
    try:
        for info in session.services():
            if not isinstance(info, dict):  # some SDKs give the struct as a list
                info = dict(zip(fields, info))
            if info.get('name') == name:
                return 'held by process %s on machine %s, %s' % (
                    info.get('processId', '?'), str(info.get('machineId', '?'))[:8],
                    ' '.join(info.get('endpoints') or []) or 'no endpoint')
    except Exception:  # an SDK of yet another shape: the error text still says it
        pass
    return None


def _close(session):
    try:
        session.close()
    except RuntimeError:
        pass


def _one_line(exc):
    text = str(exc).strip()
    return (text.splitlines()[0] if text else exc.__class__.__name__)[:200]


def _check_host(host):
    """An IPv4 address or a resolvable host name; UsageError otherwise."""
    if host and all(part.isdigit() for part in host.split('.')):
        parts = host.split('.')
        if len(parts) != 4 or any(int(p) > 255 for p in parts):
            raise UsageError('--ip %r is not a valid IPv4 address' % host)
        return host
    try:
        socket.gethostbyname(host)
    except (socket.error, UnicodeError):
        raise UsageError('--ip %r: cannot resolve this host name' % host)
    return host


def parse_args(argv):
    p = OneLineParser(
        prog='naoqiAudio', description='Forward NAOqi ALAudioDevice buffers to a websocket '
        '(the ROS side is naoqiAudioPublisher).')
    p.add_argument('--ip', default='127.0.0.1', help='NAOqi address (default 127.0.0.1)')
    p.add_argument('--port', type=port_arg, default=9559, help='NAOqi port (default 9559)')
    p.add_argument('--ws', default='ws://127.0.0.1:9090',
                   help='websocket URL of naoqiAudioPublisher (default ws://127.0.0.1:9090)')
    p.add_argument('--token', default=None,
                   help='shared token sent in the %s handshake header; visible in ps: prefer '
                   '$%s (a file holding it) or $PEPPER_AUDIO_TOKEN' % (TOKEN_HEADER,
                                                                      TOKEN_FILE_ENV))
    p.add_argument('--token-file', default=None,
                   help='file holding the token (default: $%s)' % TOKEN_FILE_ENV)
    p.add_argument('--module-name', default='SoundProcessingModule',
                   help='name of the NAOqi service that receives the buffers')
    p.add_argument('--queue-seconds', type=float, default=2.0,
                   help='audio kept while the websocket is down (default 2.0 s)')
    p.add_argument('--listen-url', default=None,
                   help='where NAOqi reaches this side\'s service (default: tcp://127.0.0.1:0 '
                   'when NAOqi is on this machine, else libqi\'s choice), e.g. '
                   'tcp://0.0.0.0:0 when capturing from another machine')
    p.add_argument('--planar', action='store_true',
                   help='ask NAOqi for deinterleaved (planar) buffers; default interleaved, as '
                   'naoqi_driver (src/event/audio.cpp setClientPreferences(..., 0, 0))')
    p.add_argument('--interleaved', action='store_true',
                   help='ask for interleaved buffers (the default; kept for old command lines)')
    args = p.parse_args(argv)
    if not (args.ws.startswith('ws://') or args.ws.startswith('wss://')):
        p.error('--ws must be a ws:// or wss:// URL, not %r' % args.ws)
    if not 0 < args.queue_seconds <= 60:
        p.error('--queue-seconds must be in (0, 60]')
    if not args.module_name.replace('_', '').isalnum():
        p.error('--module-name must be letters, digits and underscores')
    if args.planar and args.interleaved:
        p.error('--planar and --interleaved exclude each other')
    return args


def main(argv=None):
    args = parse_args(without_remappings(sys.argv[1:] if argv is None else argv))
    logging.basicConfig(level=logging.INFO, stream=sys.stderr,
                        format='naoqiAudio: %(levelname)s: %(message)s')
    try:
        _check_host(args.ip)
        token, _, warning = read_token(args.token, args.token_file)
    except (UsageError, TokenError) as exc:
        sys.stderr.write('naoqiAudio: error: %s\n' % exc)
        return 2
    if warning:
        LOG.warning(warning)
    try:
        import qi
    except ImportError:
        sys.stderr.write('naoqiAudio: error: the NAOqi Python SDK (module qi) is not '
                         'installed\n')
        return 2
    if hasattr(getattr(qi, 'logging', None), 'setFilters'):
        qi.logging.setFilters('-qi.path.sdklayout')
    try:
        qi.Application([sys.argv[0] or 'naoqiAudio', '--qi-log-level=warning'], raw=True)
    except Exception:  # older SDKs: sessions work without an Application
        pass
    stop = threading.Event()
    signal.signal(signal.SIGINT, lambda *_: stop.set())
    signal.signal(signal.SIGTERM, lambda *_: stop.set())
    queue = FrameQueue(args.queue_seconds)
    capture = Capture(queue, planar=args.planar)
    sender = WebsocketSender(args.ws, token, queue, stop)
    sender.start()
    summary = threading.Thread(target=_summaries, args=(capture, sender, queue, stop))
    summary.daemon = True
    summary.start()
    url = 'tcp://%s:%d' % (args.ip, args.port)
    listen = args.listen_url
    if listen is None and (args.ip.startswith('127.') or args.ip == 'localhost'):
        listen = 'tcp://127.0.0.1:0'
    NaoqiLink(url, args.module_name, _make_module(capture.on_buffer), stop,
              planar=args.planar, listen_url=listen).run()
    sender.join(3.0)
    LOG.info('stopped: %d buffer(s) received, %d sent, %d dropped (queue full)',
             capture.received, sender.sent, queue.dropped)
    # Leave without interpreter teardown: libqi-python can deadlock while Python finalizes
    # its event loop (the loop thread waits for the GIL held by the finalizer).
    logging.shutdown()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(0)


def _summaries(capture, sender, queue, stop):
    """One status line a minute, so a long run shows it is alive without flooding."""
    while not stop.wait(SUMMARY_INTERVAL):
        LOG.info('%d buffer(s) received, %d sent, %d queued, %d dropped (queue full), '
                 '%d websocket connection(s)', capture.received, sender.sent, len(queue),
                 queue.dropped, sender.connections)
