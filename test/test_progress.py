"""progress.Snapshots: the running windows' snapshots are taken when an observer reads them, not
on every tick (a recording's run ticks 1,200 times a minute of record time, issue 45), and the
terminal reads them only when it shows a line."""
import io

from pepper_interface_tests.outputs.terminal import Terminal
from pepper_interface_tests.progress import Progress, Snapshots


def progress(name, now):
    return Progress(name, 'range', '/t', 'sensor_msgs/Range', False, 10.0, 5.0, now, 3, 3, 10.0, None,
                    (4.0, 16.0), 10.0, (), False)


def counting():
    taken = []

    def take(now):
        taken.append(now)
        return progress('frontSonar', now)
    return take, taken


def test_len_and_truth_take_no_snapshot_reading_takes_each_once():
    take, taken = counting()
    snaps = Snapshots([take, take], 1.5)
    assert len(snaps) == 2 and bool(snaps) and taken == []
    assert [p.elapsed for p in snaps] == [1.5, 1.5] and snaps[0].name == 'frontSonar'
    assert list(snaps) and taken == [1.5, 1.5]       # taken once, then kept
    assert not Snapshots([], 0.0)


def test_the_plain_terminal_reads_the_snapshots_only_when_it_prints():
    out = io.StringIO()
    terminal = Terminal(out, plain_every=5.0)
    take, taken = counting()
    for k in range(200):                 # 10 s of 50 ms ticks
        terminal.tick(Snapshots([take], k * 0.05), k * 0.05)
    assert len(taken) == 1 and out.getvalue().count('... frontSonar') == 1, (taken, out.getvalue())
