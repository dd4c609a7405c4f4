"""Unit: JUnit XML from hostile robot strings, and the atomic write of every results file."""
import io
import os
import re
import stat
import xml.etree.ElementTree as ET

import genpy
import pytest

from check_runs import R0, T0, N, close, judged, make_run
from fake_pepper import serialized, sonar
from pepper_interface_tests import results
from pepper_interface_tests import results as R
from pepper_interface_tests.outputs import files
from pepper_interface_tests.outputs.atomicfile import write_atomic
from pepper_interface_tests.outputs.terminal import Terminal
from pepper_interface_tests.results import FAIL, PASS, SKIPPED, RunResult, SensorResult

HOSTILE = 'a\x00b\x1b[31mred\x07 ]]> <script>alert(1)</script> & "q" \'s\' \ud800 \ufffe \x85 é 漢'


def run_with(reason, frame=HOSTILE, big=''):
    run = R.RunResult('robot', 'parallel', 1000.0, end=1012.5, source=HOSTILE)
    run.sensors = [
        R.SensorResult('imu', 'IMU', '/naoqi_driver/imu/base', 'sensor_msgs/Imu', R.FAIL,
                       reasons=[reason], warnings=['frame_id %s' % frame], window_s=5.0),
        R.SensorResult('laser', 'Laser', '/naoqi_driver/laser', 'sensor_msgs/LaserScan', R.PASS,
                       notes=[big], window_s=5.0),
        R.SensorResult('odometry', 'Odometry', '/naoqi_driver/odom', 'nav_msgs/Odometry',
                       R.INTERRUPTED, reasons=['interrupted after 1.0 s'], window_s=1.0),
        R.SensorResult('stereoCamera', 'Stereo', None, 'sensor_msgs/Image', R.SKIPPED,
                       reasons=['no stereo camera']),
    ]
    return run


def test_junit_parses_and_keeps_hostile_text():
    root = ET.fromstring(files.junit_text(run_with('bad ' + HOSTILE)).encode('utf-8'))
    assert root.tag == 'testsuite'
    assert (root.get('tests'), root.get('failures'), root.get('skipped')) == ('4', '1', '2')
    assert root.get('time') == '12.500'
    props = {p.get('name'): p.get('value') for p in root.iter('property')}
    assert '<script>alert(1)</script>' in props['source'] and '\\x1b[31mred' in props['source']
    cases = {c.get('name'): c for c in root.iter('testcase')}
    failure = cases['imu'].find('failure')
    msg = failure.get('message')
    # what XML cannot hold is written as an escape; everything else arrives as it was
    for kept in (']]>', '<script>alert(1)</script>', '& "q" \'s\'', 'é 漢', '\\x00', '\\x07',
                 '\\ud800', '\\ufffe', '\\x85'):
        assert kept in msg, (kept, msg)
    assert '\x1b' not in msg and '\x00' not in msg
    assert 'frame_id a\\x00b' in failure.text and 'topic: /naoqi_driver/imu/base' in failure.text
    assert cases['laser'].find('failure') is None and cases['laser'].find('system-out') is not None
    assert cases['odometry'].find('skipped').get('message') == 'interrupted after 1.0 s'
    assert 'topic: /naoqi_driver/odom' in cases['odometry'].find('system-out').text
    assert cases['stereoCamera'].find('skipped').get('message') == 'no stereo camera'
    assert cases['stereoCamera'].find('system-out') is None


def test_junit_200kb_string_parses_and_is_bounded():
    huge = ('<x>]]>&' * 30000)[:200000]
    text = files.junit_text(run_with(huge, big=huge))
    root = ET.fromstring(text.encode('utf-8'))
    msg = root.find('testcase/failure').get('message')
    assert msg.startswith('<x>]]>&<x>') and '(198000 more characters)' in msg
    assert len(text) < 20000       # FILE_LIMIT per robot string, not 200 kB each


def test_junit_file_written_whole(tmp_path):
    path = str(tmp_path / R.JUNIT_FILE)
    files.write_junit(run_with('x'), path)
    ET.parse(path)
    assert os.listdir(str(tmp_path)) == [R.JUNIT_FILE]


def test_atomic_write_replaces_with_umask_permissions(tmp_path):
    path = str(tmp_path / 'out.json')
    with open(path, 'w') as f:
        f.write('old')
    old = os.umask(0o027)
    try:
        write_atomic(path, 'new ünïcode \udcff\n')
    finally:
        os.umask(old)
    with open(path, 'rb') as f:
        assert f.read() == 'new ünïcode \\udcff\n'.encode()
    assert stat.S_IMODE(os.stat(path).st_mode) == 0o640
    assert os.listdir(str(tmp_path)) == ['out.json']


def test_atomic_write_error_names_the_file_and_leaves_nothing(tmp_path):
    folder = tmp_path / 'f'
    folder.mkdir()
    path = str(folder / 'out.xml')
    os.mkdir(path)
    with pytest.raises(OSError) as err:      # a directory where the file should go: rename fails
        write_atomic(path, 'text')
    assert err.value.filename == path
    assert os.listdir(str(folder)) == ['out.xml']      # only the directory; no temporary file left


def test_atomic_write_failing_midway_keeps_the_old_file(tmp_path):
    path = str(tmp_path / 'out.json')
    write_atomic(path, 'old')
    with pytest.raises(TypeError):          # the write itself fails (here: not text)
        write_atomic(path, b'new')
    with open(path) as f:
        assert f.read() == 'old'
    assert os.listdir(str(tmp_path)) == ['out.json']


def test_printable_shows_control_characters_and_keeps_the_rest():
    """results.printable, the one escaping rule of the terminal, the .dat, JUnit and the report."""
    assert R.printable('Sonar\x01\x1b[31mRED\x1b[0m\x07') == 'Sonar\\x01\\x1b[31mRED\\x1b[0m\\x07'
    assert R.printable('a\x7fb\x85c\u2028d\ud800e') == 'a\\x7fb\\x85c\\u2028d\\ud800e'
    assert R.printable('two\nlines\tand a tab') == 'two\\nlines\\tand a tab'
    assert R.printable('two\nlines', one_line=False) == 'two\nlines'
    assert R.printable('<script> & "é 漢"') == '<script> & "é 漢"'       # markup is the writers' job
    assert R.printable('x' * 30, limit=10) == 'x' * 10 + '... (20 more characters)'


def test_dat_block_holds_no_control_character_and_one_string_per_line():
    r = run_with('bad ' + HOSTILE + '\nsecond line').sensors[0]
    r.fields = [('Frame id', HOSTILE), ('Range', 'x' * 5000)]
    block = files.dat_block(r)
    lines = block.rstrip('\n').split('\n')
    assert not any(c in block for c in '\x00\x1b\x07\x85\ud800\ufffe')
    assert 'Frame id: a\\x00b\\x1b[31mred\\x07 ]]> <script>' in block
    assert lines[-1].startswith('[RESULT] FAIL: bad a\\x00b') and lines[-1].endswith('\\nsecond line')
    assert '(3000 more characters)' in block          # FILE_LIMIT per robot string


def sample_run(tmp_path):
    """A run with a real PASS (from a SensorRun), a FAIL with XML-hostile text and a SKIPPED."""
    ok = judged('backSonar', tmp_path, [sonar(i) for i in range(N)])
    bad = SensorResult(name='laser', title='LASER', topic='/naoqi_driver/laser',
                       msg_type='sensor_msgs/LaserScan', verdict=FAIL,
                       reasons=['range <min> & "max" wrong', 'rate 2.00 Hz outside the expected 4-16 Hz'],
                       warnings=['1 pause'], messages=6, rate_hz=2.0, window_s=3.0,
                       fields=[['Frame id', 'base_footprint']], stopped_because='window ended',
                       rate_series=[(0.5, 2.0)])
    skipped = SensorResult(name='imu', title='IMU', topic=None, msg_type='sensor_msgs/Imu',
                           verdict=SKIPPED, reasons=['not available in the simulator'])
    run = RunResult(platform='robot', mode='sequential', start=1700000000.0, end=1700000012.5,
                    output_dir=str(tmp_path), sensors=[ok, bad, skipped])
    return run


def test_output_file_blocks(tmp_path):
    run = sample_run(tmp_path)
    path = str(tmp_path / results.OUTPUT_FILE)
    for _ in range(2):                     # appended, never truncated
        f = files.OutputFile(path)
        f.begin(run)
        for s in run.sensors:
            f.sensor(s)
        f.end(run)
        f.close()
    text = open(path).read()
    assert text.count('[TESTING] ############ SENSORS ############') == 2
    assert text.count('[END TIME] %s' % results.timestamp(run.end)) == 2
    first = text.split('[TESTING] ############ SENSORS ############')[1]
    assert re.search(r'\[START TIME\] \d{4}-\d\d-\d\d\.\d\d:\d\d:\d\d\n', first)
    sonar_block = first.split('[TESTING] ---- BACK SONAR ----\n')[1].split('\n\n')[0].splitlines()
    assert sonar_block[0] == '[TOPIC] /t (sensor_msgs/Range)'
    assert sonar_block[1] == '[MESSAGES] Printing back sonar data received.'
    assert [ln.split(':')[0] for ln in sonar_block[2:7]] == ['Frame id', 'Field of view', 'Minimum range value',
                                                         'Maximum range value', 'Range value']
    assert sonar_block[7] == '[END MESSAGES] Finished printing.'
    assert sonar_block[8].startswith('[SUMMARY] 25 messages in 3.0 s, rate 10.00 Hz')
    assert sonar_block[-1] == '[RESULT] PASS'
    assert '[RESULT] FAIL: range <min> & "max" wrong; rate 2.00 Hz outside the expected 4-16 Hz' in first
    assert '[WARNING] 1 pause' in first
    assert '[TESTING] ---- IMU ----\n[RESULT] SKIPPED: not available in the simulator\n' in first
    assert '[SUMMARY] 1 passed, 1 failed, 1 skipped\n[END TIME]' in first
    assert '[INTERRUPTED]' not in text


def test_output_file_interrupted(tmp_path):
    run = sample_run(tmp_path)
    run.interrupted, run.interrupt_reason = True, 'the ROS master at http://x:1 went away'
    f = files.OutputFile(str(tmp_path / 'o.dat'))
    f.begin(run)
    f.end(run)
    f.close()
    text = open(str(tmp_path / 'o.dat')).read()
    assert '[INTERRUPTED] the ROS master at http://x:1 went away\n' in text
    assert text.index('[INTERRUPTED]') < text.index('[END TIME]')


def test_json_fields(tmp_path):
    run = sample_run(tmp_path)
    path = str(tmp_path / results.JSON_FILE)
    files.write_json(run, path)
    data = files.load_json(path)
    assert data['schema_version'] == results.SCHEMA_VERSION
    assert (data['platform'], data['mode'], data['exit_code']) == ('robot', 'sequential', 1)
    assert data['summary'] == {PASS: 1, FAIL: 1, SKIPPED: 1, 'INTERRUPTED': 0}
    assert data['start'] == results.timestamp(run.start) and data['end_unix'] == 1700000012.5
    by = {s['name']: s for s in data['sensors']}
    assert by['laser']['reasons'][0] == 'range <min> & "max" wrong'
    assert by['backSonar']['messages'] == N and by['backSonar']['expected_rate_hz'] == [4.0, 16.0]
    assert by['backSonar']['fields'][0] == ['Frame id', 'SonarBack_frame']
    assert by['imu']['verdict'] == SKIPPED
    for s in data['sensors']:
        for key in ('verdict', 'reasons', 'warnings', 'messages', 'rate_hz', 'topic', 'stats',
                    'window_s', 'stopped_because', 'started_at', 'ended_at'):
            assert key in s
        assert 'series' not in s            # plots only on request
    assert 'series' in run.to_dict(with_series=True)['sensors'][0]
    assert not [f for f in os.listdir(str(tmp_path)) if f.startswith('.tmp-')]


def test_junit_xml(tmp_path):
    run = sample_run(tmp_path)
    path = str(tmp_path / results.JUNIT_FILE)
    files.write_junit(run, path)
    root = ET.parse(path).getroot()
    assert root.tag == 'testsuite'
    assert (root.get('tests'), root.get('failures'), root.get('skipped')) == ('3', '1', '1')
    assert float(root.get('time')) == pytest.approx(12.5)
    cases = root.findall('testcase')
    assert [c.get('name') for c in cases] == ['backSonar', 'laser', 'imu']
    passed, failed, skipped = cases
    assert passed.find('failure') is None and passed.find('skipped') is None
    assert 'topic: /t' in passed.find('system-out').text
    failure = failed.find('failure')
    assert failure.get('message') == ('range <min> & "max" wrong; '
                                      'rate 2.00 Hz outside the expected 4-16 Hz')
    assert 'topic: /naoqi_driver/laser' in failure.text
    assert skipped.find('skipped').get('message') == 'not available in the simulator'
    props = {p.get('name'): p.get('value') for p in root.find('properties')}
    assert props == {'platform': 'robot', 'mode': 'sequential', 'source': 'live', 'interrupted': 'false'}


def test_a_pass_with_warnings_shows_in_every_output(tmp_path, monkeypatch):
    """Issue 10, item 4: a suspicious but possible condition (here a pause in the stream) keeps
    the PASS, and every output says which PASS carries it: terminal PASS* with a legend, the
    .dat's [WARNING], the JSON's warnings, JUnit system-out, /diagnostics WARN."""
    from diagnostic_msgs.msg import DiagnosticStatus

    from pepper_interface_tests.outputs.diagnostics import result_status
    run = make_run('backSonar', tmp_path)
    msgs = [sonar(i) for i in range(N)]
    t = T0
    for i, m in enumerate(msgs):
        t = T0 + 0.05 + i / 10.0 + (1.5 if i >= 12 else 0.0)      # one 1.6 s pause
        m.header.stamp = genpy.Time.from_sec(R0 + (t - T0) - 0.01)
        run.feed_raw(run.sensor.msg_type, serialized(m), t, R0 + (t - T0))
    warned = close(run, at=4.5)
    assert warned.verdict == PASS and warned.warnings, (warned.reasons, warned.warnings)
    clean = judged('frontSonar', tmp_path, [sonar(i, frame_id='SonarFront_frame') for i in range(N)])
    assert clean.verdict == PASS and not clean.warnings, clean.warnings
    rr = RunResult(platform='robot', mode='parallel', start=1700000000.0, end=1700000005.0,
                   output_dir=str(tmp_path), sensors=[warned, clean])
    term = io.StringIO()
    monkeypatch.setenv('COLUMNS', '130')      # the summary as a table (narrower: one block per sensor)
    Terminal(stream=term).run_ended(rr)
    rows = {line.split()[0]: line for line in term.getvalue().splitlines() if line[:1].isalpha()}
    assert rows['backSonar'].split()[1] == 'PASS*' and 'warning: ' in rows['backSonar']
    assert rows['frontSonar'].split()[1] == 'PASS'
    assert 'PASS* = passed with 1 warning to read (not a failure)' in term.getvalue()
    f = files.OutputFile(str(tmp_path / results.OUTPUT_FILE))
    f.begin(rr)
    for s in rr.sensors:
        f.sensor(s)
    f.end(rr)
    f.close()
    files.write_json(rr, str(tmp_path / results.JSON_FILE))
    files.write_junit(rr, str(tmp_path / results.JUNIT_FILE))
    assert '[WARNING] ' + warned.warnings[0] in open(str(tmp_path / results.OUTPUT_FILE)).read()
    data = files.load_json(str(tmp_path / results.JSON_FILE))
    assert data['sensors'][0]['verdict'] == 'PASS' and data['sensors'][0]['warnings'] == warned.warnings
    case = ET.parse(str(tmp_path / results.JUNIT_FILE)).getroot().findall('testcase')[0]
    assert case.find('failure') is None and 'WARNING: ' + warned.warnings[0] in case.find('system-out').text
    status = result_status(warned)
    assert status.level == DiagnosticStatus.WARN and status.message.startswith('PASS with warnings: ')
    assert result_status(clean).level == DiagnosticStatus.OK


def test_the_robots_identity_in_the_dat_junit_json_and_report_header(tmp_path):
    from pepper_interface_tests.outputs.report.page import header
    run = RunResult(platform='robot', mode='parallel', start=T0, end=T0 + 3, robot='AP990370B0000001',
                    robot_info={'body_id': 'AP990370B0000001', 'topic': '/naoqi_driver/info',
                                'body_type': 'juliette', 'base_version': '1.8a'})
    assert '[RUN] robot AP990370B0000001 (juliette, base 1.8a)\n' in files.dat_begin(run)
    props = {p.get('name'): p.get('value') for p in ET.fromstring(files.junit_text(run)).iter('property')}
    assert props['robot'] == 'AP990370B0000001'
    data = run.to_dict()
    assert data['robot'] == 'AP990370B0000001' and data['robot_info']['body_type'] == 'juliette'
    again = R.read_run(data)
    assert again.robot == 'AP990370B0000001' and R.robot_line(again) == R.robot_line(run)
    assert header(run)['robot'] == 'robot AP990370B0000001 (juliette, base 1.8a)'
    # unknown: said once, with the reason; the JUnit file has no robot property; the simulator says nothing
    bag = RunResult(platform='robot', mode='parallel', start=T0,
                    robot_info={'unknown': 'a recording does not name its robot'})
    assert files.dat_begin(bag).count('[RUN] robot identity unknown: a recording does not name its robot') == 1
    assert 'robot' not in {p.get('name') for p in ET.fromstring(files.junit_text(bag)).iter('property')}
    assert bag.to_dict()['robot'] is None
    assert R.robot_line(RunResult(platform='simulator', mode='parallel', start=T0)) == ''
