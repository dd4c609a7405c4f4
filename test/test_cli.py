"""sensorTest as a user runs it: a real roscore, real rospy publishers (core_publisher.py), the
`sensorTest` script as a subprocess; verdicts, reasons, exit codes and the three output files.

Most tests share one master and one set of good publishers (module scope); every sensorTest
run writes into its own output folder. Timing assertions are deliberately loose: the machine
is shared with other test runs.
"""
import os
import signal
import time

import pytest
import rosgraph

from rosmaster import Master
from sensor_test_runs import (
    DAT,
    Publishers,
    Running,
    assert_outputs_complete,
    child_pids,
    sensor_test,
    topic_of,
    write_topics,
)

TEXT = 'This is the CSSR4Africa speaker test.'
DURATION = 3        # seconds each sensor listens, in most runs

# what the robot would publish: kind, extra publisher arguments (rates and frames the shipped
# robot expectations ask for)
GOOD = {
    'backSonar': ('range', ['--frame', 'SonarBack_frame']),
    'frontSonar': ('range', ['--frame', 'SonarFront_frame']),
    'laser': ('laser', []),
    'jointState': ('joints', ['--rate', '50']),
    'odometry': ('odometry', []),
    'imu': ('imu', []),
}


# ------------------------------------------------------------------ helpers


# ------------------------------------------------------------------ shared master and good publishers

@pytest.fixture(scope='module')
def good(module_master, tmp_path_factory):
    """Good publishers for every core sensor plus a /speech listener, under /good."""
    tmp = tmp_path_factory.mktemp('good')
    pubs = Publishers(module_master, tmp)
    prefix = '/good'
    for name, (kind, extra) in GOOD.items():
        pubs.start(name, topic_of(prefix, name), kind, *extra)
    pubs.start('speech', topic_of(prefix, 'speech'), 'listener')
    pubs.wait([topic_of(prefix, n) for n in GOOD], [topic_of(prefix, 'speech')])
    pubs.prefix = prefix
    pubs.topics = write_topics(tmp / 'topics.dat', prefix, list(GOOD) + ['speech'])
    yield pubs
    pubs.stop()


# ------------------------------------------------------------------ all good

def test_all_good_sensors_pass(module_master, good, tmp_path):
    names = list(GOOD) + ['speech']
    heard_before = good.log('speech').count('heard: ' + TEXT)
    r = sensor_test(module_master, tmp_path, '--topics', good.topics, '--sensors', ','.join(names),
                    '--mode', 'parallel', '--duration', str(DURATION), '--wait', '2')
    assert r.rc == 0, r
    assert {n: s['verdict'] for n, s in r.sensors.items()} == {n: 'PASS' for n in names}, r
    assert_outputs_complete(r, names)
    for name in GOOD:
        s = r.sensors[name]
        assert s['messages'] >= 5 and s['rate_hz'] > 0 and s['topic'] == topic_of(good.prefix, name)
    assert r.json['summary'] == {'PASS': len(names), 'FAIL': 0, 'SKIPPED': 0, 'INTERRUPTED': 0}
    # the spec's fields of the first message in each block
    sonar = r.block('BACK SONAR')
    assert '[MESSAGES] Printing back sonar data received.' in sonar
    for field in ('Frame id: SonarBack_frame', 'Field of view: ', 'Minimum range value: 0.25',
                  'Maximum range value: 2.55', 'Range value: '):
        assert field in sonar
    assert 'Range data size: 61' in r.block('LASER')
    assert 'Joint: HeadYaw: Position' in r.block('JOINT STATE')
    assert 'Child frame id: base_link' in r.block('ODOMETRY')
    assert 'Linear acceleration: (0, 0, 9.81)' in r.block('IMU')
    assert r.block('SPEECH').endswith('[RESULT] PASS')
    # speech: delivered to the listener, which printed it
    deadline = time.time() + 10
    while good.log('speech').count('heard: ' + TEXT) <= heard_before and time.time() < deadline:
        time.sleep(0.2)
    assert good.log('speech').count('heard: ' + TEXT) == heard_before + 1
    assert any('core_publisher' in n for n in r.sensors['speech']['values']['subscribers'])


# ------------------------------------------------------------------ every fault, named

# fault id -> (batch, sensor, kind, publisher args, words expected in the reasons)
FAULTS = {
    'sonar_nan': ('A', 'backSonar', 'range', ['--fault', 'nan', '--frame', 'SonarBack_frame'], 'range is NaN'),
    'sonar_out_of_range': ('A', 'frontSonar', 'range', ['--fault', 'out_of_range', '--frame', 'SonarFront_frame'],
                           "range outside the sensor's physical limits [0, 5] m"),
    # 40 ranges under angles for 61: inconsistent in itself (another layout alone is a warning)
    'laser_wrong_ranges': ('A', 'laser', 'laser', ['--fault', 'wrong_ranges'],
                           'number of ranges does not match the angles'),
    'joints_missing': ('A', 'jointState', 'joints', ['--fault', 'missing_joint', '--rate', '50'],
                       'expected joints missing: HeadYaw'),
    'odometry_quaternion': ('A', 'odometry', 'odometry', ['--fault', 'broken_quaternion'],
                            'orientation is not a unit quaternion (norm 2)'),
    'imu_zero_stamp': ('A', 'imu', 'imu', ['--fault', 'zero_stamp'], 'with a zero header stamp'),
    'sonar_bad_limits': ('B', 'backSonar', 'range', ['--fault', 'bad_limits', '--frame', 'SonarBack_frame'],
                         'min_range 3 is not below max_range 1'),
    'sonar_frame': ('B', 'frontSonar', 'range', ['--fault', 'frame'],
                    'frame_id is "wrong_frame", expected "SonarFront_frame"'),
    'laser_nan': ('B', 'laser', 'laser', ['--fault', 'nan'], 'scan without a single valid return'),
    'joints_duplicate': ('B', 'jointState', 'joints', ['--fault', 'dup_joint', '--rate', '50'],
                         'duplicate joint names HeadYaw'),
    'odometry_old_stamp': ('B', 'odometry', 'odometry', ['--fault', 'old_stamp'],
                           'clock offset: header stamps are a constant 30.0 s behind'),
    'imu_quaternion': ('B', 'imu', 'imu', ['--fault', 'broken_quaternion'],
                       'orientation is not a unit quaternion (norm 0.5)'),
    'joints_short_velocity': ('C', 'jointState', 'joints', ['--fault', 'short_velocity', '--rate', '50'],
                              'velocity has 19 values for 20 joints'),
    'imu_nan': ('C', 'imu', 'imu', ['--fault', 'nan'], 'angular velocity or linear acceleration holds NaN'),
    'laser_frame': ('C', 'laser', 'laser', ['--fault', 'frame'], 'frame_id is "wrong_frame", expected '
                                                                 '"base_footprint"'),
    'odometry_zero_stamp': ('C', 'odometry', 'odometry', ['--fault', 'zero_stamp'], 'with a zero header stamp'),
}
_batches = {}


def run_batch(master, tmp_path_factory, batch):
    """All faults of a batch in one parallel run (one sensor each); cached for the module."""
    if batch not in _batches:
        tmp = tmp_path_factory.mktemp('faults' + batch)
        prefix = '/fault' + batch
        cases = {fid: c for fid, c in FAULTS.items() if c[0] == batch}
        names = [c[1] for c in cases.values()]
        with Publishers(master, tmp) as pubs:
            for _, sensor, kind, args, _ in cases.values():
                pubs.start(sensor, topic_of(prefix, sensor), kind, *args)
            pubs.wait([topic_of(prefix, n) for n in names])
            _batches[batch] = sensor_test(master, tmp / 'out', '--topics', write_topics(tmp / 't.dat', prefix, names),
                                          '--sensors', ','.join(names), '--mode', 'parallel',
                                          '--duration', str(DURATION), '--wait', '2')
    return _batches[batch]


@pytest.mark.parametrize('fault', sorted(FAULTS))
def test_each_fault_fails_with_its_reason(module_master, tmp_path_factory, fault):
    batch, sensor, _, _, words = FAULTS[fault]
    r = run_batch(module_master, tmp_path_factory, batch)
    assert r.rc == 1, r
    s = r.sensors[sensor]
    assert s['verdict'] == 'FAIL' and s['messages'] > 0, s['reasons']
    assert any(words in reason for reason in s['reasons']), s['reasons']
    title = s['title']
    result_line = [ln for ln in r.block(title).splitlines() if ln.startswith('[RESULT] ')][0]
    assert result_line.startswith('[RESULT] FAIL: ') and words in result_line
    case = [c for c in r.junit.findall('testcase') if c.get('name') == sensor][0]
    assert words in case.find('failure').get('message')
    assert_outputs_complete(r, [c[1] for c in FAULTS.values() if c[0] == batch])


# ------------------------------------------------------------------ causes outside the messages

def test_no_publisher_wrong_type_dying_publisher_and_no_listener(module_master, tmp_path):
    """Each is a FAIL with its cause, and the run goes on with the next sensor (sequential)."""
    prefix = '/causes'
    names = ['backSonar', 'laser', 'frontSonar', 'odometry', 'speech']
    with Publishers(module_master, tmp_path) as pubs:
        pubs.start('backSonar', topic_of(prefix, 'backSonar'), 'string')             # wrong type
        pubs.start('laser', topic_of(prefix, 'laser'), 'laser')                       # will die
        pubs.start('odometry', topic_of(prefix, 'odometry'), 'odometry')              # good
        pubs.wait([topic_of(prefix, n) for n in ('backSonar', 'laser', 'odometry')])
        run = Running(['--topics', write_topics(tmp_path / 't.dat', prefix, names),
                       '--sensors', ','.join(names), '--mode', 'sequential',
                       '--duration', '3', '--wait', '2', '--output-dir', str(tmp_path / 'out')],
                      module_master.env(), tmp_path / 'out')
        run.wait_for('start  laser')
        time.sleep(1.0)    # 1 s into the laser's window
        pubs.procs['laser'].kill()          # the laser driver crashes 1 s into its window
        r = run.finish()
    assert r.rc == 1, r
    s = r.sensors
    assert [n for n in s] == names                 # every sensor ran, in this order
    assert s['backSonar']['verdict'] == 'FAIL'
    assert ('topic %s carries std_msgs/String, expected sensor_msgs/Range'
            % topic_of(prefix, 'backSonar')) in s['backSonar']['reasons']
    assert s['laser']['verdict'] == 'FAIL' and s['laser']['messages'] >= 3
    stopped = [x for x in s['laser']['reasons'] if x.startswith('messages stopped')]
    assert stopped and 'publisher left at' in stopped[0], s['laser']['reasons']
    assert s['frontSonar']['verdict'] == 'FAIL' and s['frontSonar']['messages'] == 0
    assert s['frontSonar']['reasons'][0].startswith('no publisher on %s' % topic_of(prefix, 'frontSonar'))
    assert s['odometry']['verdict'] == 'PASS', s['odometry']['reasons']
    assert s['speech']['verdict'] == 'FAIL'
    assert s['speech']['reasons'] == ['no subscriber on %s after 3.0 s: is naoqi_driver running?'
                                      % topic_of(prefix, 'speech')]
    assert_outputs_complete(r, names)
    for i in range(1, len(names)):                 # one after another
        assert s[names[i]]['started_at'] >= s[names[i - 1]]['ended_at'] - 0.01


# ------------------------------------------------------------------ modes, order, timing

def test_sequential_and_parallel_order_and_timing(module_master, good, tmp_path):
    names = ['odometry', 'backSonar', 'laser']            # not the input file's order
    out = tmp_path / 'out'
    common = ['--topics', good.topics, '--sensors', ','.join(names), '--duration', '2', '--wait', '2']
    seq = sensor_test(module_master, out, '--mode', 'sequential', *common)
    par = sensor_test(module_master, out, '--mode', 'parallel', *common)
    assert (seq.rc, par.rc) == (0, 0), (seq, par)
    s = [seq.sensors[n] for n in names]
    p = [par.sensors[n] for n in names]
    assert list(seq.sensors) == names and list(par.sensors) == names
    assert seq.json['mode'] == 'sequential' and par.json['mode'] == 'parallel'
    # sequential: one window after the other, in the given order: about N windows
    for a, b in zip(s, s[1:]):
        assert b['started_at'] >= a['ended_at'] - 0.01
    assert s[-1]['ended_at'] >= 3 * 2.0 - 0.1
    # parallel: all windows at once (all open together at one moment, whenever the run got to
    # open them on a loaded machine): about one window in all, not three
    assert max(x['started_at'] for x in p) < min(x['ended_at'] for x in p)
    assert max(x['ended_at'] for x in p) - min(x['started_at'] for x in p) < 2 * 2.0
    assert all(x['window_s'] >= 1.9 for x in s + p)
    assert par.elapsed < seq.elapsed
    # terminal shows the starts in this order
    starts = [ln.split()[1] for ln in seq.stdout.splitlines() if ln.strip().startswith('start ')]
    assert starts == names
    # the output file is appended: both runs are in it
    assert par.dat.count('[TESTING] ############ SENSORS ############') == 2
    assert par.dat.count('[END TIME] ') == 2


def test_quick_ends_each_window_early(module_master, good, tmp_path):
    names = ['backSonar', 'laser', 'imu']
    r = sensor_test(module_master, tmp_path, '--topics', good.topics, '--sensors', ','.join(names),
                    '--mode', 'sequential', '--duration', '30', '--wait', '2', '--quick')
    assert r.rc == 0, r
    for n in names:
        s = r.sensors[n]
        assert s['verdict'] == 'PASS' and s['stopped_because'] == 'verdict settled (--quick)'
        assert s['window_s'] < 10 and s['messages'] >= 10
    assert r.elapsed < 60      # without --quick: at least 90 s


def test_simulator_platform_skips_what_it_lacks(module_master, good, tmp_path):
    # the simulator's own spellings (laserSensor, ...), the good publishers' topics
    topics = tmp_path / 'simulatorTopics.dat'
    topics.write_text('backSonar %s\nlaserSensor %s\njointState %s\nHead /head\n'
                      % (topic_of(good.prefix, 'backSonar'), topic_of(good.prefix, 'laser'),
                         topic_of(good.prefix, 'jointState')))
    names = ['backSonar', 'imu', 'microphone', 'stereoCamera', 'laser', 'speech',
             'realsenseRGBCamera', 'realsenseDepthCamera', 'jointState']
    lacking = {'imu', 'microphone', 'stereoCamera', 'speech', 'realsenseRGBCamera', 'realsenseDepthCamera'}
    r = sensor_test(module_master, tmp_path / 'out', '--platform', 'simulator', '--topics', str(topics),
                    '--sensors', ','.join(names), '--mode', 'parallel', '--duration', '2', '--wait', '2')
    assert r.rc == 0, r
    assert r.json['platform'] == 'simulator'
    assert_outputs_complete(r, names)
    for n in names:
        s = r.sensors[n]
        if n in lacking:
            assert s['verdict'] == 'SKIPPED' and s['reasons'] == ['not available in the simulator']
            assert s['messages'] == 0
            assert '[RESULT] SKIPPED: not available in the simulator' in r.block(s['title'])
        else:
            assert s['verdict'] == 'PASS', s['reasons']
    skipped = [c.get('name') for c in r.junit.findall('testcase') if c.find('skipped') is not None]
    assert set(skipped) == lacking
    assert r.junit.get('skipped') == str(len(lacking))


# ------------------------------------------------------------------ private ROS params

@pytest.fixture
def clean_params(module_master):
    """Private params (`_mode:=...` or rosparam) stay on the master after the node ends: remove
    them after the test, so that they cannot leak into the next runs on the shared master."""
    m = rosgraph.Master('/test_sensor_test_cli', master_uri=module_master.uri)
    yield m
    if m.hasParam('/sensorTest'):
        m.deleteParam('/sensorTest')


def test_private_params_override_the_configuration_file(module_master, good, tmp_path, clean_params):
    config = tmp_path / 'config.ini'
    config.write_text('platform robot\nmode sequential\n')
    out = tmp_path / 'out'
    names = ['backSonar', 'laser', 'odometry']
    r = Running(['--config', str(config), '_mode:=parallel', '_duration:=2', '_wait:=2',
                 '_sensors:=' + ','.join(names), '_topics:=' + good.topics, '_output_dir:=' + str(out)],
                module_master.env(), out).finish()
    assert r.rc == 0, r
    assert r.json['mode'] == 'parallel'
    assert list(r.sensors) == names
    # really in parallel: every window open at one moment
    assert max(s['started_at'] for s in r.sensors.values()) < min(s['ended_at'] for s in r.sensors.values())
    assert all(1.9 <= s['window_s'] < 4 for s in r.sensors.values())


def test_rosparam_on_the_master_is_used(module_master, good, tmp_path, clean_params):
    """Set with rosparam before the run; the --topics file alone (no camera topics) would not do
    for the input file's sensors: the ~sensors param must count before the files are judged."""
    config = tmp_path / 'config.ini'
    config.write_text('platform robot\nmode sequential\n')
    params = {'/sensorTest/mode': 'parallel', '/sensorTest/sensors': ['imu', 'laser'],
              '/sensorTest/duration': 2.0}
    for k, v in params.items():
        clean_params.setParam(k, v)
    r = sensor_test(module_master, tmp_path / 'out', '--config', str(config), '--topics', good.topics,
                    '--wait', '2')
    assert r.rc == 0, r
    assert r.json['mode'] == 'parallel' and list(r.sensors) == ['imu', 'laser']
    assert all(s['window_s'] < 4 for s in r.sensors.values())


def test_bad_private_param_cannot_start(module_master, tmp_path, clean_params):
    out = tmp_path / 'out'
    r = Running(['_mode:=diagonal', '--output-dir', str(out)], module_master.env(), out).finish(30)
    assert r.rc == 2, r
    assert 'mode "diagonal" is not valid' in r.stderr and 'sequential, parallel' in r.stderr
    assert not os.path.exists(os.path.join(str(out), DAT))


# ------------------------------------------------------------------ could not start: exit 2

def test_no_master_exits_2_within_5_seconds(tmp_path):
    env = Master().env()                 # a free port with no master on it
    out = tmp_path / 'out'
    run = Running(['--sensors', 'laser', '--output-dir', str(out)], env, out)
    r = run.finish(30)
    assert r.rc == 2, r
    assert 'no ROS master at %s' % env['ROS_MASTER_URI'] in r.stderr and 'roscore' in r.stderr
    assert r.elapsed < 9.0               # gives up after ~5 s (+ interpreter start on a busy machine)
    assert not os.path.exists(os.path.join(str(out), DAT))


def test_bad_config_without_master_reports_the_file(tmp_path):
    """The file's error, not "no ROS master", and at once: no params could change the files."""
    config = tmp_path / 'config.ini'
    config.write_text('platform robot\nmode diagonal\n')
    out = tmp_path / 'out'
    r = Running(['--config', str(config), '--output-dir', str(out)], Master().env(), out).finish(30)
    assert r.rc == 2, r
    assert '%s:2: mode "diagonal" is not valid' % config in r.stderr
    assert 'no ROS master' not in r.stderr
    assert r.elapsed < 9.0


def test_unwritable_output_dir_exits_2(module_master, tmp_path):
    blocker = tmp_path / 'a_file'
    blocker.write_text('not a folder')
    out = blocker / 'results'
    r = sensor_test(module_master, out, '--sensors', 'laser', '--duration', '2', timeout=30)
    assert r.rc == 2, r
    assert 'cannot write results to %s' % out in r.stderr and '--output-dir' in r.stderr
    assert 'listening' not in r.stdout         # found before listening began
    assert blocker.read_text() == 'not a folder'


@pytest.mark.parametrize('case', ['config', 'input', 'topics', 'duration', 'sensors'])
def test_bad_files_and_values_exit_2_with_the_place(module_master, tmp_path, case):
    config = tmp_path / 'config.ini'
    config.write_text('platform robot\nmode sequential\n')
    inp = tmp_path / 'input.ini'
    inp.write_text('laser true\nbackSonar true\n')
    topics = tmp_path / 'topics.dat'
    topics.write_text('Laser /l\nBackSonar /b\n')
    args = ['--config', str(config), '--input', str(inp), '--topics', str(topics)]
    if case == 'config':
        config.write_text('platform robot\n# comment\nmode diagonal\n')
        expect = ['%s:3: mode "diagonal" is not valid' % config, 'use one of: sequential, parallel']
    elif case == 'input':
        inp.write_text('laser true\nbackSonar yes\nsonarLeft true\n')
        expect = ['%s:3: unknown sensor "sonarLeft"' % inp, 'valid sensors: backSonar, frontSonar']
    elif case == 'topics':
        topics.write_text('Laser /l\n')
        expect = ['%s: no topic for sensor "backSonar"' % topics, 'add a line "backSonar /topic/name"']
    elif case == 'duration':
        args += ['--duration', 'ten']
        expect = ['--duration "ten" is not a positive number of seconds']
    else:
        args += ['--sensors', 'laser,periscope']
        expect = ['unknown sensor "periscope" in --sensors', 'valid sensors: ']
    r = sensor_test(module_master, tmp_path / 'out', *args, timeout=30)
    assert r.rc == 2, r
    for words in expect:
        assert words in r.stderr, r
    assert not os.path.exists(str(tmp_path / 'out' / DAT))


# ------------------------------------------------------------------ interrupted: exit 130

@pytest.mark.parametrize('sig', [signal.SIGINT, signal.SIGTERM], ids=['ctrl_c', 'sigterm'])
def test_interrupted_mid_run(module_master, good, tmp_path, sig):
    """Ctrl-C (SIGINT to the process, as a terminal sends it), or SIGTERM (kill, roslaunch)."""
    out = tmp_path / 'out'
    run = Running(['--topics', good.topics, '--sensors', 'backSonar,laser', '--mode', 'sequential',
                   '--duration', '30', '--wait', '2', '--output-dir', str(out)], module_master.env(), out)
    run.wait_for('start  backSonar')
    time.sleep(2.0)    # 2 s of listening before the signal
    sent = time.monotonic()
    run.proc.send_signal(sig)
    r = run.finish(30)
    stopped_after = time.monotonic() - sent
    assert r.rc == 130, r
    assert stopped_after < 3.0, 'took %.1f s to stop' % stopped_after
    last = r.dat.split('[TESTING] ############ SENSORS ############')[-1]
    why = 'interrupted by Ctrl-C' if sig == signal.SIGINT else 'terminated (SIGTERM)'
    assert '[INTERRUPTED] ' + why in last
    assert last.index('[INTERRUPTED]') < last.index('[END TIME] ')
    data = r.json
    assert data['interrupted'] is True and data['exit_code'] == 130
    sonar = r.sensors['backSonar']
    assert sonar['messages'] >= 5 and sonar['stopped_because'] == 'interrupted'     # what was measured
    assert r.sensors['laser']['reasons'] == ['not run: the run was interrupted before it started']
    assert_outputs_complete(r, ['backSonar', 'laser'])
    assert r.junit.find('properties/property[@name="interrupted"]').get('value') == 'true'


def test_master_killed_mid_run(master, tmp_path):
    """Own master: it is killed. sensorTest must end by itself with complete files, no hang."""
    prefix = '/lost'
    out = tmp_path / 'out'
    with Publishers(master, tmp_path) as pubs:
        pubs.start('backSonar', topic_of(prefix, 'backSonar'), 'range', '--frame', 'SonarBack_frame')
        pubs.wait([topic_of(prefix, 'backSonar')])
        run = Running(['--topics', write_topics(tmp_path / 't.dat', prefix, ['backSonar', 'laser']),
                       '--sensors', 'backSonar,laser', '--duration', '30', '--wait', '2',
                       '--output-dir', str(out)], master.env(), out)
        run.wait_for('start  backSonar')
        time.sleep(1.5)    # 1.5 s into the window
        doomed = child_pids(master.proc.pid)            # rosmaster and rosout
        assert doomed
        for pid in doomed:
            os.kill(pid, signal.SIGKILL)
        os.kill(master.proc.pid, signal.SIGKILL)        # and roscore itself
        killed = time.monotonic()
        r = run.finish(60)
        took = time.monotonic() - killed
        pubs.stop(signal.SIGKILL)       # their master is gone: nothing to unregister from
    assert r.rc == 130, r
    assert took < 15, 'took %.1f s to notice' % took
    data = r.json
    assert data['interrupted'] is True and 'master' in data['interrupt_reason']
    assert master.uri in data['interrupt_reason']
    assert r.sensors['backSonar']['messages'] >= 5
    last = r.dat.split('[TESTING] ############ SENSORS ############')[-1]
    assert '[INTERRUPTED] the ROS master at %s went away' % master.uri in last
    assert '[END TIME] ' in last
    assert_outputs_complete(r, ['backSonar', 'laser'])
