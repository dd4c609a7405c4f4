"""What a ROS 2 recording says about how to check it: the topics file and the driver profile.

* Topics: naoqi_driver2 publishes at the root (/laser, /imu/base, ...; docs/drivers.md), not under
  /naoqi_driver/ as the ROS 1 driver does. When the recording holds more of the topics of
  data/naoqi_driver2Topics.dat than of the plan's own file, that file is used and a note says so;
  --topics FILE chooses the file instead.
* Driver profile (the `drivers:` section of the expectations file): yohatad/naoqi_driver2 is told
  from ros-naoqi/naoqi_driver2 by what it publishes: odometry in the frame pepper_odom
  (its src/converters/odom.cpp:105) or a laser reading of +inf (its laser.cpp encodeRange; the
  stock converter only publishes finite distances, naoqi_driver2 laser.cpp:160-199). --driver NAME
  chooses the profile instead.
"""
import math
import os
from typing import TYPE_CHECKING, List, Sequence, Tuple

from ..plan import settings
from ..plan.options import Options

if TYPE_CHECKING:
    from ..plan.settings import TestPlan
    from .ros2bag import Ros2BagSource

TOPICS_FILE = 'naoqi_driver2Topics.dat'
STOCK, FORK = 'naoqi_driver2', 'yohatad_naoqi_driver2'
LASER_PEEK = 20      # scans looked at for a +inf reading (2 s at naoqi_driver2's 10 Hz)


def _found(plan: 'TestPlan', listened: Sequence[str], types: dict) -> Tuple[int, int]:
    topics = [s.topic for s in plan.sensors if s.name in listened and s.topic is not None]
    return sum(1 for t in topics if t in types), len(topics)


def driver_of(source: 'Ros2BagSource', plan: 'TestPlan') -> Tuple[str, str]:
    """(driver profile, why) for a ROS 2 recording of Pepper."""
    topics = {s.name: s.topic for s in plan.sensors if s.topic}
    for odom_topic in dict.fromkeys((topics.get('odometry'), '/odom', '/pepper_odom')):
        if odom_topic:
            first = source.peek(odom_topic)
            if first and getattr(first[0].header, 'frame_id', '') == 'pepper_odom':
                return FORK, 'its odometry is in the frame pepper_odom (yohatad/naoqi_driver2 odom.cpp:105)'
    laser = topics.get('laser')
    if laser:
        for scan in source.peek(laser, LASER_PEEK):
            if any(r == math.inf for r in scan.ranges):
                return FORK, ('its laser reads +inf beyond range_max (yohatad/naoqi_driver2 '
                              'laser.cpp encodeRange)')
    return STOCK, 'a ROS 2 recording (ros-naoqi/naoqi_driver2)'


def recording_plan(plan: 'TestPlan', cli: Options, source: 'Ros2BagSource',
                   listened: Sequence[str]) -> Tuple['TestPlan', List[str]]:
    """The plan for a ROS 2 recording (topics file and driver profile picked from what it holds,
    unless given) and the notes that say what was picked."""
    notes: List[str] = []
    if plan.platform != 'robot':
        return plan, notes
    options = cli
    if not cli.topics:
        path = os.path.join(cli.topics_dir or os.path.join(settings.package_dir(), 'data'), TOPICS_FILE)
        if os.path.exists(path):
            alt = settings.load_plan(settings.replace(cli, topics=path))
            mine, theirs = _found(plan, listened, source.types), _found(alt, listened, source.types)
            if theirs[0] > mine[0]:
                own = os.path.basename(plan.files.get('topics', ''))
                plan, options = alt, settings.replace(cli, topics=path)
                notes.append('topics of naoqi_driver2 (%s): %d of the %d topics checked are in the '
                             'recording (%d with %s); --topics FILE chooses another file'
                             % (path, theirs[0], theirs[1], mine[0], own))
    if not cli.driver:
        driver, why = driver_of(source, plan)
        plan = settings.load_plan(settings.replace(options, driver=driver))
        notes.append('expectations of the driver profile %s: %s; --driver NAME chooses another'
                     % (driver, why))
    return plan, notes

