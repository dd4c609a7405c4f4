"""What a user sees on the terminal: the summary fits the terminal's width (a real pseudo-terminal
with COLUMNS), the parallel progress line is one compact line, output through a pipe has no
carriage returns and few progress lines, and a master where nothing is published is said once,
within seconds. Real roscore, real rospy publishers, the real sensorTest script."""
import os
import pty
import re
import select
import signal
import subprocess
import time

from rosmaster import kill_group, script, spawn
from sensor_test_runs import Publishers, sensor_test, topic_of, write_topics

ANSI = re.compile(r'\x1b\[[0-9;]*[A-Za-z]')


def run_in_pty(args, env, columns, timeout=90):
    """sensorTest with its stdout on a real pseudo-terminal `columns` wide; (rc, raw output)."""
    master_fd, slave_fd = pty.openpty()
    env = dict(env, COLUMNS=str(columns), LINES='40', TERM='xterm')
    env.pop('NO_COLOR', None)
    proc = spawn(script('sensorTest') + list(args), env, stdout=slave_fd, stderr=subprocess.PIPE)
    os.close(slave_fd)
    chunks, deadline = [], time.monotonic() + timeout
    try:
        while time.monotonic() < deadline:
            ready, _, _ = select.select([master_fd], [], [], 0.5)
            if ready:
                try:
                    data = os.read(master_fd, 65536)
                except OSError:      # EIO: the other side closed
                    break
                if not data:
                    break
                chunks.append(data)
            elif proc.poll() is not None:
                break
        proc.wait(10)
    finally:
        if proc.poll() is None:
            kill_group(proc, signal.SIGKILL)
        os.close(master_fd)
    return proc.returncode, b''.join(chunks).decode('utf-8', 'replace')


def screen_lines(raw):
    """Every line as the terminal shows it at some moment (\\r starts a rewritten line)."""
    text = ANSI.sub('', raw).replace('\r\n', '\n')
    return [part for line in text.split('\n') for part in line.split('\r')]


def summary(lines):
    i = next(i for i, ln in enumerate(lines) if ln.startswith('sensor ') or ln.startswith('backSonar'))
    return lines[i:]


def three_sensors(master, tmp_path):
    """backSonar good, laser a wrong type (a long reason), frontSonar silent."""
    prefix = '/tw'
    names = ['backSonar', 'laser', 'frontSonar']
    pubs = Publishers(master, tmp_path)
    pubs.start('backSonar', topic_of(prefix, 'backSonar'), 'range', '--frame', 'SonarBack_frame')
    pubs.start('laser', topic_of(prefix, 'laser'), 'string', '--node', 'wrong_laser')
    pubs.wait([topic_of(prefix, 'backSonar'), topic_of(prefix, 'laser')])
    topics = write_topics(tmp_path / 't.dat', prefix, names)
    return pubs, ['--topics', topics, '--sensors', ','.join(names), '--mode', 'parallel',
                  '--no-report', '--no-record', '--no-show', '--no-history']


def test_summary_and_progress_fit_80_columns_and_narrow_ones_get_blocks(module_master, tmp_path):
    pubs, args = three_sensors(module_master, tmp_path)
    with pubs:
        rc80, raw80 = run_in_pty(args + ['--duration', '3', '--wait', '2',
                                         '--output-dir', str(tmp_path / 'o80')],
                                 module_master.env(), 80)
        rc50, raw50 = run_in_pty(args + ['--duration', '1', '--wait', '1',
                                         '--output-dir', str(tmp_path / 'o50')],
                                 module_master.env(), 50)
        rc120, raw120 = run_in_pty(args + ['--duration', '1', '--wait', '1',
                                           '--output-dir', str(tmp_path / 'o120')],
                                   module_master.env(), 120)
    assert (rc80, rc50, rc120) == (1, 1, 1), raw80
    for raw, width in ((raw80, 80), (raw50, 50), (raw120, 120)):
        lines = screen_lines(raw)
        # a path the user chose may be longer than the line: it is never cut
        too_long = [ln for ln in lines if len(ln.replace(str(tmp_path), '/tmp/x')) > width]
        assert not too_long, (width, too_long)
    lines80 = screen_lines(raw80)
    # progress: one compact line, time left once, counts and the names of the silent/failing
    progress = [ln for ln in lines80 if ln.startswith('  ... ')]
    assert progress, raw80
    assert all(ln.count(' s left') == 1 for ln in progress), progress
    assert any(re.search(r'\d+ s left: 1 receiving, 1 silent \(frontSonar\), 1 failing \(laser\)$', ln)
               for ln in progress), progress
    # 80 columns: one block per sensor, reasons wrapped whole words under it, indented
    table = summary(lines80)
    laser = table.index(next(ln for ln in table if ln.startswith('laser ')))
    assert 'FAIL' in table[laser]
    reason = ' '.join(ln.strip() for ln in table[laser + 1:laser + 4] if ln.startswith('    '))
    assert 'carries std_msgs/String, expected sensor_msgs/LaserScan' in reason, table
    # 120 columns: a table with the reasons in their own column, starting at one column
    table = summary(screen_lines(raw120))
    assert table[0].split() == ['sensor', 'verdict', 'messages', 'rate', 'Hz', 'expected', 'Hz',
                                'reasons'], table
    col = table[0].index('reasons')
    laser = next(ln for ln in table if ln.startswith('laser '))
    assert laser[col:].startswith('topic /tw/laser carries std_msgs/String'), table
    rest = table[table.index(laser) + 1]
    assert rest[:col].strip() == '' and rest[col:].strip(), table


def test_through_a_pipe_progress_has_no_carriage_returns_and_comes_every_few_seconds(
        module_master, tmp_path):
    pubs, args = three_sensors(module_master, tmp_path)
    with pubs:
        r = sensor_test(module_master, tmp_path / 'out', *(args + ['--duration', '8', '--wait', '8']))
    assert r.rc == 1, r
    assert '\r' not in r.stdout and '\x1b[' not in r.stdout, repr(r.stdout)
    progress = [ln for ln in r.stdout.splitlines() if ln.startswith('  ... ')]
    # 8 s window, one line every 5 s at most: 1 (2 with start-up jitter), never one per tick
    assert 1 <= len(progress) <= 2, r.stdout
    assert re.search(r'1 receiving, 1 silent \(frontSonar\), 1 failing \(laser\)$', progress[0]), progress


def test_nothing_published_is_said_once_within_the_wait(master, tmp_path):
    """Robot off / wrong master: 5 listened-to sensors, sequential, --wait 3. Before: 5 x 3 s and
    5 separate "no publisher" lines; now one message after 3 s, every sensor FAIL, exit 1."""
    names = ['backSonar', 'frontSonar', 'laser', 'imu', 'stereoCamera']
    topics = write_topics(tmp_path / 't.dat', '/nothing', names)
    r = sensor_test(master, tmp_path / 'out', '--topics', topics, '--sensors', ','.join(names),
                    '--mode', 'sequential', '--duration', '3', '--wait', '3', '--no-report')
    assert r.rc == 1, r
    assert r.stdout.count('nothing is published') == 1, r.stdout
    said = ' '.join(r.stdout.split('nothing is published', 1)[1].split())
    assert 'ROS_MASTER_URI' in said and master.uri in said and 'after 3 s' in said, said
    assert r.elapsed < 3 + 6, r        # one --wait, not one per sensor (15 s)
    assert [s['name'] for s in r.json['sensors']] == names
    for s in r.json['sensors']:
        assert s['verdict'] == 'FAIL' and s['reasons'][0].startswith(
            'no publisher on /nothing/%s: no sensor topic of this run has a publisher' % s['name']), s
    assert 'Xtion' in r.sensors['stereoCamera']['reasons'][0]     # the per-sensor hint stays


def test_robot_off_every_default_sensor_is_judged_in_one_wait(master, tmp_path):
    """Robot off (issue 24): a bare master, every default robot sensor (robotHealth among them,
    whose /diagnostics sensorTest itself publishes on), sequential, --wait 3. Before: this
    node's own /diagnostics publisher counted as "something is published", so the fast path
    never fired: 16 windows of 3 s, about 49 s, and the long "no publisher" reason per sensor."""
    wait = 3
    r = sensor_test(master, tmp_path / 'out', '--platform', 'robot', '--mode', 'sequential',
                    '--duration', str(wait), '--wait', str(wait), '--no-report', timeout=150)
    assert r.rc == 1, r
    assert r.stdout.count('nothing is published') == 1, r.stdout
    # one --wait for every listened-to sensor, plus the speech check's own wait (it drives
    # itself: one sentence, up to --wait for a subscriber) and start-up; per sensor: 16 x wait
    assert r.elapsed < 3 * wait + 10, r
    listened = [s for s in r.json['sensors'] if s['name'] != 'speech']
    assert len(listened) >= 14 and 'robotHealth' in r.sensors, [s['name'] for s in r.json['sensors']]
    for s in listened:
        assert s['verdict'] == 'FAIL' and s['reasons'][0].startswith(
            'no publisher on %s: no sensor topic of this run has a publisher' % s['topic']), s
    assert '(is the driver running, and is the topic name right?' not in r.stdout, r.stdout


def test_this_nodes_own_diagnostics_are_no_publisher_of_them(master, tmp_path):
    """Something else is published (so each sensor has its own window), nothing but sensorTest
    itself publishes /diagnostics: robotHealth says there is no publisher, as for any topic."""
    with Publishers(master, tmp_path) as pubs:
        pubs.start('backSonar', '/own/backSonar', 'range', '--frame', 'SonarBack_frame')
        pubs.wait(['/own/backSonar'])
        topics = tmp_path / 't.dat'
        topics.write_text('backSonar /own/backSonar\nrobotHealth /diagnostics\n')
        r = sensor_test(master, tmp_path / 'out', '--topics', str(topics), '--sensors',
                        'backSonar,robotHealth', '--mode', 'sequential', '--duration', '2',
                        '--wait', '2', '--no-report')
    assert 'nothing is published' not in r.stdout, r
    assert r.sensors['backSonar']['verdict'] == 'PASS', r
    health = r.sensors['robotHealth']
    assert health['verdict'] == 'FAIL' and health['reasons'][0].startswith(
        'no publisher on /diagnostics (is the driver running'), health


def test_one_publisher_is_enough_to_listen_normally(master, tmp_path):
    """One topic published: the others are judged one by one as before (no early verdict)."""
    names = ['backSonar', 'frontSonar']
    with Publishers(master, tmp_path) as pubs:
        pubs.start('backSonar', topic_of('/one', 'backSonar'), 'range', '--frame', 'SonarBack_frame')
        pubs.wait([topic_of('/one', 'backSonar')])
        r = sensor_test(master, tmp_path / 'out', '--topics',
                        write_topics(tmp_path / 't.dat', '/one', names), '--sensors', ','.join(names),
                        '--mode', 'sequential', '--duration', '2', '--wait', '1', '--no-report')
    assert 'nothing is published' not in r.stdout, r
    assert r.sensors['backSonar']['verdict'] == 'PASS', r
    assert r.sensors['frontSonar']['reasons'][0].startswith(
        'no publisher on /one/frontSonar (is the driver running'), r
