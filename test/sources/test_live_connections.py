"""Integration: on ROS 1 the live source counts a subscriber's connections to publishers other
than this node (sources/live.py _other_connections). rospy connects a node's subscriber to the
same node's publisher of the topic: sensorTest publishes /diagnostics and robotHealth listens to
it, and counted, its own publisher made "the topic has a publisher" true with no driver at all
(robotHealth's busy-PC wait, sensors/health.py). Real rospy nodes on a real master."""
import subprocess
import sys

from rosmaster import kill_group, spawn, wait_until

NODE = '''
import sys, time
import rospy
from diagnostic_msgs.msg import DiagnosticArray
from pepper_interface_tests.sources.live import _other_connections
rospy.init_node('own_diag', anonymous=True, disable_signals=True)
pub = rospy.Publisher('/diag_own', DiagnosticArray, queue_size=1)
sub = rospy.Subscriber('/diag_own', DiagnosticArray, lambda m: None)
for want in (1, 2):             # this node's publisher, then another node's too
    t = time.time()
    while sub.get_num_connections() < want and time.time() - t < 30:
        time.sleep(0.05)
    print('all %d other %d' % (sub.get_num_connections(), _other_connections(sub)), flush=True)
    if want == 1:
        print('ready', flush=True)
        sys.stdin.readline()
'''


def test_a_subscriber_connected_to_this_nodes_own_publisher_counts_no_other(master, tmp_path):
    log = tmp_path / 'node.log'
    with open(str(log), 'w') as f:
        node = spawn([sys.executable, '-c', NODE], master.env(), stdout=f, stderr=subprocess.STDOUT,
                     stdin=subprocess.PIPE)
    other = None
    try:
        wait_until(lambda: 'ready' in log.read_text(), 60, log.read_text)
        assert 'all 1 other 0' in log.read_text(), log.read_text()
        other = spawn(['rostopic', 'pub', '-r', '1', '/diag_own', 'diagnostic_msgs/DiagnosticArray', '{}'],
                      master.env(), stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT)
        node.stdin.write(b'\n')
        node.stdin.flush()
        wait_until(lambda: log.read_text().count('all ') == 2, 60, log.read_text)
        assert 'all 2 other 1' in log.read_text(), log.read_text()
    finally:
        if other is not None:
            kill_group(other)
        kill_group(node)
