"""pepperEmulator: a Pepper robot (naoqi_driver) or Gazebo simulator that publishes every sensor
topic with plausible, moving content, optionally with injected faults.

Private params (each also a command-line option, which wins):
  ~profile            robot | simulator                       (robot)
  ~realsense          publish the RealSense D435i topics too    (false; robot profile only)
  ~audio              bridge | direct | off                   (bridge; robot profile only)
                      bridge: /naoqi_driver/audio comes from naoqiAudio + naoqiAudioPublisher;
                      direct: the emulator publishes AudioCustomMsg itself; off: no microphone
  ~naoqi_url          NAOqi endpoint for /speech            (tcp://127.0.0.1:9559)
  ~faults             fault string, see faults.py / docs/emulator.md   ('')
  ~rate_factor        multiplies every rate                   (1.0)
  ~camera_resolution  QQVGA | QVGA | VGA for the front/bottom cameras; the depth camera follows
                      up to QVGA (its maximum)                (QVGA; robot profile only)
  ~topics_file        topics file (default data/pepperTopics.dat or data/simulatorTopics.dat)
  ~seed               seed of the noise generators            (0)
Exit codes: 0 after a normal shutdown, 2 when it could not start (bad params, no master).
"""
import argparse
import sys
import threading

import rosgraph
import rospy
from std_msgs.msg import String

from .. import settings
from . import faults as faults_mod
from .faults import FaultError, parse_faults
from .profiles import AUDIO_MODES, PROFILES, RESOLUTIONS, build_profile
from .publishers import KINDS, AudioPublisher, Clock
from .speech import DirectSpeech, NaoqiSpeech

NODE_NAME = 'pepperEmulator'
DEFAULTS = dict(profile='robot', realsense=False, audio='bridge', naoqi_url='tcp://127.0.0.1:9559',
                faults='', rate_factor=1.0, camera_resolution='QVGA', topics_file='', seed=0,
                audio_pattern='tones')


class EmulatorConfig(object):
    """Validated settings of one emulator run (read once)."""

    def __init__(self, values):
        v = dict(DEFAULTS)
        v.update({k: val for k, val in values.items() if val is not None})
        self.profile = settings.choice(v['profile'], PROFILES, '~profile')
        self.realsense = settings.parse_bool(v['realsense'], key='~realsense')
        self.audio = settings.choice(v['audio'], AUDIO_MODES, '~audio')
        self.naoqi_url = str(v['naoqi_url'])
        try:
            self.rate_factor = float(v['rate_factor'])
        except (TypeError, ValueError):
            self.rate_factor = -1.0
        if not 0 < self.rate_factor < 1000:
            raise settings.ConfigError('~rate_factor "%s" is not a positive number' % v['rate_factor'],
                                       fix='give e.g. 1.0 (nominal rates) or 0.5 (half)')
        res = str(v['camera_resolution']).upper()
        if res not in RESOLUTIONS:
            raise settings.ConfigError('~camera_resolution "%s" is not valid' % v['camera_resolution'],
                                       fix='use one of: ' + ', '.join(RESOLUTIONS))
        self.camera_resolution = res
        self.seed = int(v['seed'])
        self.audio_pattern = settings.choice(v['audio_pattern'], ('tones', 'counter'), '~audio_pattern')
        self.ignored = []
        if self.profile == 'simulator':
            if self.realsense:
                self.ignored.append('~realsense (the simulator has no RealSense camera)')
            self.audio = 'off'
            self.realsense = False
        self.profile_spec = build_profile(self.profile, v['topics_file'] or None, self.realsense,
                                          self.audio, self.camera_resolution)
        self.faults = parse_faults(v['faults'])
        published = [s.name for s in self.profile_spec.sensors]
        for name in self.faults:
            if name in published:
                continue
            if name == 'microphone' and self.profile == 'robot' and self.audio == 'bridge':
                raise FaultError('microphone faults need ~audio direct (with the audio bridge the '
                                 'microphones come from naoqiEndpoint: give it --silent-channel, '
                                 'or the launch arg silent_channel)')
            hint = ''
            if name.startswith('realsense') and self.profile == 'robot':
                hint = ' (set ~realsense true to publish the RealSense topics)'
            raise FaultError('sensor "%s" is not published by this emulator (%s profile%s)%s; '
                             'sensors published: %s' % (name, self.profile,
                                                        ', audio %s' % self.audio
                                                        if self.profile == 'robot' else '',
                                                        hint, ', '.join(published)))


def _params():
    out = {}
    for key in DEFAULTS:
        if rospy.has_param('~' + key):
            out[key] = rospy.get_param('~' + key)
    return out


def _parser():
    p = argparse.ArgumentParser(prog=NODE_NAME, description=__doc__.split('\n')[0])
    p.add_argument('--profile', choices=PROFILES)
    p.add_argument('--realsense', choices=('true', 'false'))
    p.add_argument('--audio', choices=AUDIO_MODES)
    p.add_argument('--naoqi-url', dest='naoqi_url')
    p.add_argument('--faults')
    p.add_argument('--rate-factor', dest='rate_factor', type=float)
    p.add_argument('--camera-resolution', dest='camera_resolution')
    p.add_argument('--topics-file', dest='topics_file')
    p.add_argument('--seed', type=int)
    p.add_argument('--audio-pattern', dest='audio_pattern', choices=('tones', 'counter'))
    p.add_argument('--list-faults', action='store_true', help='print the fault syntax and exit')
    return p


class Emulator(object):
    """Owns the publisher threads, the speech relay and the audio source of one run."""

    def __init__(self, config):
        self.config = config
        self.stop_event = threading.Event()
        self.clock = Clock()
        self.threads = []
        self.source = None
        self.speech = None
        self.speech_sub = None

    def start(self):
        cfg = self.config
        for i, spec in enumerate(cfg.profile_spec.sensors):
            fault = cfg.faults.get(spec.name)
            cls = KINDS[spec.kind]
            seed = cfg.seed * 1000 + i
            if cls is AudioPublisher:
                from .audio_source import AudioSource
                channels = fault.silent_channel if fault else ()
                self.source = AudioSource(rate=48000, channels=4, pattern=cfg.audio_pattern,
                                          silent_channels=channels, seed=cfg.seed)
                pub = cls(spec, fault, self.clock, self.stop_event, cfg.rate_factor, seed,
                          source=self.source)
            else:
                pub = cls(spec, fault, self.clock, self.stop_event, cfg.rate_factor, seed)
            self.threads.append(pub)
        topic = cfg.profile_spec.speech_topic
        if topic:
            if self.source is not None:
                self.speech = DirectSpeech(self.source)
            else:
                self.speech = NaoqiSpeech(cfg.naoqi_url)
            self.speech_sub = rospy.Subscriber(topic, String, self._on_speech, queue_size=10)
        for t in self.threads:
            t.start()

    def _on_speech(self, msg):
        rospy.loginfo('pepperEmulator: /speech "%s"', msg.data)
        self.speech.say(msg.data)

    def summary_line(self):
        cfg = self.config
        topics = sum(1 + len(t.spec.extra) for t in self.threads)
        faults = faults_mod.format_faults(cfg.faults) or 'none'
        extra = ''
        if cfg.profile == 'robot':
            extra = ', audio %s, realsense %s, cameras %s' % (
                cfg.audio, 'on' if cfg.realsense else 'off', cfg.camera_resolution)
        return ('pepperEmulator: all %d publishers up (%d topics, %s profile%s, rate factor %g, '
                'faults: %s)' % (len(self.threads), topics, cfg.profile, extra, cfg.rate_factor,
                                 faults))

    def stop(self):
        self.stop_event.set()
        for t in self.threads:
            t.join(2.0)
        for t in self.threads:
            try:
                t.close()
            except Exception:
                pass
        if self.speech_sub is not None:
            self.speech_sub.unregister()
        if self.speech is not None:
            self.speech.close()


def main(argv=None):
    argv = rospy.myargv(sys.argv if argv is None else argv)
    args = _parser().parse_args(argv[1:])
    if args.list_faults:
        print(faults_mod.__doc__)
        print('sensors: ' + faults_mod.valid_sensors())
        print('faults:  ' + faults_mod.valid_faults())
        return 0
    master = rosgraph.Master('/' + NODE_NAME)
    if not master.is_online():
        print('%s: error: no ROS master at %s (start roscore first)'
              % (NODE_NAME, rosgraph.get_master_uri()), file=sys.stderr)
        return 2
    rospy.init_node(NODE_NAME)
    values = _params()
    values.update({k: v for k, v in vars(args).items() if v is not None and k != 'list_faults'})
    try:
        config = EmulatorConfig(values)
    except (settings.ConfigError, FaultError) as e:
        print('%s: error: %s' % (NODE_NAME, e), file=sys.stderr)
        rospy.signal_shutdown('bad configuration')
        return 2
    emulator = Emulator(config)
    emulator.start()
    for note in config.profile_spec.notes:
        rospy.loginfo('pepperEmulator: %s', note)
    for what in config.ignored:
        rospy.logwarn('pepperEmulator: ignored %s', what)
    rospy.loginfo(emulator.summary_line())      # the one "ready" line (terminal and /rosout)
    try:
        rospy.spin()
    finally:
        emulator.stop()
        counts = ', '.join('%s %d' % (t.spec.name, t.published) for t in emulator.threads)
        print('pepperEmulator: stopped; messages published: %s' % counts, flush=True)
    return 0


if __name__ == '__main__':
    sys.exit(main())
