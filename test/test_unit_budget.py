"""The unit tier's budget line (test/conftest.py) counts what its tests cost, CPU time, not
the wall time other processes' load adds: a real pytest run, in its own process, of a unit
test that waits (no CPU) and one that computes."""
import os
import re
import shutil
import subprocess
import sys

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))


@pytest.mark.integration
def test_waiting_is_not_counted_against_the_budget_computing_is(tmp_path):
    shutil.copy(os.path.join(HERE, 'conftest.py'), str(tmp_path / 'conftest.py'))
    shutil.copytree(os.path.join(HERE, 'helpers'), str(tmp_path / 'helpers'))
    shutil.copy(os.path.join(os.path.dirname(HERE), 'pytest.ini'), str(tmp_path / 'pytest.ini'))
    (tmp_path / 'test_cost.py').write_text(
        'import time\n'
        'def test_waits():\n'
        '    time.sleep(0.6)\n'
        'def test_computes():\n'
        '    t = time.process_time()\n'
        '    while time.process_time() - t < 0.3:\n'
        '        sum(range(1000))\n')
    done = subprocess.run([sys.executable, '-m', 'pytest', '-p', 'no:cacheprovider', '-q',
                           '-m', 'unit', '-n', '0', '--rootdir', str(tmp_path), str(tmp_path)],
                          cwd=str(tmp_path), capture_output=True, text=True, timeout=120)
    line = [ln for ln in done.stdout.splitlines() if ln.startswith('unit tier:')]
    assert line, done.stdout + done.stderr
    m = re.match(r'unit tier: ([\d.]+) s of CPU in its tests \(budget ([\d.]+) s\), '
                 r'([\d.]+) s of wall time$', line[0])
    assert m, line[0]
    cpu, wall = float(m.group(1)), float(m.group(3))
    # the 0.3 s computed counts, the 0.6 s slept does not (counted, the CPU would read 0.9 s or
    # more); what pytest itself spends around the tests, and contention, add a little to the 0.3
    assert 0.3 <= cpu < 0.3 + 0.6 and wall >= 0.9, line[0]


@pytest.mark.integration
def test_a_unit_test_that_starts_a_process_fails_by_name(tmp_path):
    """The unit tier is the fast loop: a test in it that starts a process (here `true`, through
    subprocess) fails, named with the command and the fix (issue 45: the demo's 25 s and a
    lost master's 7 s had put the tier over its budget); the same test marked integration
    passes, and so does a unit test that only computes."""
    shutil.copy(os.path.join(HERE, 'conftest.py'), str(tmp_path / 'conftest.py'))
    shutil.copytree(os.path.join(HERE, 'helpers'), str(tmp_path / 'helpers'))
    shutil.copy(os.path.join(os.path.dirname(HERE), 'pytest.ini'), str(tmp_path / 'pytest.ini'))
    (tmp_path / 'test_starts.py').write_text(
        'import subprocess\n'
        'import pytest\n'
        'def test_starts_true():\n'
        '    subprocess.run(["true"], check=True)\n'
        '@pytest.mark.integration\n'
        'def test_marked_starts_true():\n'
        '    subprocess.run(["true"], check=True)\n'
        'def test_computes():\n'
        '    assert sum(range(10)) == 45\n')
    done = subprocess.run([sys.executable, '-m', 'pytest', '-p', 'no:cacheprovider', '-q', '-n', '0',
                           '--rootdir', str(tmp_path), str(tmp_path)],
                          cwd=str(tmp_path), capture_output=True, text=True, timeout=120)
    out = done.stdout + done.stderr
    assert done.returncode == 1, out
    assert '3 passed, 1 error' in out, out      # its call passed; its teardown names the process
    assert 'ERROR test_starts.py::test_starts_true' in out, out
    assert "a unit test started 1 process(es) (subprocess.Popen ['true'])" in out, out
    assert 'mark it integration' in out, out
