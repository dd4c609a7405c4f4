#!/usr/bin/env python3
"""The commanded motion of the golden `move` bag (record-golden.sh move; on ROS 2, with
ROS_VERSION=2, the same through naoqi_driver2's subscribers: record-golden2.sh): while rosbag records,
the robot is stopped, the head yaws to +0.5 rad and back, then the base turns +0.5 rad in place, through the very
topics naoqi_driver subscribes to (/joint_angles: src/subscribers/teleop.cpp;
/move_base_simple/goal in base_footprint: src/subscribers/moveto.cpp), sent with the package's
own publishers (motion/commands.py). Prints each command with its time, for the manifest."""
import sys
import time

from pepper_interface_tests.motion.commands import Commands
from pepper_interface_tests.sources.live2 import ros_version

# (seconds after the start, what): first a zero /cmd_vel (ALMotion.move(0, 0, 0):
# src/subscribers/teleop.cpp), the stop any commander sends first: the fake NAOqi's robot drives
# slowly in a circle until then (emulator/body.py, the idle drive); then the head at speed 0.1
# (~0.73 rad/s) takes ~0.7 s per step;
# the base turns at up to 1 rad/s with 0.75 rad/s^2 (ALMotion's defaults): ~1.6 s for 0.5 rad
PLAN = [(0.0, 'stop', 0.0), (2.0, 'head', 0.5), (4.0, 'head', 0.0), (6.0, 'turn', 0.5)]


def main() -> int:
    graph = None
    if ros_version() == 2:      # tools/real-driver2/record-golden2.sh: naoqi_driver2's subscribers
        from pepper_interface_tests.sources.live2 import Ros2Graph
        graph = Ros2Graph('golden_move')
    else:
        import rospy
        rospy.init_node('golden_move', anonymous=True, disable_signals=True)
    cmd = Commands()
    for _ in range(50):      # the driver's subscribers
        if not cmd.missing():
            break
        time.sleep(0.1)
    start = time.monotonic()
    for at, what, value in PLAN:
        time.sleep(max(0.0, start + at - time.monotonic()))
        ok = cmd.stop() if what == 'stop' else cmd.head(value, 0.1) if what == 'head' else cmd.turn(value)
        print('%.1f s %s %+.2f rad%s' % (time.monotonic() - start, what, value, '' if ok else ' (not sent)'),
              flush=True)
    time.sleep(2.5)
    cmd.close()
    if graph is not None:
        graph.shutdown()
    return 0


if __name__ == '__main__':
    sys.exit(main())
