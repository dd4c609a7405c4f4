"""Record live ROS 2 topics into a rosbag2 MCAP recording (rosbags' Writer), for the golden
recordings of the real naoqi_driver2 (record-golden2.sh). Not part of `make test`.

    record2.py OUT SECONDS TOPIC [TOPIC ...]

A TOPIC written +TOPIC is subscribed and not recorded: naoqi_driver2 publishes a camera's
camera_info only while its image has a subscriber (src/publishers/camera.hpp:57-64 at 2.1.2
counts the image topic's subscribers; image_transport's camera publisher sends both, from
src/publishers/camera.cpp:44-47), so `audio` records each camera_info with +its image.

No rosbag2 here (the Humble core and tools overlay built on this machine have none; building
rosbag2 and its MCAP plugin is another hour on 2 cores), so this does what `ros2 bag record -s
mcap` does for a topic, with real rclpy: it waits for each topic's publishers, takes the type and
the offered QoS they announce (`get_publishers_info_by_topic`), subscribes raw (the CDR bytes as
published) with a matching QoS (the publishers' reliability and durability), and writes each
message at its receive time. The message definitions written with each channel are the .msg
files of the ROS 2 install in use (share/<package>/msg/, found through AMENT_PREFIX_PATH), so a
reader needs nothing installed. The offered QoS goes into metadata.yaml as rosbag2 writes it.
Ends after SECONDS of recording, or on SIGINT/SIGTERM (the recording is closed either way).
"""
import os
import signal
import sys
import time
from pathlib import Path
from typing import Dict, List

WAIT_PUBLISHERS_S = 20.0    # the driver's converters are registered a few seconds after start
# naoqi_driver2 converts a topic only while it has a subscriber (src/naoqi_driver.cpp, rosIteration:
# isSubscribed); the cameras then subscribe to ALVideoDevice: what arrives in the first second
# after subscribing is dropped (RECORD2_WARMUP seconds), so each recording starts steady
WARMUP_S = float(os.environ.get('RECORD2_WARMUP', '1.0'))
# rosbag2's file compression (`ros2 bag record --compression-mode file --compression-format
# zstd`): the raw images of a few seconds take tens of MB; RECORD2_COMPRESSION=none for none
COMPRESSION = os.environ.get('RECORD2_COMPRESSION', 'file')
# RECORD2_ON_SIGNAL=1: after the warm-up, wait for SIGUSR1 before recording (record-golden2.sh
# `move` starts the recording once the robot has stopped, at a time of its choosing)
ON_SIGNAL = os.environ.get('RECORD2_ON_SIGNAL') == '1'


def msg_definitions() -> Dict[str, str]:
    """Every .msg of the ROS 2 install in use: 'pkg/msg/Name' -> its text."""
    found: Dict[str, str] = {}
    for prefix in os.environ.get('AMENT_PREFIX_PATH', '').split(os.pathsep):
        share = Path(prefix) / 'share'
        if not share.is_dir():
            continue
        for path in share.glob('*/msg/*.msg'):
            found.setdefault('%s/msg/%s' % (path.parts[-3], path.stem), path.read_text())
    return found


def typestore_for(names: List[str]):
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore
    defs = msg_definitions()
    store = get_typestore(Stores.EMPTY)
    todo, done = list(names), set()
    while todo:
        name = todo.pop()
        if name in done:
            continue
        done.add(name)
        if name not in defs:
            sys.exit('record2: no %s.msg under AMENT_PREFIX_PATH (source the driver install)' % name)
        types = get_types_from_msg(defs[name], name)
        store.register(types)
        for _, desc in types[name][1]:
            todo.extend(_nested_names(desc))
    return store


def _nested_names(desc) -> List[str]:
    from rosbags.interfaces import Nodetype
    kind, rest = desc
    if kind == Nodetype.NAME:
        return [rest]
    if kind in (Nodetype.ARRAY, Nodetype.SEQUENCE):
        return _nested_names(rest[0])
    return []


def qos_of(info):
    """rosbags' Qos from a publisher's announced rclpy QoSProfile."""
    from rosbags.interfaces import Qos, QosDurability, QosHistory, QosLiveliness, QosReliability, QosTime
    q = info.qos_profile

    def t(d):
        return QosTime(sec=int(d.nanoseconds // 10**9), nsec=int(d.nanoseconds % 10**9))
    return Qos(history=QosHistory(int(q.history)), depth=int(q.depth),
               reliability=QosReliability(int(q.reliability)),
               durability=QosDurability(int(q.durability)),
               deadline=t(q.deadline), lifespan=t(q.lifespan),
               liveliness=QosLiveliness(int(q.liveliness)),
               liveliness_lease_duration=t(q.liveliness_lease_duration),
               avoid_ros_namespace_conventions=bool(q.avoid_ros_namespace_conventions))


def main(argv: List[str]) -> int:
    if len(argv) < 3:
        sys.stderr.write(__doc__)
        return 2
    out, seconds = Path(argv[0]), float(argv[1])
    topics = [t.lstrip('+') for t in argv[2:]]
    unwritten = {t.lstrip('+') for t in argv[2:] if t.startswith('+')}
    import rclpy
    from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
    from rosbags.rosbag2 import CompressionFormat, CompressionMode, StoragePlugin, Writer
    rclpy.init()
    node = rclpy.create_node('golden_recorder2')
    infos = {}
    deadline = time.monotonic() + WAIT_PUBLISHERS_S
    while time.monotonic() < deadline and len(infos) < len(topics):
        for topic in topics:
            pubs = node.get_publishers_info_by_topic(topic)
            if pubs:
                infos[topic] = pubs
        rclpy.spin_once(node, timeout_sec=0.2)
    for topic in topics:
        if topic not in infos:
            print('record2: %s has no publisher after %.0f s: not recorded' % (topic, WAIT_PUBLISHERS_S),
                  flush=True)
    msgtypes = sorted({p.topic_type for pubs in infos.values() for p in pubs})
    store = typestore_for(msgtypes)
    writer = Writer(out, version=8, storage_plugin=StoragePlugin.MCAP)
    if COMPRESSION != 'none':
        writer.set_compression(CompressionMode[COMPRESSION.upper()], CompressionFormat.ZSTD)
    writer.open()
    counts: Dict[str, int] = {}
    recording: List[int] = []
    subs = []
    for topic, pubs in infos.items():
        msgtype = pubs[0].topic_type
        conn = None if topic in unwritten else writer.add_connection(
            topic, msgtype, typestore=store, offered_qos_profiles=[qos_of(p) for p in pubs])
        reliable = all(p.qos_profile.reliability == ReliabilityPolicy.RELIABLE for p in pubs)
        latched = all(p.qos_profile.durability == DurabilityPolicy.TRANSIENT_LOCAL for p in pubs)
        qos = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=100,
                         reliability=ReliabilityPolicy.RELIABLE if reliable else ReliabilityPolicy.BEST_EFFORT,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL if latched else DurabilityPolicy.VOLATILE)
        msgclass = _msg_class(msgtype)
        counts[topic] = 0

        def cb(raw, conn=conn, topic=topic, latched=latched):
            if conn is None or (not recording and not latched):   # a latched message is kept: it comes once
                return
            writer.write(conn, time.time_ns(), bytes(raw))
            counts[topic] += 1
        subs.append(node.create_subscription(msgclass, topic, cb, qos, raw=True))
    stop: List[int] = []
    signal.signal(signal.SIGINT, lambda *_: stop.append(1))
    signal.signal(signal.SIGTERM, lambda *_: stop.append(1))
    end = time.monotonic() + WARMUP_S
    while time.monotonic() < end and not stop:
        rclpy.spin_once(node, timeout_sec=0.05)
    if ON_SIGNAL:
        go: List[int] = []
        signal.signal(signal.SIGUSR1, lambda *_: go.append(1))
        print('record2: subscribed, recording on SIGUSR1', flush=True)
        while not go and not stop:
            rclpy.spin_once(node, timeout_sec=0.05)
    recording.append(1)
    print('record2: recording %d topics for %.1f s into %s' % (len(subs), seconds, out), flush=True)
    end = time.monotonic() + seconds
    while time.monotonic() < end and not stop:
        rclpy.spin_once(node, timeout_sec=0.05)
    writer.close()
    for topic in topics:
        if topic in unwritten:
            print('record2: %-40s subscribed, not recorded' % topic)
        else:
            print('record2: %-40s %5d messages' % (topic, counts.get(topic, 0)))
    node.destroy_node()
    rclpy.shutdown()
    return 0


def _msg_class(msgtype: str):
    import importlib
    pkg, _, name = msgtype.split('/')
    return getattr(importlib.import_module('%s.msg' % pkg), name)


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
