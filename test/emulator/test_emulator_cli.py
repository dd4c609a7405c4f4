"""pepperEmulator's command line as a user meets it: --help explains every option, and
--list-faults prints a table of every fault of faults.py that fits 80 columns (no master needed;
the real script as a subprocess)."""
import os
import subprocess

from pepper_interface_tests.emulator import faults
from rosmaster import script

ENV = dict(os.environ, COLUMNS='80', ROS_MASTER_URI='http://127.0.0.1:1')   # no master


def run(*args):
    return subprocess.run(script('pepperEmulator') + list(args), env=ENV, capture_output=True,
                          text=True, timeout=60)


def test_help_describes_every_option():
    p = run('--help')
    assert p.returncode == 0, p.stderr
    options = [line.split()[0] for line in p.stdout.splitlines()
               if line.startswith('  --') and line.split()[0] != '--help']
    assert len(options) >= 15, p.stdout
    for option in options:     # every option has a help text: the line after it, or on its line
        block = p.stdout.split('\n  ' + option, 1)[1].split('\n  --', 1)[0]
        words = ' '.join(block.split()).split(' ', 1)
        assert len(words) == 2 and len(words[1]) > 15, (option, block)
    assert 'exit codes:' in p.stdout and 'examples:' in p.stdout
    assert max(len(line) for line in p.stdout.splitlines()) <= 80, 'wider than the terminal (COLUMNS=80)'


def test_list_faults_is_a_table_of_every_fault():
    p = run('--list-faults')
    assert p.returncode == 0 and not p.stderr, p.stderr
    lines = p.stdout.splitlines()
    assert max(len(line) for line in lines) <= 79, p.stdout
    header = next(i for i, line in enumerate(lines) if line.startswith('fault '))
    assert lines[header].split() == ['fault', 'applies', 'to', 'effect']
    rows = [line.split()[0] for line in lines[header + 2:] if line and not line.startswith(' ')
            and not line.startswith('sensors:')]
    assert rows == [n + ('=VALUE' if takes else '') for n, (takes, _) in faults.FAULTS.items()]
    nan = lines.index(next(line for line in lines if line.startswith('nan ')))
    where = ' '.join(line[22:48].strip() for line in lines[nan:nan + 3])
    assert where.startswith('laser, sonars, jointState, odometry, imu'), lines[nan:nan + 3]
    assert 'sensors: backSonar' in p.stdout and '"""' not in p.stdout
