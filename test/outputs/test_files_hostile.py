"""Results files under hostile conditions: a full disk (a real, small tmpfs filled during the
run), two runs sharing one output folder, and robot strings full of control characters or
200 kB long. Real roscore, real rospy publishers, the real sensorTest script."""
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

import pytest

from rosmaster import NODES, kill_group, spawn
from sensor_test_runs import (
    DAT,
    JSON_FILE,
    XML_FILE,
    Publishers,
    Running,
    assert_outputs_complete,
    sonar_and_laser_fixture,
    write_topics,
)

HERE = NODES   # the node scripts' folder (test/nodes/)
PREFIX = '/disk'
NAMES = ['backSonar', 'laser']


pubs = sonar_and_laser_fixture(PREFIX)


@pytest.fixture
def small_disk(tmp_path):
    """A real 2 MB tmpfs (needs root), unmounted afterwards."""
    path = tmp_path / 'disk'
    path.mkdir()
    done = subprocess.run(['mount', '-t', 'tmpfs', '-o', 'size=2m', 'tmpfs', str(path)],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if done.returncode != 0:
        pytest.skip('cannot mount a tmpfs (needs root): %s' % done.stdout.strip())
    yield path
    subprocess.run(['umount', '-l', str(path)])


def fill(folder):
    """Write zeros into folder/filler until the file system is full."""
    with open(os.path.join(str(folder), 'filler'), 'wb', buffering=0) as f:
        block = b'\0' * 65536
        try:
            while True:
                f.write(block)
        except OSError:
            pass
        try:
            while True:
                f.write(b'\0')
        except OSError:
            pass


@pytest.mark.parametrize('history', [True, False], ids=['run_folder', 'no_history'])
def test_a_full_disk_exits_non_zero_naming_the_file(module_master, pubs, small_disk, history):
    out = small_disk / 'out'
    run = Running(['--topics', pubs.topics, '--sensors', ','.join(NAMES), '--mode', 'sequential',
                   '--duration', '2', '--wait', '3', '--no-report', '--output-dir', str(out)]
                  + ([] if history else ['--no-history']), module_master.env(), out)
    run.wait_for('start  backSonar')
    fill(small_disk)
    r = run.finish(60)
    assert r.rc == 3, r
    folder = out if not history else out / 'runs' / os.listdir(str(out / 'runs'))[0]
    assert 'cannot write %s' % (folder / XML_FILE) in r.stderr, r
    assert 'cannot write %s' % (folder / JSON_FILE) in r.stderr, r
    assert 'No space left on device' in r.stderr
    assert 'results files not written (exit 3)' in r.stderr
    left = [os.path.join(d, n) for d, _, names in os.walk(str(out)) for n in names if n.startswith('.tmp-')
            or '.latest-' in n]
    assert left == []
    assert '3 passed' not in r.stdout


def test_two_runs_in_one_output_folder_do_not_interleave_the_dat(module_master, pubs, tmp_path):
    out = tmp_path / 'shared'
    args = ['--topics', pubs.topics, '--sensors', ','.join(NAMES), '--mode', 'sequential',
            '--duration', '2', '--wait', '3', '--no-report', '--output-dir', str(out)]
    a = Running(args, module_master.env(), out)
    b = Running(args, module_master.env(), out)
    ra, rb = a.finish(60), b.finish(60)
    assert ra.rc == 0 and rb.rc == 0, (ra, rb)
    with open(str(out / DAT)) as f:
        sections = f.read().split('[TESTING] ############ SENSORS ############')[1:]
    assert len(sections) == 2
    for s in sections:
        assert s.count('[START TIME]') == 1 and s.count('[END TIME]') == 1
        assert s.count('[RESULT] PASS') == 2 and s.count('[TESTING] ---- ') == 2, s
        assert s.index('[START TIME]') < s.index('BACK SONAR') < s.index('LASER') < s.index('[END TIME]')
    ids = sorted(s.split(', run id ')[1].split('\n')[0] for s in sections)
    assert ids == sorted(os.listdir(str(out / 'runs')))


def test_robot_strings_are_escaped_for_every_output(module_master, tmp_path):
    env = module_master.env()
    procs = [spawn([sys.executable, os.path.join(HERE, 'odd_frame_publisher.py'), '/odd/' + name, kind],
                   env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
             for name, kind in (('backSonar', 'control'), ('frontSonar', 'huge'))]
    try:
        Publishers(module_master, tmp_path).wait(['/odd/backSonar', '/odd/frontSonar'])
        topics = write_topics(tmp_path / 't.dat', '/odd', ['backSonar', 'frontSonar'])
        r = Running(['--topics', topics, '--sensors', 'backSonar,frontSonar', '--mode', 'parallel',
                     '--duration', '2', '--wait', '5', '--no-report', '--output-dir', str(tmp_path / 'out')],
                    env, tmp_path / 'out').finish(90)
    finally:
        for p in procs:
            kill_group(p)
    assert r.rc == 1, r                      # wrong frame ids fail, by name
    assert_outputs_complete(r, ['backSonar', 'frontSonar'])   # the JUnit XML parses
    suite = ET.fromstring(open(str(tmp_path / 'out' / XML_FILE), encoding='utf-8').read())
    message = suite.find('testcase[@name="backSonar"]/failure').get('message')
    assert '\\x01\\x1b[31mRED' in message and '\x1b' not in message
    # the terminal: nothing raw, nothing huge
    for text in (r.stdout, r.stderr):
        assert '\x1b' not in text and '\x01' not in text and '\x07' not in text
        assert max([len(line) for line in text.splitlines()] or [0]) < 2000
    assert 'frame_id is "Sonar\\x01\\x1b[31mRED\\x1b[0m\\x07"' in r.stdout
    # the .dat: escaped, bounded
    dat = r.dat
    assert '\x1b' not in dat and '\x01' not in dat
    assert max(len(line) for line in dat.splitlines()) < 2200
    # the JSON keeps the exact value (JSON escapes it itself)
    fields = dict(map(tuple, r.sensors['backSonar']['fields']))
    assert fields['Frame id'] == 'Sonar\x01\x1b[31mRED\x1b[0m\x07'
