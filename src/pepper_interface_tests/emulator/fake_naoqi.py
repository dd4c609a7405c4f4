"""A fake NAOqi for the real naoqi_driver: its services answered from the emulator's world.

A real libqi service directory (``qi.Session.listenStandalone``) serving what ros-naoqi/
naoqi_driver (ROS 1, master aed1b87e) asks of NAOqi, so the real driver's converters turn the
emulator's scene (scene.py, via fake_memory.py) into ROS messages. ALAudioDevice and
ALTextToSpeech are the emulator's own (naoqi_endpoint.py). What each answer must look like is
read from the driver's calls (file:line below); ros-naoqi/naoqi_driver2's src/fake_naoqi/ (branch
fake_naoqi) registers the same services, a second reading. naoqi_driver2 (2.1.2) asks one thing
more of the sensors' NAOqi: ALMemory.subscriber(key) for the touch events (QiMemory below).

  pepperFakeNaoqi --port 9559 [--head xtion] [--naoqi 2.9.5.172] [--fault NAME ...]
                  [--video-relay] [--audio-relay]

Faults (the ones the driver itself turns into data): camera-fails (getImageRemote raises for
the front camera: camera.cpp:273-281 publishes nothing), missing-key (the front sonar's key is
absent: -1, from_any_value.cpp:186-199), stuck-laser (the front board's keys never change),
touch (FrontTactilTouched pressed and released every 2 s, touch.cpp:172-180), hot-joint
(HeadYaw at 75 degC: diagnostics.cpp ERROR above 74), low-battery (20 %: "Battery almost
empty", diagnostics.cpp); --naoqi 2.9.x: the driver registers no audio (naoqi_driver.cpp:823).
"""
import argparse
import logging
import signal
import sys
import threading
import time
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

from ..sensors import joint_limits
from . import scene
from .fake_memory import Memory, WorldSettings
from .info import DEFAULT_BODY_ID
from .profiles import JOINT_NAMES

LOG = logging.getLogger('fakeNaoqi')
FAULTS = ('camera-fails', 'missing-key', 'stuck-laser', 'touch', 'hot-joint', 'low-battery')
# ALVideoDevice resolution index -> (width, height) (src/tools/alvisiondefinitions.h:46-65)
RESOLUTIONS = {0: (160, 120), 1: (320, 240), 2: (640, 480), 3: (1280, 960), 7: (80, 60),
               8: (40, 30), 9: (640, 360), 10: (320, 180), 11: (160, 90), 14: (1280, 360),
               15: (640, 180), 16: (320, 90)}
K_TOP, K_BOTTOM, K_DEPTH, K_IR_OR_STEREO = 0, 1, 2, 3          # alvisiondefinitions.h:36-39
K_RGB, K_DEPTH_CS, K_INFRARED, K_RAW_DEPTH = 11, 17, 20, 23    # alvisiondefinitions.h:79-90
# getImageRemote's reply, as from_any_value.cpp:37-181 reads it: width, height, layers,
# colorspace, timestamp s, timestamp us (ints), the buffer (Raw: a Python bytes would travel
# as a String and the driver would throw "Could not retrieve buffer"), camera id (int), the
# four angles of view (floats)
IMAGE_SIGNATURE = '(iiiiiirifff' + 'f)'


class Clock:
    def __init__(self) -> None:
        self.t0 = time.monotonic()

    def now(self) -> float:
        return time.monotonic() - self.t0


class ALMemory:
    def __init__(self, memory: Memory, clock: Clock, session: Any) -> None:
        self._m, self._clock, self._session = memory, clock, session
        self.subscribers: Dict[str, List[Tuple[str, str]]] = {}
        self.signals: Dict[str, Any] = {}       # key -> the object subscriber(key) returned

    def getData(self, key: str) -> Any:
        value = self._m.get(str(key), self._clock.now())
        if value is None:       # NAOqi raises; the driver's joint_state.cpp:128-132 writes NaN
            raise RuntimeError('ALMemory::getData: key "%s" does not exist' % key)
        return value

    def getListData(self, keys: List[str]) -> List[Any]:
        t = self._clock.now()
        return [self._m.get(str(k), t) for k in keys]

    def subscribeToEvent(self, event: str, module: str, method: str) -> None:
        # touch.cpp:97: (key, "ROS-Driver-<first key>", "touchCallback")
        self.subscribers.setdefault(str(event), []).append((str(module), str(method)))

    def unsubscribeToEvent(self, event: str, module: str) -> None:
        self.subscribers[str(event)] = [s for s in self.subscribers.get(str(event), [])
                                        if s[0] != str(module)]

    def raise_event(self, event: str, value: float) -> int:
        """Call every subscriber's method as NAOqi does: (key, value, message), and emit the
        value on the signal of the key's subscriber object (naoqi_driver2's way)."""
        done = 0
        if event in self.signals:
            self.signals[event].signal(value)
            done += 1
        for module, method in list(self.subscribers.get(event, [])):
            try:
                getattr(self._session.service(module), method)(event, value, '')
                done += 1
            except RuntimeError as exc:
                LOG.warning('%s.%s failed: %s', module, method, exc)
        return done


def _names(names: Any) -> List[str]:
    """ALMotion takes one name or a list of names."""
    return [str(names)] if isinstance(names, str) else [str(n) for n in names]


def _floats(values: Any) -> List[float]:
    return [float(values)] if isinstance(values, (int, float)) else [float(v) for v in values]


class ALMotion:
    def __init__(self, memory: Memory, clock: Clock, head: str) -> None:
        self._m, self._clock, self._head = memory, clock, head

    def getRobotConfig(self) -> List[List[Any]]:
        # driver_helpers.cpp:78-120 reads names in [0] and values in [1]
        head = '1.8a' if self._head == 'stereo' else '1.7'
        return [['Model Type', 'Head Version', 'Body Version', 'Arm Version', 'Laser', 'Extended Arms'],
                ['juliette', head, head, head, True, False]]

    def getSensorNames(self) -> List[str]:
        # driver_helpers.cpp:373-394: "CameraStereo" decides the head
        names = ['CameraTop', 'CameraBottom', 'CameraDepth']
        return names + (['CameraStereo'] if self._head == 'stereo' else [])

    def getBodyNames(self, group: str) -> List[str]:
        # joint_state.cpp:79 ("Body"), diagnostics.cpp:76 ("JointActuators")
        return list(JOINT_NAMES)

    def getLimits(self, name: str) -> List[List[float]]:
        # diagnostics.cpp:86-107: [[min, max, max velocity, max torque]]; the robot
        # description's limits (sensors/joint_limits.py), no torque (0, as the emulator's
        # /diagnostics: the URDF gives none)
        lo, hi, vel, _ = joint_limits.LIMITS.get(str(name), (0.0, 0.0, 0.0, 0))
        return [[float(lo or 0.0), float(hi or 0.0), float(vel), 0.0]]

    def getAngles(self, names: Any, use_sensors: bool) -> List[float]:
        return self._m.joint_angles(self._clock.now())

    def getPosition(self, name: str, frame: int, use_sensors: bool) -> List[float]:
        # odom.cpp:56-66: x, y, z, wx, wy, wz of the torso in FRAME_WORLD
        snap = self._m.snapshot(self._clock.now())
        return [float(snap.x), float(snap.y), 0.82, 0.0, 0.0, float(snap.yaw)]

    def getRobotVelocity(self) -> List[float]:
        snap = self._m.snapshot(self._clock.now())
        return [float(snap.vx), float(snap.vy), float(snap.wz)]

    # the driver's subscribers call these (teleop.cpp:44-65, moveto.cpp:49-129); the body
    # follows them as the emulator's own command topics do (body.py, commands.py). Each call is
    # said on stderr in received order ("ALMotion.move(0.0, 0.0, 0.0)"): what the robot was
    # last told (tools/real-driver2/live.sh, test/ros2/test_real_driver2_ros2.py)
    def move(self, x: float, y: float, theta: float) -> None:
        _said('move', x, y, theta)
        self._m.body.move(self._clock.now(), float(x), float(y), float(theta))

    def moveTo(self, x: float, y: float, theta: float) -> None:
        _said('moveTo', x, y, theta)
        self._m.body.move_to(self._clock.now(), float(x), float(y), float(theta))

    def setAngles(self, names: Any, angles: Any, speed: float) -> None:
        _said('setAngles', _names(names), _floats(angles), speed)
        self._m.body.set_angles(self._clock.now(), _names(names), _floats(angles), float(speed))

    def changeAngles(self, names: Any, changes: Any, speed: float) -> None:
        _said('changeAngles', _names(names), _floats(changes), speed)
        self._m.body.set_angles(self._clock.now(), _names(names), _floats(changes), float(speed),
                                relative=True)


def _said(call: str, *args: Any) -> None:
    LOG.info('ALMotion.%s(%s)', call, ', '.join(repr(float(a)) if isinstance(a, (int, float)) else repr(a)
                                                 for a in args))


class ALVideoDevice:
    def __init__(self, clock: Clock, failing: Optional[int], seed: int = 0,
                 memory: Optional[Memory] = None) -> None:
        self._clock, self._failing, self._seed = clock, failing, seed
        self._m = memory       # the body the pictures are seen from (base + head yaw)
        self._handles: Dict[str, Tuple[int, int, int, int, Any]] = {}
        self._lock = threading.Lock()

    def subscribeCamera(self, name: str, camera: int, resolution: int, colorspace: int, fps: int) -> str:
        # camera.cpp:248-255
        w, h = RESOLUTIONS.get(int(resolution), (320, 240))
        camera, colorspace = int(camera), int(colorspace)
        if colorspace in (K_DEPTH_CS, K_RAW_DEPTH, K_INFRARED):
            renderer: Any = scene.DepthCamera(w, h, 1.0123, seed=self._seed)
        elif camera == K_IR_OR_STEREO:
            renderer = scene.StereoCamera(w, h, 1.0472)
        else:
            renderer = scene.ColourCamera(w, h, 0.9826, view='bottom' if camera == K_BOTTOM else 'front')
        handle = '%s_%d' % (name, len(self._handles))
        with self._lock:
            self._handles[handle] = (camera, w, h, colorspace, renderer)
        LOG.info('subscribeCamera %s: camera %d, %dx%d, colorspace %d', handle, camera, w, h, colorspace)
        return handle

    def unsubscribe(self, handle: str) -> bool:
        with self._lock:
            return self._handles.pop(str(handle), None) is not None

    def image(self, handle: str) -> Tuple[Any, ...]:
        with self._lock:
            camera, w, h, colorspace, renderer = self._handles[str(handle)]
        if camera == self._failing:
            raise RuntimeError('ALVideoDevice::getImageRemote: camera %d gives no image' % camera)
        t = self._clock.now()
        if self._m is None:
            img = np.ascontiguousarray(renderer.render(t))
        else:
            snap = self._m.snapshot(t)
            img = np.ascontiguousarray(renderer.render(t, view=(snap.x, snap.y, snap.view_yaw)))
        now = time.time()
        return (w, h, 3 if img.dtype == np.uint8 else 2, colorspace, int(now), int((now % 1) * 1e6),
                img.tobytes(), camera, 0.0, 0.0, 0.0, 0.0)


class ALSonar:
    def subscribe(self, name: str) -> None:       # sonar.cpp:98 (NAOqi < 2.9)
        pass

    def unsubscribe(self, name: str) -> None:
        pass


class ALBodyTemperature:
    def setEnableNotifications(self, enable: bool) -> None:     # diagnostics.cpp:67
        pass


class ALSystem:
    def __init__(self, version: str) -> None:
        self._version = version

    def systemVersion(self) -> str:           # driver_helpers.cpp:286, four numbers
        return self._version

    def robotName(self) -> str:
        return 'fake-pepper'


class ALRobotModel:
    def _getMicrophoneConfig(self) -> int:    # audio.cpp:51: non-zero: channelMap [3, 5, 0, 2]
        return 1

    def _getConfigMap(self) -> Dict[str, str]:     # audio.cpp:55-59 (NAOqi >= 2.9)
        return {'RobotConfig/Head/Device/Micro/Version': '1'}

    def getRobotType(self) -> str:
        return 'Juliette'

    def hasLegs(self) -> bool:
        return False

    def getConfig(self) -> str:
        return ''


def register(session: Any, settings: WorldSettings, seed: int = 0,
             video_relay: bool = False, audio_relay: bool = False) -> Tuple[List[int], ALMemory]:
    """Register every service on `session`; returns their ids and the ALMemory service.
    The typed video service is FakeVideoFrames; it is ALVideoDevice too unless `video_relay`
    (then tools/real-driver/relay/video_relay.cpp registers ALVideoDevice: naoqi_driver reads
    every field of getImageRemote's answer as a dynamic value, from_any_value.cpp:39-181, and a
    Python service cannot put Raw inside a dynamic value). With `audio_relay`, ALAudioDevice is
    tools/real-driver/relay/audio_relay.cpp and the buffers come from FakeAudioFrames.next_buffer
    (typed, Raw): naoqi_driver reads processRemote's buffer with asRaw() (src/event/audio.cpp:182),
    and a Python caller cannot send a Raw argument (qi 3.1.5 sends bytes as their str() text)."""
    import qi

    from .audio_source import AudioSource
    from .naoqi_endpoint import ALAudioDeviceService, ALTextToSpeechService, AudioDevice, PolledAudioService
    class MemorySubscriber:
        """What NAOqi's ALMemory.subscriber(key) returns: an object whose signal `signal`
        carries each new value of the key."""
        def __init__(self) -> None:
            self.signal = qi.Signal('(m)')   # the driver connects a (const qi::AnyValue&) callback

    class QiMemory(ALMemory):
        # naoqi_driver2 takes ALMemory events this way, not with subscribeToEvent:
        # `p_memory_.call<qi::AnyObject>("subscriber", key)` then connect("signal", ...)
        # (naoqi_driver2 2.1.2 src/event/touch.cpp:91-92, src/event/basic.hxx:56)
        @qi.bind(returnType=qi.Object, paramsType=[qi.String])
        def subscriber(self, key: str) -> Any:
            return self.signals.setdefault(str(key), MemorySubscriber())

    clock = Clock()
    memory = Memory(settings, seed)
    mem = QiMemory(memory, clock, session)
    video = ALVideoDevice(clock, settings.failing_camera, seed, memory)

    class VideoService:
        def subscribeCamera(self, name: str, camera: int, resolution: int, colorspace: int, fps: int) -> str:
            return video.subscribeCamera(name, camera, resolution, colorspace, fps)

        def unsubscribe(self, handle: str) -> bool:
            return video.unsubscribe(handle)

        @qi.bind(returnType=IMAGE_SIGNATURE, paramsType=['s'])
        def getImageRemote(self, handle: str) -> Tuple[Any, ...]:
            return video.image(handle)

    services: List[Tuple[str, Any]] = [
        ('ALMemory', mem), ('ALMotion', ALMotion(memory, clock, settings.head)),
        ('FakeVideoFrames', VideoService()), ('ALSonar', ALSonar()),
        ('ALBodyTemperature', ALBodyTemperature()), ('ALSystem', ALSystem(settings.naoqi)),
        ('ALRobotModel', ALRobotModel())]
    if not video_relay:
        services.append(('ALVideoDevice', VideoService()))
    source = AudioSource(pattern='tones', seed=seed)
    device = AudioDevice(session, source)

    class AudioFrames(PolledAudioService):
        @qi.bind(returnType=PolledAudioService.SIGNATURE, paramsType=['s'])
        def next_buffer(self, module: str) -> Tuple[int, int, int, int, bytes]:
            return PolledAudioService.next_buffer(self, module)

    audio: Tuple[str, Any] = (('FakeAudioFrames', AudioFrames(device)) if audio_relay
                              else ('ALAudioDevice', ALAudioDeviceService(device)))
    services += [audio, ('ALTextToSpeech', ALTextToSpeechService(source))]
    ids = [session.registerService(name, obj) for name, obj in services]
    device.start()
    return ids, mem


def settings_from(args: argparse.Namespace) -> WorldSettings:
    f = set(args.fault)
    return WorldSettings(
        head=args.head, naoqi=args.naoqi,
        missing_keys=frozenset({'Device/SubDeviceList/Platform/Front/Sonar/Sensor/Value'}
                               if 'missing-key' in f else ()),
        stuck_laser='Front' if 'stuck-laser' in f else None,
        hot_joint='HeadYaw' if 'hot-joint' in f else None,
        battery=20.0 if 'low-battery' in f else 87.0,
        failing_camera=K_TOP if 'camera-fails' in f else None,
        touch='touch' in f, body_id=args.robot_id)


def parse_args(argv: Sequence[str]) -> argparse.Namespace:
    p = argparse.ArgumentParser(prog='pepperFakeNaoqi', description=__doc__.split('\n')[0])
    p.add_argument('--port', type=int, default=9559, help='TCP port on 127.0.0.1 (0: any free port)')
    p.add_argument('--head', choices=('stereo', 'xtion'), default='stereo')
    p.add_argument('--naoqi', default='2.5.10.7', help='ALSystem.systemVersion() (default 2.5.10.7)')
    p.add_argument('--fault', action='append', default=[], choices=FAULTS)
    p.add_argument('--robot-id', default=DEFAULT_BODY_ID, help='Device/DeviceList/ChestBoard/BodyId, the '
                   'serial number naoqi_driver publishes on its info topic (default %s)' % DEFAULT_BODY_ID)
    p.add_argument('--seed', type=int, default=0)
    p.add_argument('--video-relay', action='store_true',
                   help='leave ALVideoDevice to tools/real-driver video_relay (for the C++ driver)')
    p.add_argument('--audio-relay', action='store_true',
                   help='leave ALAudioDevice to tools/real-driver audio_relay (for the C++ driver)')
    return p.parse_args(argv)


def main(argv: Optional[Sequence[str]] = None) -> int:
    import qi

    from .naoqi_endpoint import exit_now
    args = parse_args(sys.argv[1:] if argv is None else argv)
    logging.basicConfig(level=logging.INFO, stream=sys.stderr, format='fakeNaoqi: %(message)s')
    session = qi.Session()
    url = 'tcp://127.0.0.1:%d' % args.port
    try:
        session.listenStandalone(url)
    except RuntimeError as exc:
        sys.stderr.write('fakeNaoqi: cannot listen on %s: %s\n' % (url, str(exc).splitlines()[0]))
        return 1
    settings = settings_from(args)
    _, mem = register(session, settings, args.seed, args.video_relay, args.audio_relay)
    bound = [u for u in session.endpoints() if u.startswith('tcp://127.0.0.1:')]
    print('fake NAOqi ready on %s (%s)' % (bound[0] if bound else url, settings), flush=True)
    stop = threading.Event()
    signal.signal(signal.SIGINT, lambda *_: stop.set())
    signal.signal(signal.SIGTERM, lambda *_: stop.set())
    pressed = False
    while not stop.wait(1.0):
        if settings.touch:
            pressed = not pressed
            mem.raise_event('FrontTactilTouched', 1.0 if pressed else 0.0)
    return exit_now(0)


if __name__ == '__main__':
    sys.exit(main())
