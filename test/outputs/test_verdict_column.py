"""The summary's verdict column fits the longest verdict of the run (outputs/terminal.py,
issue 41): "NOT JUDGED" (10 characters) and "INTERRUPTED" (11) overflowed its 8 characters
and pushed their row's figures out of line. Rendered by the real Terminal observer into a pipe
(a file), with COLUMNS set as a terminal of that width sets it: every line fits, and each
column starts at one place on every row. A real run at COLUMNS=80: test_own_lag.py's stop."""
import io

import pytest

from pepper_interface_tests.outputs.terminal import Terminal
from pepper_interface_tests.results import FAIL, INTERRUPTED, NOT_JUDGED, PASS, RunResult, SensorResult

LONG = ('PC busy: header stamps up to 6.45 s behind ROS time (at most 5 s), but the messages waited '
        'in sensorTest itself; without that wait at most 0.01 s old (load average 8.6 on 2 cores)')


def render(columns, monkeypatch, verdicts=(PASS, NOT_JUDGED, INTERRUPTED, FAIL)):
    monkeypatch.setenv('COLUMNS', str(columns))
    run = RunResult(platform='robot', mode='sequential', start=0.0, interrupted=INTERRUPTED in verdicts,
                    interrupt_reason='Ctrl-C')
    names = ('laser', 'imu', 'frontCamera', 'backSonar')
    run.sensors = [SensorResult(name=n, title=n, topic='/' + n, msg_type='', verdict=v, messages=100 + i,
                                rate_hz=9.87, expected_rate_hz=[4.0, 16.0], reasons=[] if v == PASS else [LONG])
                   for i, (n, v) in enumerate(zip(names, verdicts))]
    out = io.StringIO()
    Terminal(out).run_ended(run)
    return out.getvalue().splitlines()


@pytest.mark.parametrize('columns', [80, 104, 120, 200])
def test_every_line_fits_and_the_figures_line_up_after_the_longest_verdict(columns, monkeypatch):
    lines = render(columns, monkeypatch)
    assert not [ln for ln in lines if len(ln) > columns], lines
    rows = [ln for ln in lines if ln.split()[:1] and ln.split()[0] in ('laser', 'imu', 'frontCamera', 'backSonar')]
    assert len(rows) == 4, lines
    # the messages count right after the verdict column (11 wide: INTERRUPTED), on every row
    ends = {ln.index(str(100 + i)) + len(str(100 + i)) for i, ln in enumerate(rows)}
    assert len(ends) == 1, rows
    for ln, verdict in zip(rows, (PASS, NOT_JUDGED, INTERRUPTED, FAIL)):
        assert ln[23:23 + len(verdict)] == verdict and ln[23 + 11] == ' ', ln
    header = [ln for ln in lines if ln.startswith('sensor ')]
    if header:      # the table (wide terminals): the reasons start under their header
        col = header[0].index('reasons')
        imu = rows[1]
        assert imu[col:].startswith('PC busy: header stamps'), (col, rows)
        assert header[0].index('messages') + len('messages') == next(iter(ends)), header


def test_without_a_long_verdict_the_column_stays_eight_wide(monkeypatch):
    rows = [ln for ln in render(120, monkeypatch, (PASS, FAIL)) if ln.startswith(('laser', 'imu'))]
    assert rows[0].index('100') == 22 + 1 + 8 + 1 + 8 - 3, rows    # '%-22s %-8s %8s'
