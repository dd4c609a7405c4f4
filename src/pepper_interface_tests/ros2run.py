"""sensorTest on a live ROS 2 graph (ROS_VERSION=2): the rclpy side of run_live (cli.py).

Everything from the plan on is shared with ROS 1 (cli.execute); what differs is where messages
come from (sources/live2.py) and the defaults: on ROS 2 the robot's driver is naoqi_driver2, so
its topics file (data/naoqi_driver2Topics.dat: /laser, /sonar/front, /imu/base, /odom, ...) and
its driver profile (`naoqi_driver2` in the expectations file) are the defaults on the robot
platform; --topics and --driver choose others. Options come from the command line (ROS 2
parameters, `--ros-args -p`, are not read: the ROS 2 node is created after the plan).
"""
import os
import time
from typing import Callable, List, Optional, Tuple

from .plan import settings
from .plan.options import Options
from .plan.settings import ConfigError, TestPlan
from .sources.ros2plan import STOCK, TOPICS_FILE


def split_ros_args(argv: List[str]) -> Tuple[List[str], List[str]]:
    """(sensorTest's own arguments, the ROS 2 arguments): `--ros-args ... [--]` is rclpy's."""
    own: List[str] = []
    ros: List[str] = []
    inside = False
    for a in argv:
        if a == '--ros-args':
            inside = True
            ros.append(a)
        elif inside and a == '--':
            inside = False
        elif inside:
            ros.append(a)
        else:
            own.append(a)
    return own, ros


def ros2_options(cli: Options) -> Tuple[Options, List[str]]:
    """The options with naoqi_driver2's defaults where not given, and notes saying so."""
    notes: List[str] = []
    platform = cli.platform or 'robot'
    if platform != 'robot':
        return cli, notes
    if not cli.topics:
        path = os.path.join(cli.topics_dir or os.path.join(settings.package_dir(), 'data'), TOPICS_FILE)
        cli = settings.replace(cli, topics=path)
        notes.append('ROS 2: topics of naoqi_driver2 (%s); --topics FILE chooses another file' % path)
    if not cli.driver:
        cli = settings.replace(cli, driver=STOCK)
        notes.append('ROS 2: expectations of the driver profile %s; --driver NAME chooses another'
                     % STOCK)
    return cli, notes


def run_live2(cli: Options, ros_args: Optional[List[str]], execute: Callable[..., int],
              check_output_dir: Callable[[str], None]) -> int:
    """sensorTest's run on ROS 2; `execute` and `check_output_dir` are cli.py's."""
    from .sources import live2
    cli, notes = ros2_options(cli)
    plan: TestPlan = settings.load_plan(cli)
    for note in notes:
        print('sensorTest: note: %s' % note, flush=True)
    check_output_dir(plan.output_dir)
    try:
        graph = live2.Ros2Graph(args=['sensorTest'] + list(ros_args or []))
    except ImportError as e:
        raise ConfigError('ROS_VERSION is 2 but rclpy cannot be imported (%s)' % e,
                          fix='source your ROS 2 setup file (e.g. /opt/ros/humble/setup.bash), '
                              'or unset ROS_VERSION to run on ROS 1') from None
    try:
        source = live2.Ros2LiveSource(graph, os.path.join(settings.package_dir(), 'msg'))
        return execute(plan, source, time.monotonic, 'live')
    finally:
        graph.shutdown()
