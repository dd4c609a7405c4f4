"""pepperEmulator on ROS 2 (ROS_VERSION=2): a Pepper as naoqi_driver2 publishes it, over rclpy.

The same publishers, body and motion commands as on ROS 1 (node.py), behind rosapi.py. What
differs is naoqi_driver2's side of things:
* its node is named naoqi_driver (ros-naoqi/naoqi_driver2 launch/naoqi_driver.launch.py) and
  publishes at the root: the topics file data/naoqi_driver2Topics.dat is the default;
* it is ros-naoqi/naoqi_driver ported to ROS 2 (same converters: laser layout, odometry frames,
  AudioBuffer from ALAudioDevice, the touch events, /diagnostics): the robot-stock profile is
  the default, with the microphones published directly (no audio bridge on ROS 2);
* its publishers offer naoqi_driver2's QoS: reliable, volatile, keep-last 10 but the sonars
  (1) and /tf (100) (qos2.py), and each camera's camera_info beside its image (camera_info.py);
  held to the real driver's recordings by test/emulator/test_conformance2.py;
* options come from the command line only (`--profile robot`, `--faults ...`); ROS 2
  parameters (`--ros-args -p`) are not read;
* the tree (/tf) needs tf2_msgs, which ROS 2's core has not: without it the emulator says so
  and publishes no /tf.
Ends on SIGINT or SIGTERM (exit 0), as rospy.spin() does on ROS 1.
"""
import dataclasses
import os
import signal
import sys
import threading
from typing import List, Optional, Sequence

from .. import rosapi
from ..plan import settings
from .faults import FaultError

ROS2_NODE = 'naoqi_driver'
TOPICS_FILE = 'naoqi_driver2Topics.dat'


def _own_args(argv: Sequence[str]) -> List[str]:
    from ..ros2run import split_ros_args
    return split_ros_args(list(argv))[0]


def _has_ros2_type(name: str) -> bool:
    from ..sources.ros2wire import msg_class
    try:
        msg_class(name)
        return True
    except ImportError:
        return False


def main2(argv: Optional[Sequence[str]] = None) -> int:
    from ..sources.live2 import Ros2Graph
    from .node import NODE_NAME, Emulator, EmulatorConfig, _parser
    args = _parser().parse_args(_own_args(sys.argv[1:] if argv is None else argv[1:]))
    if args.list_faults:
        import shutil

        from .fault_table import table
        print(table(max(60, shutil.get_terminal_size((80, 20)).columns - 1)))
        return 0
    # the identity on naoqi_driver2's /info (src/naoqi_driver.cpp:683-692), once, volatile (info.py)
    values = dict(profile='robot-stock',
                  topics_file=os.path.join(settings.package_dir(), 'data', TOPICS_FILE))
    values.update({k: v for k, v in vars(args).items() if v is not None and k != 'list_faults'})
    try:
        config = EmulatorConfig(values)
    except (settings.ConfigError, FaultError) as e:
        print('%s: error: %s' % (NODE_NAME, e), file=sys.stderr)
        return 2
    notes = []
    if not _has_ros2_type('tf2_msgs/msg/TFMessage'):
        sensors = tuple(s for s in config.profile_spec.sensors if s.family != 'tf')
        if len(sensors) != len(config.profile_spec.sensors):
            config.profile_spec = dataclasses.replace(config.profile_spec, sensors=sensors)
            notes.append('no /tf: tf2_msgs is not installed in this ROS 2')
    stop = threading.Event()
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, lambda *_: stop.set())
    graph = Ros2Graph(ROS2_NODE)
    emulator = Emulator(config)
    try:
        emulator.start()
        for note in list(config.profile_spec.notes) + notes:
            rosapi.loginfo('pepperEmulator: %s', note)
        for what in config.ignored:
            rosapi.logwarn('pepperEmulator: ignored %s', what)
        rosapi.loginfo(emulator.summary_line())
        while not stop.wait(0.2) and graph.ok:
            pass
    finally:
        emulator.stop()
        counts = ', '.join('%s %d' % (t.spec.name, t.published) for t in emulator.threads)
        print('pepperEmulator: stopped; messages published: %s' % counts, flush=True)
        graph.shutdown()
    return 0
