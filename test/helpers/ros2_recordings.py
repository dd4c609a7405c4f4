"""Test helper: one synthetic Pepper recording written both ways, a ROS 1 bag (rosbag, the ROS 1
driver's /naoqi_driver/... names) and a ROS 2 recording (naoqi_driver2's root names), so that
`sensorTest --bag` can be asked to judge the very same data from each.

The messages are fake_pepper's (ROS 1 classes). For ROS 2 each is turned into CDR in one of two
independent ways:
  * `rosbags`: its typestore's ros1_to_cdr, written by the rosbags rosbag2 Writer (sqlite3 or MCAP
    storage, optionally zstd-compressed per message or per file, optionally split in several files);
  * `mcap_ros2`: the message as a dict with ROS 2 field names (stamp sec/nanosec, no seq,
    channel_map), serialized by the mcap-ros2-support writer from the ROS 2 .msg text into a
    single .mcap file (no metadata.yaml): the reader and this writer share no code.
"""
import math
import os
from collections import namedtuple

import genpy
import numpy as np

import fake_pepper as fake
from pepper_interface_tests.plan import declaration

T0 = 1700000000.0
SECONDS = 3.0

# the ROS 1 driver's names and naoqi_driver2's, as declared (plan/declaration.py; the topics files
# data/pepperTopics.dat and data/naoqi_driver2Topics.dat are written from it)
TOPICS = {name: tuple(declaration.SENSORS[name].stream(d).topic for d in (declaration.STOCK, declaration.DRIVER2))
          for name in ('backSonar', 'frontSonar', 'frontCamera', 'depthCamera', 'laser', 'microphone',
                       'jointState', 'odometry', 'imu')}   # scenario: the sensors these recordings hold
SENSORS = ','.join(TOPICS)
RATES = {'backSonar': 10.0, 'frontSonar': 10.0, 'frontCamera': 10.0, 'depthCamera': 10.0,
         'laser': 10.0, 'microphone': 48000.0 / 8192, 'jointState': 50.0, 'odometry': 15.0,
         'imu': 10.0}

# fault family -> (sensor, what the message builder does), and how sensorTest names it
FAULTS = {
    'frontCamera': 'frozen',
    'laser': 'beams are invalid',
    'imu': 'not a unit quaternion',
    'backSonar': 'is not in the bag',
    'microphone': 'frontLeft',
    'jointState': 'HeadYaw',
    'odometry': 'pose jumps',
    'depthCamera': 'frame_id',
}

# ns: the record time in integer nanoseconds when the recording must hold exactly that one (else
# the nearest to t)
Record = namedtuple('Record', 'sensor t msg ns', defaults=(None,))


def record_ns(r):
    return r.ns if r.ns is not None else int(round(r.t * 1e9))


def _camera(i, frozen):
    k = 0 if frozen else i
    y, x = np.mgrid[0:120, 0:160]
    r = ((x + 3 * k) % 256).astype(np.uint8)
    g = ((y * 2 + k) % 256).astype(np.uint8)
    b = ((x + y + 5 * k) % 256).astype(np.uint8)
    return fake.image(np.dstack([r, g, b]), 'rgb8', frame_id='CameraTop_optical_frame')


def _depth(i, frame):
    m = fake.depth_image(i, 160, 120)
    m.header.frame_id = frame
    return m


def message(sensor, i, t, faulty=False, fork=False):
    """The `i`-th message of `sensor` at time t (a good robot, or the FAULTS when `faulty`;
    `fork`: what yohatad/naoqi_driver2 publishes: odometry pepper_odom -> base_footprint, laser
    +inf beyond range_max)."""
    bad = faulty and sensor in FAULTS
    if sensor in ('backSonar', 'frontSonar'):
        m = fake.sonar(i, sensor=sensor)
    elif sensor == 'frontCamera':
        m = _camera(i, bad)
    elif sensor == 'depthCamera':
        m = _depth(i, 'wrong_frame' if bad else 'CameraDepth_optical_frame')
    elif sensor == 'laser' and fork:
        # yohatad/naoqi_driver2: +inf where nothing is within range_max; a board whose frame
        # counter stopped gives NaN in its whole segment (the right board: slots 0-14)
        m = fake.laser(i)
        m.ranges = [math.nan if bad and k < 15 else math.inf if k % 7 == 3 and r > 0 else r
                    for k, r in enumerate(m.ranges)]
    elif sensor == 'laser':
        m = fake.laser(i, fault='nan' if bad else '')
    elif sensor == 'microphone':
        m = fake.stock_audio_buffer(i, dead='frontLeft' if bad else None)
    elif sensor == 'jointState':
        m = fake.joints(i, fault='missing_joint' if bad else '')
    elif sensor == 'odometry':
        x = 0.01 * i + (5.0 if bad and i >= 20 else 0.0)
        m = fake.odometry(i, x=x, frame_id='pepper_odom' if fork else 'odom',
                          child_frame_id='base_footprint' if fork else 'base_link')
    elif sensor == 'imu':
        m = fake.imu(i, fault='broken_quaternion' if bad else '', covariance=fake.UNKNOWN_COVARIANCE)
    else:
        raise ValueError(sensor)
    if hasattr(m, 'header'):
        m.header.stamp = genpy.Time.from_sec(t)
    return m


def records(faulty=False, fork=False, seconds=SECONDS, leave_out=(), first_ns=None):
    """Every message of the recording, in record-time order (received 2 ms after its stamp).
    `first_ns`: every topic's first record at exactly this record time (integer nanoseconds),
    the next ones at whole nanoseconds after it."""
    out = []
    for sensor, rate in RATES.items():
        if sensor in leave_out or (faulty and FAULTS.get(sensor) == 'is not in the bag'):
            continue
        for i in range(int(seconds * rate)):
            if first_ns is None:
                t = T0 + i / rate
                out.append(Record(sensor, t + 0.002, message(sensor, i, t, faulty, fork)))
            else:
                ns = first_ns + int(round(i * 1e9 / rate))
                out.append(Record(sensor, ns / 1e9, message(sensor, i, ns / 1e9 - 0.002, faulty, fork), ns))
    return sorted(out, key=record_ns)


def write_ros1(path, recs):
    import rosbag
    with rosbag.Bag(str(path), 'w') as bag:
        for r in recs:
            t = genpy.Time.from_sec(r.t) if r.ns is None else genpy.Time(r.ns // 10**9, r.ns % 10**9)
            bag.write(TOPICS[r.sensor][0], r.msg, t)
    return str(path)


def _ros2_type(msg):
    pkg, name = msg._type.split('/')
    return '%s/msg/%s' % (pkg, name)


def _typestore():
    """The ROS 2 standard types and naoqi_bridge_msgs/AudioBuffer of the ROS 2 message package
    (ros-naoqi/naoqi_bridge_msgs2: `channel_map`)."""
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore
    ts = get_typestore(Stores.ROS2_HUMBLE)
    ts.register(get_types_from_msg(AUDIO_BUFFER_ROS2, 'naoqi_bridge_msgs/msg/AudioBuffer'))
    return ts


AUDIO_BUFFER_ROS2 = """std_msgs/Header header
uint16 frequency
uint8 CHANNEL_FRONT_LEFT=0
uint8 CHANNEL_FRONT_CENTER=1
uint8 CHANNEL_FRONT_RIGHT=2
uint8 CHANNEL_REAR_LEFT=3
uint8 CHANNEL_REAR_CENTER=4
uint8 CHANNEL_REAR_RIGHT=5
uint8 CHANNEL_SURROUND_LEFT=6
uint8 CHANNEL_SURROUND_RIGHT=7
uint8 CHANNEL_SUBWOOFER=8
uint8 CHANNEL_LFE=9
uint8[] channel_map
int16[] data
"""


def write_rosbags(path, recs, storage='sqlite3', compression=None, split=None, definitions=True):
    """A rosbag2 folder written by rosbags (storage 'sqlite3' or 'mcap'; compression None,
    'message' or 'file' (zstd); `split`: a record time after which a second file begins,
    written as a second recording and joined into one metadata.yaml)."""
    from rosbags.rosbag2 import CompressionFormat, CompressionMode, StoragePlugin, Writer
    ts = _typestore()
    plugin = StoragePlugin.MCAP if storage == 'mcap' else StoragePlugin.SQLITE3
    w = Writer(str(path), version=8, storage_plugin=plugin)
    if compression:
        w.set_compression(getattr(CompressionMode, compression.upper()), CompressionFormat.ZSTD)
    with w:
        conns = {}
        for r in recs:
            topic = TOPICS[r.sensor][1]
            if topic not in conns:
                kw = {'typestore': ts} if definitions else {'msgdef': '', 'rihs01': ''}
                conns[topic] = w.add_connection(topic, _ros2_type(r.msg), **kw)
            raw = bytes(ts.ros1_to_cdr(fake.serialized(r.msg), _ros2_type(r.msg)))
            w.write(conns[topic], record_ns(r), raw)
    return str(path)


def _ros2_dict(value):
    """A ROS 1 message as the dict the mcap-ros2-support writer serializes (ROS 2 fields)."""
    if isinstance(value, genpy.Time):
        return {'sec': value.secs, 'nanosec': value.nsecs}
    if isinstance(value, genpy.Message):
        out = {}
        for name in value.__slots__:
            if name == 'seq' and value._type == 'std_msgs/Header':
                continue
            out['channel_map' if name == 'channelMap' else name] = _ros2_dict(getattr(value, name))
        return out
    if isinstance(value, bytes):
        return list(value)
    if isinstance(value, (list, tuple)):
        return [_ros2_dict(v) for v in value]
    return value


def write_mcap_ros2(path, recs):
    """A single .mcap file written by the mcap and mcap-ros2-support packages."""
    from mcap_ros2.writer import Writer
    ts = _typestore()
    with open(str(path), 'wb') as f:
        w = Writer(f)
        schemas = {}
        for r in recs:
            name = _ros2_type(r.msg)
            if name not in schemas:
                text = ts.generate_msgdef(name, ros_version=2)[0]
                schemas[name] = w.register_msgdef(name.replace('/msg/', '/msg/'), text)
            ns = record_ns(r)
            w.write_message(TOPICS[r.sensor][1], schemas[name], _ros2_dict(r.msg), log_time=ns,
                            publish_time=ns)
        w.finish()
    return str(path)


def convert(bag, dst, storage='sqlite3'):
    """A ROS 1 bag converted into a rosbag2 folder by `rosbags-convert` (rosbags' own command,
    tools/requirements.txt): the ROS 1 topic names and definitions, the record times as they are."""
    import shutil
    import subprocess
    import sys
    exe = shutil.which('rosbags-convert') or os.path.join(os.path.dirname(sys.executable), 'rosbags-convert')
    subprocess.run([exe, '--src', str(bag), '--dst', str(dst), '--dst-storage', storage],
                   check=True, capture_output=True, timeout=120)
    return str(dst)


def size(path):
    if os.path.isdir(path):
        return sum(os.path.getsize(os.path.join(path, f)) for f in os.listdir(path))
    return os.path.getsize(path)


def write_split(path, recs, storage='sqlite3'):
    """A rosbag2 folder of two storage files, as `ros2 bag record --max-bag-duration` leaves
    it: the records before the middle in <name>_0, the rest in <name>_1, one metadata.yaml."""
    import shutil

    import yaml
    path = str(path)
    half = recs[len(recs) // 2].t
    parts = [write_rosbags(path + '.part%d' % k, part, storage)
             for k, part in enumerate(([r for r in recs if r.t < half], [r for r in recs if r.t >= half]))]
    os.makedirs(path)
    infos, files = [], []
    for k, part in enumerate(parts):
        with open(os.path.join(part, 'metadata.yaml')) as f:
            info = yaml.safe_load(f)['rosbag2_bagfile_information']
        name = '%s_%d.%s' % (os.path.basename(path), k, 'mcap' if storage == 'mcap' else 'db3')
        shutil.move(os.path.join(part, info['relative_file_paths'][0]), os.path.join(path, name))
        shutil.rmtree(part)
        info['files'][0]['path'] = name
        infos.append(info)
        files.append(name)
    meta = infos[0]
    meta['relative_file_paths'] = files
    meta['files'] = [i['files'][0] for i in infos]
    meta['message_count'] = sum(i['message_count'] for i in infos)
    end = max(i['starting_time']['nanoseconds_since_epoch'] + i['duration']['nanoseconds'] for i in infos)
    meta['duration']['nanoseconds'] = end - meta['starting_time']['nanoseconds_since_epoch']
    counts = {}
    for i in infos:
        for t in i['topics_with_message_count']:
            name = t['topic_metadata']['name']
            if name in counts:
                counts[name]['message_count'] += t['message_count']
            else:
                counts[name] = t
    meta['topics_with_message_count'] = list(counts.values())
    with open(os.path.join(path, 'metadata.yaml'), 'w') as f:
        yaml.safe_dump({'rosbag2_bagfile_information': meta}, f)
    return path
