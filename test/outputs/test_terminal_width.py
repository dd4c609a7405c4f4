"""What a real sensorTest run prints at 80 columns: every line fits, or is one word that cannot
be broken (a long path stands alone on its own line, never cut), and a reason every sensor
shares (no publisher at all) is said once, at the start, with its likely causes.

A real roscore with nothing published, the real sensorTest program (report and history on),
an output folder whose path is longer than the terminal is wide.
"""
import json
import os
import subprocess

import pytest

from rosmaster import script

PKG = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
# the reason each sensor keeps in the results files (observer.SHARED)
SHARED = 'no sensor topic of this run has a publisher on the ROS master'


def too_wide(text, width=80):
    return [line for line in text.splitlines() if len(line) > width and len(line.split()) > 1]


@pytest.fixture(scope='module')
def run80(module_master, tmp_path_factory):
    """sensorTest at 80 columns with nothing published: (its stdout, its output folder)."""
    base = tmp_path_factory.mktemp('w80')
    out = base / ('an-output-folder-with-a-name-long-enough-to-need-its-own-line' * 2)
    env = dict(module_master.env(), COLUMNS='80')
    cmd = script('sensorTest') + [
        '--topics', os.path.join(PKG, 'data', 'pepperTopics.dat'), '--sensors', 'laser,odometry',
        '--platform', 'robot', '--duration', '1', '--wait', '1', '--output-dir', str(out),
        '--no-show', '--no-diagnostics', '--no-record']
    done = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=120)
    assert done.returncode == 1, done.stdout + done.stderr
    return done.stdout, out


def test_every_line_fits_80_columns_or_is_one_word(run80):
    text, _ = run80
    assert not too_wide(text), too_wide(text)
    # the report, history and results lines are there, each path on a line of its own
    lines = [line.strip() for line in text.splitlines()]
    for start in ('report:', 'run ', 'results in'):
        assert any(line.startswith(start) for line in lines), (start, text)
    assert any(line.endswith('sensorTestReport.html') and len(line.split()) == 1 for line in lines), text


def test_no_publisher_is_said_once_with_its_causes(run80):
    text, out = run80
    # said once: the header with the likely causes; each sensor then names only its topic
    assert text.count('nothing is published') == 1 and 'Likely causes' in ' '.join(text.split()), text
    assert SHARED not in text, text
    assert 'no publisher on /naoqi_driver/laser' in text
    # the results files keep the whole reason
    data = json.loads((out / 'sensorTestResults.json').read_text())
    assert all(SHARED in s['reasons'][0] for s in data['sensors']), data['sensors']


def test_fill_never_cuts_a_path():
    from pepper_interface_tests.outputs.terminal import fill
    path = '/a/' + 'b' * 90 + '/sensorTestReport.html'
    text = fill('report: %s (2.2 MB, 1.9 s)' % path, 79)
    assert text.splitlines() == ['report:', '  ' + path, '  (2.2 MB, 1.9 s)']
    assert fill('report: /tmp/x.html (7 kB, 0.2 s)', 79) == 'report: /tmp/x.html (7 kB, 0.2 s)'
    # the figures stay together: not "(2.2 MB," at the end of one line and "1.9 s)" below
    assert fill('report: %s (2.2 MB, 1.9 s)' % ('/p' * 30), 79, keep=['(2.2 MB, 1.9 s)']) == \
        'report: %s\n  (2.2 MB, 1.9 s)' % ('/p' * 30)


@pytest.mark.integration     # a Python process of its own, its stdout a pipe
@pytest.mark.parametrize('stderr_tty', [True, False])
def test_through_a_pipe_the_lines_fit_the_terminal_on_stderr(stderr_tty):
    """`sensorTest | tee run.log` in a 70-column terminal: stdout is a pipe, stderr the terminal;
    the lines fit its 70 columns. With no terminal at all (CI, a file) they are 120 wide."""
    import fcntl
    import struct
    import sys
    import termios
    master_fd, slave_fd = os.openpty()
    fcntl.ioctl(slave_fd, termios.TIOCSWINSZ, struct.pack('HHHH', 24, 70, 0, 0))
    env = {k: v for k, v in os.environ.items() if k not in ('COLUMNS', 'LINES')}
    try:
        done = subprocess.run(
            [sys.executable, '-c', 'from pepper_interface_tests.outputs.terminal import columns; '
                                   'print(columns())'],
            env=env, stdout=subprocess.PIPE, stderr=slave_fd if stderr_tty else subprocess.DEVNULL,
            text=True, timeout=60)
    finally:
        os.close(slave_fd)
        os.close(master_fd)
    assert int(done.stdout) == (69 if stderr_tty else 119), done.stdout
