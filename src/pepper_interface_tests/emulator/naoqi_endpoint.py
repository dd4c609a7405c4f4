"""A NAOqi-protocol endpoint on loopback: ALAudioDevice and ALTextToSpeech, backed by AudioSource.

It is a real libqi service directory (``qi.Application`` with ``--qi-standalone``), so the
capture side talks to it exactly as to a robot. Behaviour follows NAOqi 2.5's ALAudioDevice:

- ``setClientPreferences(module, sampleRate, channelsFlag, deinterleaved)``: channelsFlag
  ALL=0 gives 4 channels at 48000 Hz (the only rate NAOqi offers for all channels); LEFT=1,
  RIGHT=2, FRONT=3, REAR=4 give one channel at 16000 Hz (emulator choice: LEFT = frontLeft,
  RIGHT = frontRight, FRONT = mean of the front pair, REAR = mean of the rear pair; decimated by
  3, so buffers hold 1365 or 1366 samples). The requested sampleRate is otherwise ignored, as
  NAOqi ties the rate to the flag.
- ``subscribe(module)`` / ``unsubscribe(module)``: while subscribed, the service registered under
  the name ``module`` receives ``processRemote(nbOfChannels, nbOfSamplesByChannel,
  [sec, usec], buffer)`` every 4096 samples (85.3 ms) at real-time pace, scheduled by absolute
  time (no drift); buffer is int16 LE, planar when deinterleaved else interleaved; the timestamp
  is the wall-clock time of the buffer's first sample. Several subscribers may be active; each
  has its own delivery thread, so a slow one does not hold up the others.
- ``ALTextToSpeech.say(text)`` mixes the spoken text into the microphone stream (returns when
  queued).
"""
import argparse
import collections
import logging
import os
import signal
import socket
import sys
import threading
import time
from typing import Any, Dict, NoReturn, Optional, Sequence, Tuple

import numpy as np

from pepper_interface_tests.audio_bridge import OneLineParser, RateLimiter, listen_port_arg, without_remappings
from pepper_interface_tests.emulator.audio_source import CHANNEL_NAMES, AudioSource
from pepper_interface_tests.emulator.network import NETWORKS, Network, network_of

LOG = logging.getLogger('naoqiEndpoint')
BUFFER_SAMPLES = 4096
RATE_ALL = 48000
RATE_SINGLE = 16000
CHANNEL_FLAGS = {0: 'ALL', 1: 'LEFT', 2: 'RIGHT', 3: 'FRONT', 4: 'REAR'}
# Channel indices mixed for the single-channel flags (rearLeft, rearRight, frontLeft, frontRight).
SINGLE_CHANNEL_MIX = {1: (2,), 2: (3,), 3: (2, 3), 4: (0, 1)}
SUBSCRIBER_QUEUE = 8


class Subscriber:
    """One subscribed module: its preferences, decimation state and delivery thread."""

    network: Optional[Network] = None     # --network wifi: deliveries wait for its holds

    def __init__(self, session: Any, name: str, flag: int, planar: bool, polled: bool = False) -> None:
        self.session, self.name, self.flag, self.planar = session, name, flag, planar
        self._carry = np.zeros(0, dtype=np.float64)
        self._queue: collections.deque = collections.deque()
        self._cond = threading.Condition()
        self._stopped = False
        self._proxy: Any = None      # the subscriber's service once found (a qi object)
        self._limiter = RateLimiter(5.0)
        self.delivered = 0
        if not polled:    # polled: a relay takes the buffers (take()) and calls processRemote
            threading.Thread(target=self._run, name='deliver-' + name, daemon=True).start()

    def push(self, block: np.ndarray, ts: Tuple[int, int]) -> None:
        """Format one 4-channel 48 kHz block per this subscriber's preferences and queue it."""
        if self.flag == 0:
            data = np.ascontiguousarray(block.T) if self.planar else block
            item = (4, block.shape[0], ts, data.astype('<i2').tobytes())
        else:
            mono = block[:, SINGLE_CHANNEL_MIX[self.flag]].astype(np.float64).mean(axis=1)
            x = np.concatenate([self._carry, mono])
            usable = len(x) // 3 * 3
            self._carry = x[usable:]
            out = np.rint(x[:usable].reshape(-1, 3).mean(axis=1)).astype('<i2')
            item = (1, len(out), ts, out.tobytes())
        with self._cond:
            if len(self._queue) >= SUBSCRIBER_QUEUE:
                self._queue.popleft()
                n = self._limiter.hit('overflow')
                if n:
                    LOG.warning('%s is not keeping up: dropped %d buffer(s)', self.name, n)
            self._queue.append(item)
            self._cond.notify()

    def stop(self) -> None:
        with self._cond:
            self._stopped = True
            self._cond.notify()

    def take(self, timeout: float) -> Optional[Tuple[int, int, Tuple[int, int], bytes]]:
        """The next queued buffer (nbOfChannels, samplesByChannel, (sec, usec), int16 bytes),
        waiting up to `timeout` s; None when none came or the subscriber stopped."""
        with self._cond:
            if not self._queue and not self._stopped:
                self._cond.wait(timeout)
            if self._stopped or not self._queue:
                return None
            self.delivered += 1
            item = self._queue.popleft()
        held = self.network.wait(time.monotonic()) if self.network is not None else 0.0
        if held > 0:
            time.sleep(held)          # a busy WiFi holds the buffer (network.py)
        return item

    def _run(self) -> None:
        while True:
            with self._cond:
                while not self._queue and not self._stopped:
                    self._cond.wait()
                if self._stopped:
                    return
                nch, nsamp, ts, payload = self._queue.popleft()
            held = self.network.wait(time.monotonic()) if self.network is not None else 0.0
            if held > 0:
                time.sleep(held)      # a busy WiFi holds the buffer; the next ones follow at once
            try:
                if self._proxy is None:
                    self._proxy = self.session.service(self.name)
                self._proxy.processRemote(nch, nsamp, list(ts), payload)
                self.delivered += 1
            except Exception as exc:  # the subscriber's process went away or misbehaves
                self._proxy = None
                n = self._limiter.hit('call')
                if n:
                    LOG.warning('processRemote on %r failed (%d time(s) in the last 5 s): %s',
                                self.name, n, str(exc).splitlines()[0] if str(exc) else exc)


class AudioDevice:
    """The engine behind the ALAudioDevice service: the real-time pump and the subscribers."""

    def __init__(self, session: Any, source: AudioSource) -> None:
        self.session, self.source = session, source
        self.prefs: Dict[str, Tuple[int, bool]] = {}
        self.subscribers: Dict[str, Subscriber] = {}
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._pump, name='pump', daemon=True)

    def start(self) -> None:
        self._thread.start()

    def stop(self) -> None:
        self._stop.set()
        self._thread.join(5)
        with self._lock:
            for sub in self.subscribers.values():
                sub.stop()
            self.subscribers.clear()

    def set_preferences(self, module: str, rate: int, flag: int, deinterleaved: bool) -> None:
        flag = int(flag)
        if flag not in CHANNEL_FLAGS:
            raise RuntimeError('ALAudioDevice::setClientPreferences: channelsFlag %d is not one '
                               'of 0 (ALL), 1 (LEFT), 2 (RIGHT), 3 (FRONT), 4 (REAR)' % flag)
        wanted = RATE_ALL if flag == 0 else RATE_SINGLE
        if int(rate) != wanted:
            LOG.info('%s asked for %d Hz with channels %s: NAOqi gives %d Hz', module, rate,
                     CHANNEL_FLAGS[flag], wanted)
        with self._lock:
            self.prefs[module] = (flag, bool(deinterleaved))

    def subscribe(self, module: str, polled: bool = False) -> None:
        with self._lock:
            flag, planar = self.prefs.get(module, (0, False))
            old = self.subscribers.pop(module, None)
            if old:
                old.stop()
            self.subscribers[module] = Subscriber(self.session, module, flag, planar, polled)
        LOG.info('%s subscribed: channels %s, %s', module, CHANNEL_FLAGS[flag],
                 'planar' if planar else 'interleaved')

    def unsubscribe(self, module: str) -> None:
        with self._lock:
            sub = self.subscribers.pop(module, None)
        if sub is None:
            raise RuntimeError('ALAudioDevice::unsubscribe: %r is not subscribed' % module)
        sub.stop()
        LOG.info('%s unsubscribed after %d buffers', module, sub.delivered)

    def _pump(self) -> None:
        """Read one buffer per 4096/48000 s, scheduled on absolute time, and fan it out."""
        period = BUFFER_SAMPLES / float(RATE_ALL)
        t0, wall0, i = time.monotonic(), time.time(), 0
        while not self._stop.is_set():
            due = t0 + (i + 1) * period  # a buffer is available once its last sample exists
            lag = time.monotonic() - due
            if lag < 0:
                if self._stop.wait(-lag):
                    return
            elif lag > 2.0:
                LOG.warning('pump fell %.1f s behind real time (machine overloaded?): '
                            'skipping ahead', lag)
                skip = int(lag / period)
                self.source.read(skip * BUFFER_SAMPLES)
                i += skip
                continue
            block = self.source.read(BUFFER_SAMPLES)
            start = wall0 + i * period
            ts = (int(start), int(round((start - int(start)) * 1e6)) % 1000000)
            with self._lock:
                subs = list(self.subscribers.values())
            for sub in subs:
                sub.push(block, ts)
            i += 1


class ALAudioDeviceService:
    """What NAOqi clients see as ALAudioDevice."""

    def __init__(self, device: AudioDevice) -> None:
        self._device = device

    def setClientPreferences(self, module: str, sampleRate: int, channelsFlag: int, deinterleaved: bool) -> None:
        self._device.set_preferences(str(module), sampleRate, channelsFlag, deinterleaved)

    def subscribe(self, module: str) -> None:
        self._device.subscribe(str(module))

    def unsubscribe(self, module: str) -> None:
        self._device.unsubscribe(str(module))


class PolledAudioService:
    """ALAudioDevice for a relay (tools/real-driver/relay/audio_relay.cpp), registered as
    FakeAudioFrames: a Python caller cannot send processRemote's buffer as Raw (qi 3.1.5 hands a
    bytes argument over as its str() text), so the relay takes each buffer with next(), whose
    return is typed with a Raw member, and calls the subscriber's processRemote itself."""

    SIGNATURE = '(iiiir)'    # nbOfChannels, samplesByChannel, sec, usec, buffer

    def __init__(self, device: AudioDevice) -> None:
        self._device = device

    def setClientPreferences(self, module: str, sampleRate: int, channelsFlag: int, deinterleaved: bool) -> None:
        self._device.set_preferences(str(module), sampleRate, channelsFlag, deinterleaved)

    def subscribe(self, module: str) -> None:
        self._device.subscribe(str(module), polled=True)

    def unsubscribe(self, module: str) -> None:
        self._device.unsubscribe(str(module))

    def next_buffer(self, module: str) -> Tuple[int, int, int, int, bytes]:
        """The subscriber's next buffer, at real-time pace (waits up to 1 s); raises when the
        module is not subscribed or no buffer came."""
        with self._device._lock:
            sub = self._device.subscribers.get(str(module))
        item = sub.take(1.0) if sub is not None else None
        if item is None:
            raise RuntimeError('ALAudioDevice: no buffer for %r (not subscribed)' % module)
        nch, nsamp, (sec, usec), payload = item
        return (nch, nsamp, sec, usec, payload)


class ALTextToSpeechService:
    """What NAOqi clients see as ALTextToSpeech: the words end up in the microphone stream."""

    def __init__(self, source: AudioSource) -> None:
        self._source = source

    def say(self, text: str) -> None:
        LOG.info('say %r', text)
        self._source.say(str(text))


def _host(value: str) -> str:
    try:
        socket.inet_aton(value)
    except (OSError, ValueError):
        raise argparse.ArgumentTypeError('%r is not an IPv4 address' % value) from None
    if value.count('.') != 3:
        raise argparse.ArgumentTypeError('%r is not a dotted IPv4 address' % value)
    return value


def parse_args(argv: Sequence[str]) -> argparse.Namespace:
    p = OneLineParser(prog='naoqiEndpoint', description=__doc__.split('\n')[0])
    p.add_argument('--port', type=listen_port_arg, default=9559,
                   help='TCP port (default 9559; 0 = any free port, the ready line says which)')
    p.add_argument('--host', type=_host, default='127.0.0.1',
                   help='address to listen on (default 127.0.0.1)')
    p.add_argument('--pattern', choices=('tones', 'counter'), default='tones',
                   help='microphone signal: per-channel tones or the sample-exact counter')
    p.add_argument('--silent-channel', action='append', default=[], choices=CHANNEL_NAMES,
                   metavar='NAME', help='a dead microphone (all zeros); repeatable; one of '
                   + ', '.join(CHANNEL_NAMES))
    p.add_argument('--seed', type=int, default=0, help='noise seed (default 0)')
    p.add_argument('--network', choices=NETWORKS, default='none',
                   help='none, or wifi: buffers wait for a busy WiFi\'s holds (network.py)')
    return p.parse_args(argv)


def _start_qi(url: str) -> Any:
    import qi
    logging_mod = getattr(qi, 'logging', None)
    if logging_mod is not None and hasattr(logging_mod, 'setFilters'):
        logging_mod.setFilters('-qi.path.sdklayout')
    app = qi.Application([sys.argv[0] or 'naoqiEndpoint', '--qi-listen-url=' + url,
                          '--qi-standalone', '--qi-log-level=warning'])
    app.start()
    return app


def main(argv: Optional[Sequence[str]] = None) -> int:
    args = parse_args(without_remappings(sys.argv[1:] if argv is None else argv))
    logging.basicConfig(level=logging.INFO, stream=sys.stderr,
                        format='naoqiEndpoint: %(levelname)s: %(message)s')
    url = 'tcp://%s:%d' % (args.host, args.port)
    stop = threading.Event()
    signal.signal(signal.SIGINT, lambda *_: stop.set())
    signal.signal(signal.SIGTERM, lambda *_: stop.set())
    try:
        app = _start_qi(url)
    except RuntimeError as exc:
        sys.stderr.write('naoqiEndpoint: cannot listen on %s: %s\n'
                         % (url, str(exc).splitlines()[0] if str(exc) else 'error'))
        return 1
    source = AudioSource(pattern=args.pattern, silent_channels=tuple(args.silent_channel),
                         seed=args.seed)
    Subscriber.network = network_of(args.network, args.seed)
    device = AudioDevice(app.session, source)
    ids = [app.session.registerService('ALAudioDevice', ALAudioDeviceService(device)),
           app.session.registerService('ALTextToSpeech', ALTextToSpeechService(source))]
    device.start()
    bound = [u for u in app.session.endpoints() if u.startswith('tcp://%s:' % args.host)]
    sys.stdout.write('NAOqi endpoint ready on %s\n' % (bound[0] if bound else url))
    sys.stdout.flush()
    while not stop.wait(0.5):
        pass
    LOG.info('shutting down')
    device.stop()
    for sid in ids:
        try:
            app.session.unregisterService(sid)
        except RuntimeError:
            pass
    app.stop()
    return exit_now(0)


def exit_now(code: int) -> NoReturn:
    """Flush and leave without interpreter teardown: libqi-python (3.1.5) can deadlock when
    Python finalizes its Application (its event loop waits for the GIL the finalizer holds)."""
    logging.shutdown()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)
