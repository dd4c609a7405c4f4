"""The tree's stamps on a busy PC or a bursty WiFi (sensors/tf.py, tree.FRESHEST, issue 41):
a real rospy node publishes naoqi_driver's root of the tree (test/nodes/bursty_tf.py), 50 Hz,
each message stamped when it is made, and the real sensorTest judges the tf row.
- delivered as a starved reader's backlog builds and drains (up to 2.2 s behind, then caught up;
  no pause longer than 100 ms): the median message is over 0.5 s old when it arrives, the
  freshest are not: the stamps are right, the delivery was late: a warning naming it, never
  "old when they arrive" (which the median alone gave);
- stamps 0.8 s behind (a driver clock behind, steadily or in bursts): FAIL, as before."""
import os
import subprocess
import sys

import pytest

from rosmaster import NODES, kill_group, spawn, wait_until
from sensor_test_runs import Running, wait_registered

TOPIC = '/bursty_tf/tf'


def judge_tf(master, tmp_path, offset, bursts):
    log = tmp_path / 'tf.log'
    with open(str(log), 'w') as f:
        pub = spawn([sys.executable, os.path.join(NODES, 'bursty_tf.py'), TOPIC, str(offset)]
                    + (['--bursts'] if bursts else []), master.env(), stdout=f, stderr=subprocess.STDOUT)
    try:
        wait_until(lambda: 'tf up' in log.read_text(), 30, log.read_text)
        wait_registered(master, [TOPIC])
        topics = tmp_path / 't.dat'
        topics.write_text('tf %s\n' % TOPIC)
        out = tmp_path / 'out'
        r = Running(['--topics', str(topics), '--sensors', 'tf', '--duration', '7', '--wait', '4',
                     '--no-report', '--output-dir', str(out)], master.env(), out).finish(90)
    finally:
        kill_group(pub)
    return r.sensors['tf'], r


@pytest.mark.parametrize('offset, bursts, verdict', [
    (0.0, True, 'PASS'),
    (-0.8, False, 'FAIL'),
    (-0.8, True, 'FAIL'),
], ids=['right-stamps-in-bursts', 'clock-behind-steady', 'clock-behind-in-bursts'])
def test_late_delivery_is_not_stale_stamps(master, tmp_path, offset, bursts, verdict):
    tf, r = judge_tf(master, tmp_path, offset, bursts)
    stale = [x for x in tf['reasons'] if 'old when they arrive' in x]
    assert tf['verdict'] == verdict, (tf['reasons'], tf['warnings'], r.stdout[-1500:])
    if verdict == 'FAIL':
        assert stale and 'even the freshest tenth' in stale[0], tf['reasons']
    else:
        assert not stale
        late = [w for w in tf['warnings'] if w.startswith('/tf came late in bursts')]
        assert late and 'load average' in late[0], tf['warnings']
        median = float(late[0].split('stamps ')[1].split(' s old')[0])
        assert median > 0.5, late      # what the median alone called stale
    print(tf['reasons'] + tf['warnings'])
