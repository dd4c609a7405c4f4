"""sensorTest's own lag told apart from the sensor's (sensors/lag.py, issue 41): sensorTest
stopped by a real SIGSTOP for longer than max_delay (5 s) while an IMU publishes on time finds
the held messages' stamps old once it runs again: NOT JUDGED naming the PC, exit code 4, never
"stale data". Stamps really that old still FAIL (test_node.py's growing delay, the clock offset).
A rate below its band on a busy PC (sensorTest keeping up) still FAILs, with a hint that a
publisher on this PC may have been starved, naming the load (lag.starved_hint)."""
import os
import subprocess
import sys
import time

from rosmaster import pause_group, wait_connected, wait_until
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
                     '--no-report', '--output-dir', str(out)], dict(master.env(), COLUMNS='80'), out)
        r.wait_for('start  imu')
        wait_connected(master, '/sensorTest', topic)
        time.sleep(1.0)          # some messages handled on time first
        pause_group(r.proc, 6.5)     # the stall under test: longer than max_delay (5 s)
        result = r.finish(60)
    imu = result.sensors['imu']
    assert imu['verdict'] == 'NOT JUDGED' and result.rc == 4, (result, imu['reasons'])
    assert not any('stale data' in x for x in imu['reasons'] + imu['warnings']), imu
    reason = imu['reasons'][0]
    assert reason.startswith('PC busy: header stamps up to ') and 'waited in sensorTest itself' in reason, reason
    assert 'load average' in reason and 'sensorTest up to' in reason, reason
    assert result.json['exit_code'] == 4
    assert 'could not judge everything' in result.stdout, result.stdout
    # at 80 columns through a pipe: one block per sensor, the verdict column as wide as NOT JUDGED;
    # every line fits but a path, never cut (test_terminal_width.py)
    assert not [ln for ln in result.stdout.splitlines() if len(ln) > 80 and len(ln.split()) > 1], result.stdout
    assert any(ln.startswith('imu' + ' ' * 20 + 'NOT JUDGED ') and ' msgs, ' in ln
               for ln in result.stdout.splitlines()), result.stdout
    print(reason)


# ------------------------------------------------------------------ a publisher starved on this PC

def test_the_starved_publisher_hint_needs_a_busy_pc_and_a_live_run():
    from pepper_interface_tests.sensors.lag import OwnLag, StallProbe, starved_hint
    lag = OwnLag(StallProbe.shared())
    lag.cores, lag.load = 2, 8.6
    assert 'load average 8.6 on 2 cores' in starved_hint(lag) and 'starved' in starved_hint(lag)
    lag.load = 2.0          # as many runnable processes as cores: not busy (lag.BUSY_LOAD_PER_CORE)
    assert starved_hint(lag) == ''
    assert starved_hint(OwnLag()) == '' and starved_hint(None) == ''   # a bag: nothing measured


def test_a_low_rate_on_a_busy_pc_still_fails_and_says_the_publisher_may_be_starved(master, tmp_path):
    """An IMU at 2 Hz (band 4-16 Hz) beside busy loops (the load above the cores): FAIL, and the
    reason adds that a publisher on this PC may have been starved, naming the load."""
    cores = os.cpu_count() or 1
    loops = []
    try:
        if os.getloadavg()[0] <= cores + 0.5:     # the machine is not busy enough by itself
            loops = [subprocess.Popen([sys.executable, '-c', 'while True: pass']) for _ in range(2 * cores)]
            wait_until(lambda: os.getloadavg()[0] > cores + 0.5, 150, lambda: 'load %.1f' % os.getloadavg()[0],
                       every=1.0)
        out = tmp_path / 'out'
        topic = topic_of(PREFIX, 'imu')
        with Publishers(master, tmp_path) as p:
            p.start('imu', topic, 'imu', '--rate', '2')
            p.wait([topic])
            topics = write_topics(tmp_path / 't.dat', PREFIX, ['imu'])
            result = Running(['--topics', topics, '--sensors', 'imu', '--duration', '5', '--wait', '3',
                              '--no-report', '--output-dir', str(out)], master.env(), out).finish(90)
    finally:
        for proc in loops:
            proc.kill()
            proc.wait()
    imu = result.sensors['imu']
    low = [r for r in imu['reasons'] if r.startswith('rate ') and 'outside the expected 4-16 Hz' in r]
    assert imu['verdict'] == 'FAIL' and low, imu['reasons']
    assert 'may have been starved' in low[0] and 'load average' in low[0], low
    load = float(low[0].split('load average ')[1].split()[0])
    assert load > cores, low
    print(low[0])
