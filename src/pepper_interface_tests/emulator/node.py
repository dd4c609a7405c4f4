"""pepperEmulator: a Pepper robot (naoqi_driver) or Gazebo simulator that publishes every sensor
topic with plausible, moving content, optionally with injected faults.

Private params (each also a command-line option, which wins):
  ~profile            robot | robot-stock | simulator         (robot)
                      robot: naoqi_driver as the CSSR4Africa fork runs it (AudioCustomMsg from
                      an audio bridge); robot-stock: ros-naoqi/naoqi_driver (AudioBuffer from the
                      driver); simulator: the awesomebytes Gazebo Pepper, on sim time
  ~head               stereo | xtion: Pepper 1.8 stereo head (depth 640x360 + stereo camera)
                      or Pepper 1.7 Xtion head (no stereo topic)   (stereo; robot profiles)
  ~real_time_factor   simulator: simulated seconds per wall second; the emulator sets
                      /use_sim_time and publishes /clock       (0.6)
  ~condition          normal | loaded | still | dark | resting: healthy but unusual (loaded:
                      cameras ~1.3 fps with jitter; still: the robot stands still; dark: a
                      dark room; resting: a robot in Rest mode, stiffness 0 on /diagnostics
                      and its laser frozen, as naoqi_driver publishes it)       (normal)
                      Robot profiles take naoqi_driver's motion commands (/cmd_vel,
                      /joint_angles, /move_base_simple/goal; commands.py, body.py): the
                      idle drive stops as soon as a publisher connects to one of them.
  ~network            none | wifi: a busy WiFi between robot and PC (network.py): what
                      naoqi_driver fetches and the audio wait for its holds     (none)
  ~realsense          publish the RealSense D435i topics too    (false; robot profiles only)
  ~audio              bridge | direct | off                   (robot: bridge; robot-stock: direct)
                      bridge: /naoqi_driver/audio comes from naoqiAudio + naoqiAudioPublisher;
                      direct: the emulator publishes the microphones itself (AudioCustomMsg for
                      robot, naoqi_bridge_msgs/AudioBuffer for robot-stock); off: no microphone
  ~audio_buffer       samples per channel per audio message (robot 4096, robot-stock 8192)
  ~naoqi_url          NAOqi endpoint for /speech            (tcp://127.0.0.1:9559)
  ~faults             fault string, see faults.py / docs/emulator.md   ('')
  ~rate_factor        multiplies every rate                   (1.0)
  ~camera_resolution  QQVGA | QVGA | VGA for the front/bottom cameras (robot profiles; default
                      the driver's boot_config.json: VGA for robot, QVGA for robot-stock)
  ~topics_file        topics file (default data/pepperTopics.dat or data/simulatorTopics.dat)
  ~seed               seed of the noise generators            (0)
  ~touch              robot profiles: the touch event topics (head, hands, bumpers), as a
                      driver whose boot_config.json enables them (robot-stock: true, as
                      stock naoqi_driver; robot: false, as the CSSR fork's boot_config.json)
  ~robot_id           robot profiles: the serial number (Device/DeviceList/ChestBoard/BodyId)
                      on the latched /naoqi_driver/info, as naoqi_driver publishes it (info.py)
                      (AP990370B0000000; none: no info topic, as a driver whose
                      boot_config.json disables converters.info)
  ~operator           an emulated operator follows /sensorTest/prompt and touches each zone
                      the guided check asks for                (false)
Exit codes: 0 after a normal shutdown, 2 when it could not start (bad params, no master).
"""
import argparse
import sys
import threading
from typing import TYPE_CHECKING, Any, Dict, List, Optional, Sequence, Type, Union

from .. import rosapi
from ..outputs.terminal import HelpFormatter
from ..plan import settings
from . import faults as faults_mod
from .events import EVENT_PUBLISHERS, EmulatedOperator
from .faults import FaultError, parse_faults
from .info import DEFAULT_BODY_ID, InfoPublisher, check_body_id
from .network import NETWORKS, network_of
from .profiles import AUDIO_MODES, CONDITIONS, HEADS, PROFILES, RESOLUTIONS, build_profile, default_resolution
from .publishers import AudioPublisher, Clock, ClockPublisher, JointStatePublisher, StreamPublisher, publisher_class
from .speech import DirectSpeech, NaoqiSpeech
from .tf_publisher import TfPublisher

if TYPE_CHECKING:
    from .audio_source import AudioSource
    from .commands import CommandSubscribers

NODE_NAME = 'pepperEmulator'
DEFAULTS = dict(profile='robot', realsense=False, audio='', naoqi_url='tcp://127.0.0.1:9559',
                faults='', rate_factor=1.0, camera_resolution='', topics_file='', seed=0,
                audio_pattern='tones', head='stereo', real_time_factor=0.6, condition='normal',
                audio_buffer=0, operator=False, touch='', robot_id=DEFAULT_BODY_ID, network='none')


class EmulatorConfig:
    """Validated settings of one emulator run (read once)."""

    def __init__(self, values: Dict[str, Any]) -> None:
        v: Dict[str, Any] = dict(DEFAULTS)      # param values: whatever rosparam holds
        v.update({k: val for k, val in values.items() if val is not None})
        self.profile = settings.choice(v['profile'], PROFILES, '~profile')
        self.realsense = settings.parse_bool(v['realsense'], key='~realsense')
        self.audio = settings.choice(v['audio'] or ('direct' if self.profile == 'robot-stock'
                                                    else 'bridge'), AUDIO_MODES, '~audio')
        if self.profile == 'robot-stock' and self.audio == 'bridge':
            raise settings.ConfigError(
                '~audio bridge with profile robot-stock: stock naoqi_driver publishes '
                '/naoqi_driver/audio itself, a bridge would be a second publisher',
                fix='use ~audio direct (the default for robot-stock) or off')
        self.head = settings.choice(v['head'], HEADS, '~head')
        self.condition = settings.choice(v['condition'], CONDITIONS, '~condition')
        self.network = settings.choice(v['network'], NETWORKS, '~network')
        self.real_time_factor = self._positive(v, 'real_time_factor', 'e.g. 0.6 (Gazebo slower '
                                               'than real time) or 1.0', upper=10)
        try:
            self.audio_buffer = int(v['audio_buffer'] or 0)
        except (TypeError, ValueError):
            self.audio_buffer = -1
        if not 0 <= self.audio_buffer <= 65536:
            raise settings.ConfigError('~audio_buffer "%s" is not a sample count' % v['audio_buffer'],
                                       fix='give samples per channel, e.g. 4096 or 8192 (0 = default)')
        self.naoqi_url = str(v['naoqi_url'])
        self.rate_factor = self._positive(v, 'rate_factor', 'e.g. 1.0 (nominal rates) or 0.5 (half)')
        res = str(v['camera_resolution'] or default_resolution(self.profile)).upper()
        if res not in RESOLUTIONS:
            raise settings.ConfigError('~camera_resolution "%s" is not valid' % v['camera_resolution'],
                                       fix='use one of: ' + ', '.join(RESOLUTIONS))
        self.camera_resolution = res
        self.seed = int(v['seed'])
        self.operator = settings.parse_bool(v['operator'], key='~operator')
        self.robot_id = check_body_id(v['robot_id'])
        self.audio_pattern = settings.choice(v['audio_pattern'], ('tones', 'counter'), '~audio_pattern')
        self.ignored: List[str] = []
        if self.profile == 'simulator':
            if self.realsense:
                self.ignored.append('~realsense (the simulator has no RealSense camera)')
            self.audio = 'off'
            self.realsense = False
        # '' = the driver's boot_config.json: stock enables the touch events, the CSSR fork not
        self.touch = None if v['touch'] in ('', None) else settings.parse_bool(v['touch'], key='~touch')
        self.profile_spec = build_profile(self.profile, v['topics_file'] or None, self.realsense,
                                          self.audio, self.camera_resolution, self.head,
                                          self.audio_buffer or None, self.touch)
        self.faults = parse_faults(v['faults'])
        published = [s.name for s in self.profile_spec.sensors]
        for name in self.faults:
            if name in published or name == faults_mod.ROBOT:
                continue
            if name == 'microphone' and self.profile != 'simulator' and self.audio == 'bridge':
                raise FaultError('microphone faults need ~audio direct (with the audio bridge the '
                                 'microphones come from naoqiEndpoint: give it --silent-channel, '
                                 'or the launch arg silent_channel)')
            hint = ''
            if name.startswith('realsense') and self.profile != 'simulator':
                hint = ' (set ~realsense true to publish the RealSense topics)'
            raise FaultError('sensor "%s" is not published by this emulator (%s profile%s)%s; '
                             'sensors published: %s' % (name, self.profile,
                                                        ', audio %s' % self.audio
                                                        if self.profile != 'simulator' else '',
                                                        hint, ', '.join(published)))


    @staticmethod
    def _positive(v: Dict[str, Any], key: str, example: str, upper: float = 1000) -> float:
        try:
            value = float(v[key])
        except (TypeError, ValueError):
            value = -1.0
        if not 0 < value <= upper:
            raise settings.ConfigError('~%s "%s" is not a positive number (at most %g)'
                                       % (key, v[key], upper), fix='give ' + example)
        return value


def _params() -> Dict[str, Any]:
    import rospy
    out = {}
    for key in DEFAULTS:
        if rospy.has_param('~' + key):
            out[key] = rospy.get_param('~' + key)
    return out


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog=NODE_NAME, description='A Pepper robot (naoqi_driver) or Gazebo simulator that '
        'publishes every sensor topic as the real drivers do, optionally with injected faults. '
        'The robot profiles take naoqi_driver\'s motion commands (/cmd_vel, /joint_angles, '
        '/move_base_simple/goal) and the world follows them. Each option overrides the private '
        'ROS param of the same name (~profile, ...); launch: pepperEmulator.launch.',
        epilog='examples:\n  rosrun pepper_interface_tests pepperEmulator --profile simulator\n'
               '  rosrun pepper_interface_tests pepperEmulator --head xtion --audio direct\n'
               '  rosrun pepper_interface_tests pepperEmulator --faults "laser:nan;imu:nan"\n'
               'exit codes: 0 after a normal shutdown, 2 when it could not start (bad option or '
               'param, no master)', formatter_class=HelpFormatter)
    p.add_argument('--profile', choices=PROFILES, help='robot: naoqi_driver as the CSSR4Africa fork '
                   'runs it; robot-stock: stock naoqi_driver (AudioBuffer); simulator: the awesomebytes '
                   'Gazebo Pepper on sim time (default robot)')
    p.add_argument('--head', choices=HEADS, help='robot profiles: stereo (Pepper 1.8: depth 640x360 + '
                   'stereo camera) or xtion (Pepper 1.7: no stereo topic) (default stereo)')
    p.add_argument('--realsense', choices=('true', 'false'), help='also publish the RealSense D435i '
                   'topics (robot profiles; default false)')
    p.add_argument('--audio', choices=AUDIO_MODES, help='bridge: the microphones come from naoqiAudio '
                   '+ naoqiAudioPublisher; direct: published here; off: none (default: bridge for '
                   'robot, direct for robot-stock)')
    p.add_argument('--audio-buffer', dest='audio_buffer', type=int, metavar='N', help='samples per '
                   'channel per audio message (default robot 4096, robot-stock 8192)')
    p.add_argument('--audio-pattern', dest='audio_pattern', choices=('tones', 'counter'),
                   help='microphone content: tones (default) or a sample counter (tests)')
    p.add_argument('--naoqi-url', dest='naoqi_url', metavar='URL', help='NAOqi endpoint that speaks '
                   '/speech (default tcp://127.0.0.1:9559)')
    p.add_argument('--faults', metavar='SPEC', help='faults to inject, e.g. "frontCamera:frozen;laser:nan" '
                   '(see --list-faults; default none)')
    p.add_argument('--list-faults', action='store_true', help='print the table of faults, their '
                   'values and the sensors they apply to, and exit')
    p.add_argument('--rate-factor', dest='rate_factor', type=float, metavar='F', help='multiplies every '
                   'publishing rate (default 1.0)')
    p.add_argument('--camera-resolution', dest='camera_resolution', metavar='RES', help='QQVGA, QVGA or '
                   'VGA for the front/bottom cameras (default: the driver\'s boot_config.json, VGA for '
                   'robot, QVGA for robot-stock)')
    p.add_argument('--real-time-factor', dest='real_time_factor', type=float, metavar='F',
                   help='simulator: simulated seconds per wall second on /clock (default 0.6)')
    p.add_argument('--condition', choices=CONDITIONS, help='healthy but unusual: loaded (cameras '
                   '~1.3 fps with jitter), still (the robot stands still), dark (a dark room), '
                   'resting (Rest mode: stiffness 0, the laser frozen) (default normal)')
    p.add_argument('--network', choices=NETWORKS, help='none, or wifi: what naoqi_driver fetches and '
                   'the audio waits now and then for a busy WiFi (holds of 0.30-0.45 s every '
                   '1.5-3.5 s; docs/emulator.md) (default none)')
    p.add_argument('--topics-file', dest='topics_file', metavar='FILE', help='topics file (default '
                   'data/pepperTopics.dat, or data/simulatorTopics.dat for the simulator)')
    p.add_argument('--seed', type=int, help='seed of the noise generators (default 0)')
    p.add_argument('--robot-id', dest='robot_id', help='robot profiles: the serial number on the latched '
                   '/naoqi_driver/info (default %s; none: no info topic)' % DEFAULT_BODY_ID)
    p.add_argument('--touch', choices=('true', 'false'), help='robot profiles: publish the touch '
                   'events (head, hands, bumpers) as a driver whose boot_config.json enables them '
                   '(default: robot-stock true as stock naoqi_driver, robot false as the CSSR fork)')
    p.add_argument('--operator', choices=('true', 'false'), help='an emulated operator who touches '
                   'each zone sensorTest\'s guided check asks for on /sensorTest/prompt (default false)')
    return p


class Emulator:
    """Owns the publisher threads, the speech relay and the audio source of one run."""

    def __init__(self, config: EmulatorConfig) -> None:
        self.config = config
        self.stop_event = threading.Event()
        sim = config.profile_spec.sim_time
        self.clock = Clock(config.real_time_factor if sim else None)
        self.clock_thread: Optional[ClockPublisher] = None
        self.set_sim_time = False
        self.threads: List[StreamPublisher] = []
        self.source: Optional[AudioSource] = None
        self.speech: Optional[Union[DirectSpeech, NaoqiSpeech]] = None
        self.speech_sub: Any = None
        self.operator: Optional[EmulatedOperator] = None
        self.commands: Optional[CommandSubscribers] = None
        self.info: Optional[InfoPublisher] = None
        robot = config.faults.get(faults_mod.ROBOT, faults_mod.HEALTHY)
        from .body import Body
        # a glass pane ahead of the start pose (frontSonar:glass): the robot stands before it
        glass = any(f.glass for f in config.faults.values())
        # ~condition resting and robot:resting are one state: the robot in Rest mode
        self.resting = robot.resting or config.condition == 'resting'
        self.body = Body(idle=config.condition != 'still' and not glass, seed=config.seed, resting=self.resting,
                         base_blocked=robot.base_blocked, obstacle=robot.obstacle)
        self.network = network_of(config.network, config.seed)   # network.py: one for every stream

    def start(self) -> None:
        cfg = self.config
        self.body.log = lambda text: rosapi.loginfo('pepperEmulator: %s', text)
        if not self.clock.sim:
            # naoqi_driver's subscribers (src/naoqi_driver.cpp:933-940); the simulator takes
            # /pepper/cmd_vel and trajectory actions instead (docs/drivers.md), not emulated
            from .commands import CommandSubscribers
            robot = cfg.faults.get(faults_mod.ROBOT, faults_mod.HEALTHY)
            self.commands = CommandSubscribers(self.body, self.clock.now, self.resting, robot.base_blocked)
            if cfg.robot_id:
                self.info = InfoPublisher(cfg.head, cfg.robot_id)   # the driver's latched identity
        if self.clock.sim:
            # Gazebo's world publishes /clock; its launch sets /use_sim_time (empty_world.launch)
            self.clock_thread = ClockPublisher(self.clock, self.stop_event)
            import rospy
            if rospy.get_param('/use_sim_time', False) is not True:
                rospy.set_param('/use_sim_time', True)
                self.set_sim_time = True
        for i, spec in enumerate(cfg.profile_spec.sensors):
            fault = cfg.faults.get(spec.name)
            pub: StreamPublisher
            cls: Type[StreamPublisher] = EVENT_PUBLISHERS.get(spec.family) or \
                (TfPublisher if spec.family == TfPublisher.family else publisher_class(spec))
            seed = cfg.seed * 1000 + i
            if issubclass(cls, AudioPublisher):
                from .audio_source import AudioSource
                # with after=T the publisher silences them itself from T on
                channels = fault.silent_channel if fault and fault.after is None else ()
                self.source = AudioSource(rate=48000, channels=4, pattern=cfg.audio_pattern,
                                          silent_channels=channels, seed=cfg.seed)
                pub = cls(spec, fault, self.clock, self.stop_event, cfg.rate_factor, seed,
                          cfg.condition, source=self.source)
            else:
                pub = cls(spec, fault, self.clock, self.stop_event, cfg.rate_factor, seed, cfg.condition)
            pub.body = self.body
            pub.network = self.network
            self.threads.append(pub)
        # the tree goes out with every joint state, as naoqi_driver's loop sends it (tf_publisher.py)
        trees = [t for t in self.threads if isinstance(t, TfPublisher)]
        joints = [t for t in self.threads if isinstance(t, JointStatePublisher)]
        if trees and joints:
            trees[0].driven = True
            joints[0].tree = trees[0]
        topic = cfg.profile_spec.speech_topic
        if topic:
            if self.source is not None:
                self.speech = DirectSpeech(self.source)
            else:
                self.speech = NaoqiSpeech(cfg.naoqi_url)
            self.speech_sub = rosapi.subscriber(topic, 'std_msgs/String', self._on_speech, queue_size=10)
        if cfg.operator:
            self.operator = EmulatedOperator(self.threads)
        if self.clock_thread is not None:
            self.clock_thread.start()
        for t in self.threads:
            t.start()

    def _on_speech(self, msg: Any) -> None:
        rosapi.loginfo('pepperEmulator: /speech "%s"', msg.data)
        self.speech.say(msg.data)  # type: ignore[union-attr]  # set in start() before any /speech

    def summary_line(self) -> str:
        cfg = self.config
        topics = sum(1 + len(t.spec.extra) for t in self.threads)
        faults = faults_mod.format_faults(cfg.faults) or 'none'
        extra = ''
        if cfg.profile != 'simulator':
            extra = ', head %s, audio %s, realsense %s, cameras %s, robot %s' % (
                cfg.head, cfg.audio, 'on' if cfg.realsense else 'off', cfg.camera_resolution, cfg.robot_id or 'unnamed')
        else:
            extra = ', sim time at real-time factor %g' % cfg.real_time_factor
        if cfg.condition != 'normal':
            extra += ', condition %s' % cfg.condition
        if cfg.network != 'none':
            extra += ', network %s' % cfg.network
        return ('pepperEmulator: all %d publishers up (%d topics, %s profile%s, rate factor %g, '
                'faults: %s)' % (len(self.threads), topics, cfg.profile, extra, cfg.rate_factor,
                                 faults))

    def stop(self) -> None:
        self.stop_event.set()
        for t in self.threads:
            if t.ident is not None:      # started (a start that failed half-way leaves some not)
                t.join(2.0)
        for t in self.threads:
            try:
                t.close()
            except Exception:
                pass
        if self.speech_sub is not None:
            self.speech_sub.unregister()
        if self.commands is not None:
            self.commands.close()
        if self.info is not None:
            self.info.close()
        if self.operator is not None:
            self.operator.close()
        if self.speech is not None:
            self.speech.close()
        if self.clock_thread is not None:
            self.clock_thread.join(1.0)
            self.clock_thread.close()
        if self.set_sim_time:
            # leave the master as it was: a later node on it must not wait for a /clock
            try:
                import rosgraph
                rosgraph.Master('/' + NODE_NAME).deleteParam('/use_sim_time')
            except Exception:
                pass


def main(argv: Optional[Sequence[str]] = None) -> int:
    import rosgraph
    import rospy
    argv = rospy.myargv(sys.argv if argv is None else argv)
    args = _parser().parse_args(argv[1:])
    if args.list_faults:
        import shutil

        from .fault_table import table
        print(table(max(60, shutil.get_terminal_size((80, 20)).columns - 1)))
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
