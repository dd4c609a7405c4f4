"""Test driver: the real scripts/naoqiAudio under the robot's Python 2.7, with a stand-in for NAOqi.

    python2.7 naoqi27_standin.py FED.raw SAMPLES_PER_BUFFER -- [naoqiAudio options]

Runs scripts/naoqiAudio itself (its ``main``: options, token, NAOqi link, capture, websocket
sender, signals, exit), with a stand-in ``qi`` module in place of the NAOqi SDK's: ``qi`` for
Python 2.7 (PyPI's 1.8.3) needs OpenSSL 1.0, which Debian 12 lacks, so a session and an
ALAudioDevice are stood in for here, in this test driver only. The qi path itself is tested
with qi 3.1.5 against naoqiEndpoint (test_audio_bridge.py).

The stand-in ALAudioDevice does what NAOqi does for a module that subscribed with
``setClientPreferences(name, 48000, 0, 0)`` (all four channels, 48 kHz, interleaved): it calls the
registered service's ``processRemote(nbOfChannels, nbOfSamplesByChannel, timeStamp, buffer)``
once per buffer, in real time, from a thread of its own. As NAOqi passes them to a Python 2
module: two ints, the timestamp as [seconds, microseconds] (the wall-clock time of the buffer's
first sample here), and the samples as one ``str`` of int16 little-endian bytes, interleaved
(ros-naoqi/naoqi_driver src/event/audio.cpp:175-184 at aed1b87 reads the same argument as raw
bytes, nbOfChannels x samplesByChannel int16; ricardodeazambuja/pepper-demo2017
microphone_working.py, a NAOqi Python 2 module, writes ``inputBuff`` to a file as it comes and
reads the timestamp as timeStamp[0] + timeStamp[1] / 1e6). NAOqi's own buffers are 170 ms
(doc.aldebaran.com/2-4/naoqi/audio/alaudiodevice.html, "Performances and Limitations": four
channels interleaved, 48000 Hz, 170 ms buffer): SAMPLES_PER_BUFFER 8192 is 170.7 ms.

The samples are FED.raw, four interleaved int16 channels, cut into buffers in order, each fed
once; when all are fed, feeding stops. Lines on stdout: "standin: Python X.Y.Z", "standin: subscribed NAME ...",
"standin: fed all N buffer(s)", "standin: unsubscribed NAME after N buffer(s)".
Python 2.7 and 3 (no f-strings, no annotations).
"""
import os
import runpy
import sys
import threading
import time
import types

CHANNELS = 4
RATE = 48000
HERE = os.path.dirname(os.path.abspath(__file__))
NAOQI_AUDIO = os.path.join(HERE, '..', '..', 'scripts', 'naoqiAudio')


def say(text):
    sys.stdout.write('standin: %s\n' % text)
    sys.stdout.flush()


class Naoqi(object):
    """The robot's side: the services registered with it and its ALAudioDevice."""

    def __init__(self, data, samples):
        self.services = {}      # name -> service object
        self.ids = {}           # service id -> name
        self.audio = AudioDevice(self, data, samples)


class AudioDevice(object):
    """ALAudioDevice: setClientPreferences, subscribe, unsubscribe; feeds one module."""

    def __init__(self, naoqi, data, samples):
        self.naoqi, self.data, self.samples = naoqi, data, samples
        self.fed = 0
        self._prefs = {}
        self._stop = threading.Event()
        self._thread = None

    def setClientPreferences(self, name, rate, channels, deinterleaved):
        if (channels, deinterleaved) != (0, 0):
            raise RuntimeError('this stand-in gives only what naoqiAudio asks by default: all '
                               'channels (0), interleaved (0); asked %r, %r'
                               % (channels, deinterleaved))
        self._prefs[name] = rate

    def subscribe(self, name):
        if name not in self._prefs:
            raise RuntimeError('%s: setClientPreferences first' % name)
        module = self.naoqi.services[name]
        say('subscribed %s: %d ch, %d Hz, interleaved, %d samples per buffer'
            % (name, CHANNELS, RATE, self.samples))
        self._stop.clear()
        self._thread = threading.Thread(target=self._feed, args=(module,))
        self._thread.daemon = True
        self._thread.start()

    def unsubscribe(self, name):
        self._stop.set()
        if self._thread is not None:
            self._thread.join(5.0)
            self._thread = None
            say('unsubscribed %s after %d buffer(s)' % (name, self.fed))

    def _feed(self, module):
        size = CHANNELS * self.samples * 2
        period = float(self.samples) / RATE
        start = time.time()
        while self.fed * size < len(self.data):
            due = start + self.fed * period
            if self._stop.wait(max(0.0, due - time.time())):
                return
            buf = self.data[self.fed * size:(self.fed + 1) * size]
            sec = int(due)
            module.processRemote(CHANNELS, self.samples, [sec, int((due - sec) * 1e6)], buf)
            self.fed += 1
        say('fed all %d buffer(s)' % self.fed)


class Session(object):
    """qi.Session: connect, listen, registerService, service, unregisterService, close."""

    naoqi = None    # the one Naoqi every session reaches (standin_qi)

    def connect(self, url):
        say('session connected to %s' % url)

    def listen(self, url):
        pass

    def isConnected(self):
        return True

    def registerService(self, name, obj):
        if name in self.naoqi.services:
            raise RuntimeError('Service "%s" is already registered' % name)
        self.naoqi.services[name] = obj
        sid = max(self.naoqi.ids or [0]) + 1
        self.naoqi.ids[sid] = name
        return sid

    def unregisterService(self, sid):
        self.naoqi.services.pop(self.naoqi.ids.pop(sid), None)

    def service(self, name):
        if name != 'ALAudioDevice':
            raise RuntimeError('no service %s in this stand-in' % name)
        return self.naoqi.audio

    def services(self):
        return [{'name': n} for n in self.naoqi.services]

    def close(self):
        pass


def standin_qi(data, samples):
    """The stand-in ``qi`` module."""
    qi = types.ModuleType('qi')
    qi.Session = Session
    qi.Application = lambda args, raw=False: None
    Session.naoqi = Naoqi(data, samples)
    return qi


def main():
    args = sys.argv[1:]
    split = args.index('--')
    raw, samples = args[0], int(args[1])
    with open(raw, 'rb') as f:
        data = f.read()
    say('Python %s' % sys.version.split()[0])
    sys.modules['qi'] = standin_qi(data, samples)
    sys.argv = [NAOQI_AUDIO] + args[split + 1:]
    runpy.run_path(NAOQI_AUDIO, run_name='__main__')


if __name__ == '__main__':
    main()
