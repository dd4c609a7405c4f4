"""sensorTest's own lag told apart from the sensor's (sensors/lag.py, issue 41): sensorTest
stopped by a real SIGSTOP for longer than max_delay (5 s) while an IMU publishes on time finds
the held messages' stamps old once it runs again: NOT JUDGED naming the PC, exit code 4, never
"stale data". Stamps really that old still FAIL (test_node.py's growing delay, the clock offset)."""
import os
import signal
import time

from rosmaster import wait_connected
from sensor_test_runs import Publishers, Running, topic_of, write_topics

PREFIX = '/own_lag'


def test_messages_held_in_a_stopped_sensor_test_are_not_judged_stale(master, tmp_path):
    out = tmp_path / 'out'
    topic = topic_of(PREFIX, 'imu')
    with Publishers(master, tmp_path) as p:
        p.start('imu', topic, 'imu')
        p.wait([topic])
        topics = write_topics(tmp_path / 't.dat', PREFIX, ['imu'])
        r = Running(['--topics', topics, '--sensors', 'imu', '--duration', '12', '--wait', '3',
                     '--no-report', '--output-dir', str(out)], master.env(), out)
        r.wait_for('start  imu')
        wait_connected(master, '/sensorTest', topic)
        time.sleep(1.0)          # some messages handled on time first
        os.killpg(r.proc.pid, signal.SIGSTOP)
        try:
            time.sleep(6.5)      # the stall under test: longer than max_delay (5 s)
        finally:
            os.killpg(r.proc.pid, signal.SIGCONT)
        result = r.finish(60)
    imu = result.sensors['imu']
    assert imu['verdict'] == 'NOT JUDGED' and result.rc == 4, (result, imu['reasons'])
    assert not any('stale data' in x for x in imu['reasons'] + imu['warnings']), imu
    reason = imu['reasons'][0]
    assert reason.startswith('PC busy: header stamps up to ') and 'waited in sensorTest itself' in reason, reason
    assert 'load average' in reason and 'sensorTest up to' in reason, reason
    assert result.json['exit_code'] == 4
    assert 'could not judge everything' in result.stdout, result.stdout
    print(reason)
