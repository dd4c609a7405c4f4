"""sensorTest on a live ROS 2 graph (ROS_VERSION=2): the rclpy side of run_live (cli.py).

Everything from the plan on is shared with ROS 1 (cli.execute); what differs is where messages
come from (sources/live2.py) and the defaults: on ROS 2 the robot's driver is naoqi_driver2, so
its topics file (data/naoqi_driver2Topics.dat: /laser, /sonar/front, /imu/base, /odom, ...) and
its driver profile (`naoqi_driver2` in the expectations file) are the defaults on the robot
platform; --topics and --driver choose others.

Options come from the command line and, as the private params on ROS 1, from the node's ROS 2
parameters (`--ros-args -p duration:=5`, `--params-file FILE` with a `sensorTest:` or `/**:`
section): the same names (docs/options.md), the command line winning; each one used is
reported with its origin in the run header and the results (param_sources).
"""
import os
import time
from typing import Any, Callable, Dict, List, Optional, Tuple

from .plan import options, settings
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


def read_parameters(graph: Any) -> Tuple[Options, Dict[str, str]]:
    """(Options, {name: origin}) from the node's ROS 2 parameters (options.from_params)."""
    origins: Dict[str, str] = {}

    def get(key: str, default: Any = None) -> Any:
        name = key.lstrip('~')
        value = graph.parameter(name)
        if value is None or value == '':
            return default
        origins[name] = 'ROS 2 parameter %s (--ros-args -p or --params-file)' % name
        return list(value) if isinstance(value, (list, tuple)) else value

    return options.from_params(get, what=lambda name: 'ROS 2 parameter %s' % name), origins


def run_live2(cli: Options, ros_args: Optional[List[str]], execute: Callable[..., int],
              check_output_dir: Callable[[str], None]) -> int:
    """sensorTest's run on ROS 2; `execute` and `check_output_dir` are cli.py's."""
    from . import rosapi
    from .sources import identity, live2
    try:
        graph = live2.Ros2Graph(args=['sensorTest'] + list(ros_args or []), parameters=True)
    except ImportError as e:
        raise ConfigError('ROS_VERSION is 2 but rclpy cannot be imported (%s)' % e,
                          fix='source your ROS 2 setup file (e.g. /opt/ros/humble/setup.bash), '
                              'or unset ROS_VERSION to run on ROS 1') from None
    try:
        params, from_params = read_parameters(graph)
        merged, notes = ros2_options(params.merged(cli))
        plan: TestPlan = settings.load_plan(merged)
        for note in notes:
            print('sensorTest: note: %s' % note, flush=True)
        check_output_dir(plan.output_dir)
        from_params = {k: v for k, v in from_params.items() if getattr(cli, k, None) is None}
        robot = identity.read_live2(graph, rosapi.subscriber) if plan.platform == 'robot' else None
        source = live2.Ros2LiveSource(graph, os.path.join(settings.package_dir(), 'msg'))
        return execute(plan, source, time.monotonic, 'live', from_params, robot)
    finally:
        graph.shutdown()
