"""The facts of a ROS 2 recording's topics that a driver's format fixes, as bag_facts.py gives
them for a ROS 1 bag: type, frame ids, per type the layout (bag_facts.message_facts, the same
rules), the rate, and what only ROS 2 has: the offered QoS of the publishers (reliability,
durability, history depth) from metadata.yaml. Read with rosbags (no ROS 2 install). For holding
the emulator on ROS 2 against the real naoqi_driver2 (tools/real-driver2/record-golden2.sh)."""
from pathlib import Path

import yaml

from bag_facts import message_facts

RELIABILITY = {1: 'reliable', 2: 'best_effort'}       # rmw_qos_reliability_policy_t
DURABILITY = {1: 'transient_local', 2: 'volatile'}    # rmw_qos_durability_policy_t


def ros1_type(msgtype):
    """'sensor_msgs/msg/Image' -> 'sensor_msgs/Image' (bag_facts' names)."""
    pkg, _, name = msgtype.split('/')
    return '%s/%s' % (pkg, name)


def offered_qos(path):
    """{topic: ((reliability, durability, depth), ...) one per publisher} from metadata.yaml."""
    meta = yaml.safe_load((Path(path) / 'metadata.yaml').read_text())['rosbag2_bagfile_information']
    out = {}
    for t in meta['topics_with_message_count']:
        md = t['topic_metadata']
        profiles = yaml.safe_load(md.get('offered_qos_profiles') or '[]') or []
        out[md['name']] = tuple(sorted((RELIABILITY.get(q['reliability'], q['reliability']),
                                        DURABILITY.get(q['durability'], q['durability']), q['depth'])
                                       for q in profiles))
    return out


class _Audio:
    """An AudioBuffer with the ROS 1 field name bag_facts reads (ROS 2's is channel_map)."""

    def __init__(self, m):
        self.frequency, self.channelMap, self.data = m.frequency, m.channel_map, m.data


class _CameraInfo:
    """A CameraInfo with the ROS 1 field names bag_facts reads (ROS 2's are d, k, r, p)."""

    def __init__(self, m):
        self.width, self.height, self.distortion_model = m.width, m.height, m.distortion_model
        self.D, self.K, self.R, self.P = m.d, m.k, m.r, m.p


ROS1_NAMES = {'AudioBuffer': _Audio, 'CameraInfo': _CameraInfo}


def recording_facts(path):
    """{topic: {'type', 'frames', 'count', 'rate', 'facts', 'qos'}} of a rosbag2 recording."""
    from rosbags.highlevel import AnyReader
    qos = offered_qos(path)
    out = {}
    with AnyReader([Path(path)]) as reader:
        for conn in reader.connections:
            msgtype = ros1_type(conn.msgtype)
            times, frames, facts = [], set(), None
            for _, t, raw in reader.messages(connections=[conn]):
                m = reader.deserialize(raw, conn.msgtype)
                times.append(t / 1e9)
                header = getattr(m, 'header', None)
                if header is not None:
                    frames.add(header.frame_id)
                if facts is None:
                    wrap = ROS1_NAMES.get(msgtype.rsplit('/', 1)[1])
                    facts = message_facts(msgtype, wrap(m) if wrap else m)
            span = times[-1] - times[0] if len(times) > 1 else 0.0
            out[conn.topic] = dict(type=msgtype, frames=frames, count=len(times),
                                   rate=(len(times) - 1) / span if span > 0 else None,
                                   facts=facts or {}, qos=qos.get(conn.topic, ()))
    return out


def differences(real, other, keys=('type', 'frames', 'facts', 'qos')):
    """{(topic, key): text} where `other` differs from `real` (a topic missing on either side too)."""
    out = {}
    for topic in sorted(set(real) | set(other)):
        if topic not in other:
            out[(topic, 'topic')] = 'only in the first recording'
            continue
        if topic not in real:
            out[(topic, 'topic')] = 'only in the second recording'
            continue
        for key in keys:
            if real[topic][key] != other[topic][key]:
                out[(topic, key)] = '%r != %r' % (real[topic][key], other[topic][key])
    return out


def messages(path, topics):
    """(topic, message, receive time in ns) of a rosbag2 recording's `topics`, in time order
    (rosbags' own message classes: ROS 2 field names)."""
    from rosbags.highlevel import AnyReader
    with AnyReader([Path(path)]) as reader:
        conns = [c for c in reader.connections if c.topic in topics]
        for conn, t, raw in reader.messages(connections=conns):
            yield conn.topic, reader.deserialize(raw, conn.msgtype), t


def healthy_recordings(manifest):
    """The manifest's recordings of a healthy robot standing still (healthy_stereo, healthy_xtion)."""
    return sorted(name for name in manifest['recordings'] if name.startswith('healthy_'))
