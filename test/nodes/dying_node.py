#!/usr/bin/env python3
"""A node of a test launch (test/launch/test_watch.py) that runs AFTER seconds, says why it
stops, and dies, as an emulator node breaking mid-run would:

  dying_node.py rospy AFTER    a rospy node: logs its error (rospy's log file) and exits 1
  dying_node.py screen AFTER   a plain process: prints a line prefixed with its name, then an
                               uncaught exception (a traceback on stderr)
  dying_node.py steady         a rospy node that stays up
"""
import sys
import time

mode = sys.argv[1]
if mode == 'screen':
    print('flaky: INFO: capture started', flush=True)
    time.sleep(float(sys.argv[2]))
    print('flaky: ERROR: the capture device went away', file=sys.stderr, flush=True)
    raise RuntimeError('capture device /dev/fake0 gone')

import rospy  # noqa: E402  (the screen mode runs without ROS)

rospy.init_node('dyingNode' if mode == 'rospy' else 'steady')
rospy.loginfo('up and publishing')
if mode == 'steady':
    rospy.spin()
    sys.exit(0)
time.sleep(float(sys.argv[2]))
rospy.logerr('lost the device /dev/fake0: Input/output error')
sys.exit(1)
