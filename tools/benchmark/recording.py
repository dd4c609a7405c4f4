"""The recording benchmark's workload: one synthetic recording of Pepper's streams written three
ways in one pass, the same messages at the same record times (integer nanoseconds):
  a ROS 1 bag (rosbag's writer, naoqi_driver's /naoqi_driver/... names, data/pepperTopics.dat),
  a rosbag2 sqlite3 folder and a rosbag2 MCAP folder (rosbags' writer, naoqi_driver2's root
  names, data/naoqi_driver2Topics.dat; each message turned into CDR by rosbags' ros1_to_cdr).

The streams: four 640x480 cameras at 10 Hz (front and bottom rgb8, RealSense colour rgb8 and
aligned depth 16UC1), the depth camera 320x240 16UC1, laser, both sonars and the IMU at 10 Hz,
odometry at 15 Hz, joints at 50 Hz, the driver's /tf with every joint state (its tree from
naoqi_driver's URDF, emulator/urdf_tree.py: about 84 transforms a message), and stock
naoqi_driver's AudioBuffer (4 x 8192 samples at 48 kHz, 5.9 Hz): 60 s is about 2.1 GB per form. The messages are
the tests' made-up healthy Pepper messages (test/helpers/fake_pepper.py, built from the emulator's
profiles); the pixels of each camera cycle through RING distinct frames (serialized once, the
stamp patched into the bytes), so that writing 2 GB costs seconds, not minutes."""
import os
import struct
import sys
from typing import Any, Callable, Dict, Iterator, List, Tuple

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, '..', '..', 'test', 'helpers'))

import fake_pepper as fake  # noqa: E402  (test/helpers, put on the path above)
from pepper_interface_tests.plan import catalog, declaration  # noqa: E402

RING = 20          # distinct frames per camera, cycled (frozen_frames is 5 in the expectations)
NS = 1000000000
T0_NS = 1700000000123456700     # the first record, the same nanosecond on every topic

# The benchmark's scenario: which sensors the recording carries and at what rate (Hz; the
# RealSense at 10 Hz like the head cameras, the microphone at its AudioBuffer rate). Each
# sensor's topics are the declaration's (plan/declaration.py): stock naoqi_driver's for the ROS 1
# bag, naoqi_driver2's for the ROS 2 forms, realsense2_camera's for the RealSense.
RATES: Dict[str, float] = {  # scenario
    'frontCamera': 10.0, 'bottomCamera': 10.0, 'realsenseRGBCamera': 10.0,
    'realsenseDepthCamera': 10.0, 'depthCamera': 10.0, 'laser': 10.0, 'frontSonar': 10.0,
    'backSonar': 10.0, 'imu': 10.0, 'odometry': 15.0, 'jointState': 50.0,
    'microphone': 48000.0 / 8192,
    'tf': 50.0,       # with every joint state (naoqi_driver joint_state.cpp)
}


def _topics(sensor: str) -> Tuple[str, str]:
    """(ROS 1 topic, ROS 2 topic) of a sensor, as its drivers publish it."""
    row = declaration.SENSORS[sensor]
    ros1 = row.stream(declaration.STOCK) or row.stream(declaration.REALSENSE)
    ros2 = row.stream(declaration.DRIVER2) or row.stream(declaration.REALSENSE)
    assert ros1 and ros2, sensor
    return ros1.topic, ros2.topic


# sensor -> (ROS 1 topic, ROS 2 topic, rate in Hz)
STREAMS: Dict[str, Tuple[str, str, float]] = {n: _topics(n) + (r,) for n, r in RATES.items()}
STREAMS['tf_static'] = ('/tf_static', '/tf_static', 0.0)    # once: the RealSense's frames and mount
SENSORS = ','.join(s for s in STREAMS if s != 'tf_static')
TF_STREAMS = ('tf', 'tf_static')
# the sensors alone (a recording without the driver's /tf: users record what they record)
SENSORS_ALONE = ','.join(s for s in STREAMS if s not in TF_STREAMS)


def sensors(tf: bool) -> str:
    """sensorTest's --sensors for a recording with or without /tf."""
    return SENSORS if tf else SENSORS_ALONE


def _frame(sensor: str, i: int) -> Any:
    """The i-th message of `sensor` (ROS 1 class), stamp left to the caller."""
    if catalog.SENSORS[sensor].family == 'camera':
        frame = {'frontCamera': 'CameraTop_optical_frame', 'bottomCamera': 'CameraBottom_optical_frame'}
        return fake.camera_image(i + 7 * len(sensor), 640, 480,
                                 frame_id=frame.get(sensor, 'camera_color_optical_frame'))
    if sensor == 'realsenseDepthCamera':
        m = fake.depth_image(i, 640, 480)
        m.header.frame_id = 'camera_color_optical_frame'
        return m
    if sensor == 'depthCamera':
        return fake.depth_image(i, 320, 240)
    if sensor == 'laser':
        return fake.laser(i)
    if sensor in ('frontSonar', 'backSonar'):
        return fake.sonar(i, sensor=sensor)
    if sensor == 'imu':
        return fake.imu(i, covariance=fake.UNKNOWN_COVARIANCE)
    if sensor == 'odometry':
        return fake.odometry(i, x=0.01 * i)
    if sensor == 'jointState':
        return fake.joints(i)
    if sensor == 'microphone':
        return fake.stock_audio_buffer(i)
    raise ValueError(sensor)


def _tf(i: int, ns: int) -> Any:
    """The i-th /tf message: the tree at the i-th joint state's positions, stamped `ns` (its
    transforms carry their stamps: built whole, not patched), the base 0.15 m/s ahead."""
    import genpy

    from pepper_interface_tests.emulator.tf_publisher import tf_message
    from pepper_interface_tests.emulator.urdf_tree import driver_tree
    js = fake.joints(i)
    tree = driver_tree(dict(zip(js.name, js.position)))
    tree.append(('odom', 'base_link', (0.15 * (ns - T0_NS) / NS, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)))
    return tf_message(tree, genpy.Time(ns // NS, ns % NS))


def _tf_static(ns: int) -> Any:
    """/tf_static: the RealSense's own frames and its mount on the head, as the emulator's."""
    import genpy

    from pepper_interface_tests.emulator.tf_publisher import REALSENSE_TREE, tf_message
    return tf_message(list(REALSENSE_TREE), genpy.Time(ns // NS, ns % NS))


def _typestore() -> Any:
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    from pepper_interface_tests.sources.ros2types import AUDIO_BUFFER_DEFINITION_ROS2
    ts = get_typestore(Stores.ROS2_HUMBLE)
    ts.register(get_types_from_msg(AUDIO_BUFFER_DEFINITION_ROS2, 'naoqi_bridge_msgs/msg/AudioBuffer'))
    return ts


class _Message:
    """One message in both encodings, built once (cameras: RING times, then patched)."""

    def __init__(self, msg: Any, ts: Any) -> None:
        pkg, name = msg._type.split('/')
        self.ros2_type = '%s/msg/%s' % (pkg, name)
        self.ros1 = bytearray(fake.serialized(msg))
        self.cdr = bytearray(ts.ros1_to_cdr(bytes(self.ros1), self.ros2_type))
        self.ros1_info = (msg._type, msg._md5sum, type(msg))

    def stamped(self, ns: int) -> Tuple[bytes, bytes]:
        """(ROS 1 bytes, CDR bytes) with header.stamp = ns: in ROS 1 after seq (uint32 secs,
        nsecs), in CDR after the 4-byte encapsulation header (int32 sec, uint32 nanosec)."""
        stamp = struct.pack('<II', ns // NS, ns % NS)
        self.ros1[4:12] = stamp
        self.cdr[4:12] = stamp
        return bytes(self.ros1), bytes(self.cdr)


def _schedule(seconds: float, tf: bool = True) -> Iterator[Tuple[int, str, int]]:
    """(record time ns, sensor, index) of every message, in record-time order; `tf` False:
    without /tf and /tf_static."""
    out = []
    for sensor, (_, _, rate) in STREAMS.items():
        if not tf and sensor in TF_STREAMS:
            continue
        for i in range(int(seconds * rate) if rate else 1):
            out.append((T0_NS + (int(round(i * NS / rate)) if rate else 0), sensor, i))
    out.sort()
    return iter(out)


def write(folder: str, seconds: float, log: Callable[[str], None] = print, tf: bool = True) -> Dict[str, str]:
    """Write the three forms into `folder`; {'ros1': bag, 'sqlite3': folder, 'mcap': folder};
    `tf` False: the sensors alone, without the driver's /tf and /tf_static."""
    import genpy
    import rosbag
    from rosbags.rosbag2 import StoragePlugin, Writer
    ts = _typestore()
    paths = {'ros1': os.path.join(folder, 'pepper.bag'), 'sqlite3': os.path.join(folder, 'pepper_sqlite3'),
             'mcap': os.path.join(folder, 'pepper_mcap')}
    writers = [Writer(paths['sqlite3'], version=8, storage_plugin=StoragePlugin.SQLITE3),
               Writer(paths['mcap'], version=8, storage_plugin=StoragePlugin.MCAP)]
    rings: Dict[str, List[_Message]] = {}
    conns: List[Dict[str, Any]] = [{}, {}]
    for w in writers:
        w.open()
    try:
        with rosbag.Bag(paths['ros1'], 'w') as bag:
            for ns, sensor, i in _schedule(seconds, tf):
                ring = rings.setdefault(sensor, [])
                camera = 'Camera' in sensor
                if sensor in ('tf', 'tf_static'):
                    m = _Message(_tf(i, ns) if sensor == 'tf' else _tf_static(ns), ts)
                    ros1, cdr = bytes(m.ros1), bytes(m.cdr)
                else:
                    if camera and len(ring) >= RING:
                        m = ring[i % RING]
                    else:
                        m = _Message(_frame(sensor, i), ts)
                        if camera:
                            ring.append(m)
                    ros1, cdr = m.stamped(ns)
                topic1, topic2, _ = STREAMS[sensor]
                bag.write(topic1, (m.ros1_info[0], ros1, m.ros1_info[1], m.ros1_info[2]),
                          genpy.Time(ns // NS, ns % NS), raw=True)
                for w, c in zip(writers, conns):
                    if topic2 not in c:
                        c[topic2] = w.add_connection(topic2, m.ros2_type, typestore=ts)
                    w.write(c[topic2], ns, cdr)
    finally:
        for w in writers:
            w.close()
    for name, path in paths.items():
        log('  %-8s %s (%.0f MB)' % (name, path, size(path) / 1e6))
    return paths


def size(path: str) -> int:
    if os.path.isdir(path):
        return sum(os.path.getsize(os.path.join(path, f)) for f in os.listdir(path))
    return os.path.getsize(path)
