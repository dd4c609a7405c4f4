"""Unit: JUnit XML from hostile robot strings, and the atomic write of every results file."""
import os
import stat
import xml.etree.ElementTree as ET

import pytest

from pepper_interface_tests import results as R
from pepper_interface_tests.outputs import files
from pepper_interface_tests.outputs.atomicfile import write_atomic

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
