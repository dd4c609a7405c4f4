"""Which robot a live run is talking to, as naoqi_driver says it.

ros-naoqi/naoqi_driver publishes the robot's identity once, latched, on `<namespace>/info`
(naoqi_bridge_msgs/StringStamped): src/naoqi_driver.cpp:617-633 registers the info converter
at 0 Hz ("published once ... the publisher is latched"), src/publishers/info.cpp:38 advertises
it latched, and src/converters/info.cpp:40-56 reads these ALMemory keys with getListData and
joins them as "key: value ; key: value" (lines 73-88):

  RobotConfig/Head/FullHeadId, Device/DeviceList/ChestBoard/BodyId, RobotConfig/Body/Type,
  RobotConfig/Body/BaseVersion, ... (arm, hand, leg, platform versions)

The chest board's BodyId is the robot's serial number: the one value that tells two Pepper
robots apart, so it is the identity here. The driver's other offer, the service
`/naoqi_driver/get_robot_config` (src/naoqi_driver.cpp:950, src/services/robot_config.cpp:37-40),
answers naoqi_bridge_msgs/RobotInfo (src/helpers/driver_helpers.cpp:34-250): type, model and
versions, no serial number, so it cannot tell two robots of one model apart and is not used.

Seen with the real driver (built from ros-naoqi/naoqi_driver aed1b87) against the fake NAOqi:
in 3 of 8 starts the topic was advertised but never sent (15 s of waiting in one). The converter
runs once at 0 Hz (naoqi_driver.cpp:239-243 drops it from the queue after its one turn) and is
only published if publishing is enabled at that moment (line 202); init() starts the loop (line
158) before setMasterURINet enables publishing (line 1041), the likely cause. A run then says
the identity is unknown.

On ROS 2, naoqi_driver2 registers the same converter on `/info` (src/naoqi_driver.cpp:683-692),
and its comment says latched (:675-681), but the publisher is its BasicPublisher's plain
`create_publisher<T>(topic, 10)` (src/publishers/basic.hpp:72, info.hpp): volatile. The one
message goes out at start-up and a node started later never receives it. read_live2 follows the
behaviour: it reads /info only from a transient-local publisher, and otherwise says why the
identity is unknown.

The lookup never hangs or fails a run: the master is asked which topic of that type is
published (one call), the latched message is awaited for at most WAIT seconds, and anything
that goes wrong leaves the identity unknown with the reason.
"""
import threading
from dataclasses import dataclass, field
from typing import Any, Callable, Dict, Iterable, Optional, Sequence

from .naoqi_msgs import STRING_STAMPED_TYPE

BODY_ID = 'Device/DeviceList/ChestBoard/BodyId'
HEAD_ID = 'RobotConfig/Head/FullHeadId'
BODY_TYPE = 'RobotConfig/Body/Type'
BASE_VERSION = 'RobotConfig/Body/BaseVersion'
# A latched message arrives as soon as the subscriber connects (tens of ms on a robot's
# network); 2 s covers a loaded machine and keeps an absent or silent driver from delaying a run.
WAIT = 2.0


@dataclass
class Identity:
    """The robot's identity (`body_id`, '' when unknown) and `why` it is unknown."""
    body_id: str = ''
    values: Dict[str, str] = field(default_factory=dict)     # every key: value of the message
    topic: str = ''
    why: str = ''

    def to_dict(self) -> Dict[str, str]:
        """What the results keep as "robot_info"."""
        if not self.body_id:
            return {'unknown': self.why}
        out = {'body_id': self.body_id, 'topic': self.topic}
        for name, key in (('head_id', HEAD_ID), ('body_type', BODY_TYPE), ('base_version', BASE_VERSION)):
            if self.values.get(key):
                out[name] = self.values[key]
        return out


def parse_info(text: str) -> Dict[str, str]:
    """The key: value pairs of naoqi_driver's info message (src/converters/info.cpp:83-88 joins
    them with " ; "); a part without ": " is left out."""
    out = {}
    for part in text.split(' ; '):
        key, sep, value = part.partition(': ')
        if sep and key.strip():
            out[key.strip()] = value.strip()
    return out


def from_text(text: str, topic: str) -> Identity:
    values = parse_info(text)
    body_id = values.get(BODY_ID, '')
    if not body_id:
        return Identity(values=values, topic=topic,
                        why='%s names no %s' % (topic, BODY_ID))
    return Identity(body_id, values, topic)


def unknown(why: str) -> Identity:
    return Identity(why=why)


def info_topic(published: Iterable[Sequence[str]]) -> Optional[str]:
    """The driver's info topic among the master's published [topic, type] pairs: the
    StringStamped topic named .../info (its namespace is the driver's --namespace)."""
    names = sorted(t for t, kind in published if kind == STRING_STAMPED_TYPE and t.rsplit('/', 1)[-1] == 'info')
    return names[0] if names else None


def read_live(caller_id: str, wait: float = WAIT) -> Identity:
    """The identity the driver on the current master publishes (rospy initialised)."""
    try:
        import rosgraph
        import rospy

        from .naoqi_msgs import known_class
        topic = info_topic(rosgraph.Master(caller_id).getPublishedTopics(''))
        if topic is None:
            return unknown('no driver publishes an info topic (naoqi_bridge_msgs/StringStamped)')
        got = _first_data(lambda take: rospy.Subscriber(topic, known_class(STRING_STAMPED_TYPE), take,
                                                        queue_size=1), wait)
        if got is None:
            # naoqi_driver sends it once, at start-up, and sometimes never (docs/drift.md)
            return unknown('%s is advertised but sent nothing within %g s (naoqi_driver sends it once at '
                           'start-up, and not always)' % (topic, wait))
        return from_text(got, topic)
    except Exception as e:     # the identity is a nicety: it never stops a run
        return unknown('cannot read the driver\'s info topic: %s: %s' % (type(e).__name__, e))


def read_live2(graph: Any, subscriber: Callable[..., Any], wait: float = WAIT) -> Identity:
    """The identity the driver on the ROS 2 graph publishes (sources/live2.Ros2Graph);
    `subscriber` is rosapi.subscriber, handed in by the caller (rosapi sits above sources)."""
    try:
        from rclpy.qos import DurabilityPolicy

        from .ros2types import ros1_name
        published = [(t, ros1_name(kinds[0])) for t, kinds in graph.topic_types().items() if kinds]
        topic = info_topic(published)
        if topic is None:
            return unknown('no driver publishes an info topic (naoqi_bridge_msgs/StringStamped)')
        pubs = graph.publishers(topic)
        if not pubs or any(p.qos_profile.durability != DurabilityPolicy.TRANSIENT_LOCAL for p in pubs):
            return unknown('%s is published volatile: naoqi_driver2 sends it once at start-up '
                           '(src/publishers/basic.hpp:72), so a node started later never receives it'
                           % topic)
        got = _first_data(lambda take: subscriber(topic, STRING_STAMPED_TYPE, take, queue_size=1,
                                                  latched=True), wait)
        if got is None:
            return unknown('%s is published but sent nothing within %g s' % (topic, wait))
        return from_text(got, topic)
    except Exception as e:     # the identity is a nicety: it never stops a run
        return unknown('cannot read the driver\'s info topic: %s: %s' % (type(e).__name__, e))


def _first_data(subscribe: Callable[[Callable[[Any], None]], Any], wait: float) -> Optional[str]:
    """The `data` of the first message a subscription (`subscribe(callback)`, unregistered
    after) delivers within `wait` s; None when none came."""
    got: Dict[str, str] = {}
    event = threading.Event()

    def take(msg: Any) -> None:
        got.setdefault('data', str(msg.data))
        event.set()

    sub = subscribe(take)
    try:
        event.wait(wait)
    finally:
        sub.unregister()
    return got.get('data')
