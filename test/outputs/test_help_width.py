"""--help of sensorTest, sensorTestHistory and sensorTestBenchmark on an 80-column terminal:
no line wider than the terminal, every example command kept whole on its own line (a wrapped
command could not be copied), and prose wrapped rather than cut."""
import pytest

from pepper_interface_tests import cli, history_cli
from pepper_interface_tests.outputs.terminal import HelpFormatter


@pytest.mark.parametrize('columns', [80, 100])
@pytest.mark.parametrize('build', [cli.build_parser, history_cli.build_parser])
def test_help_fits_the_terminal_and_keeps_examples_whole(monkeypatch, build, columns):
    monkeypatch.setenv('COLUMNS', str(columns))
    text = build().format_help()
    too_wide = [line for line in text.splitlines() if len(line) > columns]
    assert not too_wide, too_wide
    for line in text.splitlines():
        if line.strip().startswith('rosrun '):
            assert line.count('rosrun') == 1 and not line.endswith(' '), line


def test_the_formatter_wraps_long_lines_under_themselves_and_keeps_short_ones():
    fmt = HelpFormatter('prog', width=40)
    text = fmt._fill_text('short line\n  indented example\nexit codes: ' + 'word ' * 20, 40, '')
    lines = text.splitlines()
    assert lines[:2] == ['short line', '  indented example']
    assert all(len(line) <= 40 for line in lines)
    assert lines[2].startswith('exit codes:') and all(line.startswith('  word') for line in lines[3:])
