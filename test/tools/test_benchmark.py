"""Unit: the benchmark tool (tools/benchmark/, sensorTestBenchmark) without running a round:
the files it points sensorTest at are read by the package's own loaders as meant, its stream
table judges counts, its profile summary adds up, its options refuse what they should. A
round itself (publisher, rostopic hz, sensorTest, ffmpeg) is run by `make bench`."""
import os
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))   # test/tools/ -> the repository
sys.path.insert(0, os.path.join(ROOT, 'tools', 'benchmark'))
import report  # noqa: E402
import sensor_test_benchmark  # noqa: E402
import workload  # noqa: E402

from pepper_interface_tests.plan import expectations  # noqa: E402


def test_the_expectations_it_writes_load_with_each_streams_rate_and_format(tmp_path):
    topics, inputs, expect = workload.write_files(str(tmp_path))
    loaded = expectations.load(expect, 'robot')
    for name, _topic, enc, w, h, rate in workload.STREAMS:
        e = loaded[name]
        assert e.rate == (round(rate * 0.8, 2), round(rate * 1.25, 2)) and e.nominal == round(rate, 2)
        if enc == 'audio':
            assert isinstance(e, expectations.AudioExpect) and e.sample_rate == 48000
        else:
            assert isinstance(e, expectations.ImageExpect) and (e.encoding, e.width, e.height) == (enc, w, h)
    with open(topics) as f:
        assert [line.split() for line in f] == [[s[0], s[1]] for s in workload.STREAMS]
    with open(inputs) as f:
        assert [line.split() for line in f] == [[s[0], 'true'] for s in workload.STREAMS]


def _results(short_by=0):
    published = {'published': {s[0]: 100 for s in workload.STREAMS}}
    results = {s[0]: {'messages': 100, 'rate_hz': s[5], 'verdict': 'PASS'} for s in workload.STREAMS}
    results['depthCamera'].update(messages=100 - short_by, verdict='FAIL', reasons=['too few'])
    return results, published


def test_the_stream_table_passes_every_message_received_and_not_one_missing(tmp_path, capsys):
    results, published = _results()
    rows, ok = report.stream_table(results, published, str(tmp_path), 0.99, record=False)
    assert ok and rows['microphone'] == {'published': 100, 'received': 100, 'recorded': None}
    results, published = _results(short_by=2)
    rows, ok = report.stream_table(results, published, str(tmp_path), 0.99, record=False)
    out = capsys.readouterr().out
    assert not ok and rows['depthCamera']['received'] == 98
    assert '320x240 16UC1 @ 20 Hz' in out and 'reason: too few' in out and 'recording off' in out


def test_a_recording_round_without_files_counts_nothing_recorded(tmp_path, capsys):
    results, published = _results()
    rows, ok = report.stream_table(results, published, str(tmp_path), 0.99, record=True)
    assert not ok and rows['frontCamera']['recorded'] is None
    out = capsys.readouterr().out
    assert 'no video' in out and 'no WAV' in out


def test_the_profile_summary_counts_self_and_inclusive_samples(tmp_path, capsys):
    path = tmp_path / 'profile.txt'
    path.write_text('main (a/cli.py:10);run (b/runner.py:5) 3\nmain (a/cli.py:10) 1\n')
    report.print_profile(str(path))
    out = capsys.readouterr().out
    assert 'profile %s: 4 samples' % path in out
    assert '75.0%  run (runner.py)' in out and '100.0%  main (cli.py)' in out


def test_modes_other_than_off_and_on_are_refused(capsys):
    with pytest.raises(SystemExit) as exc:
        sensor_test_benchmark.main(['--modes', 'sideways'])
    assert exc.value.code == 2 and '--modes takes off, on or off,on' in capsys.readouterr().err


def test_its_help_fits_an_80_column_terminal(monkeypatch, capsys):
    monkeypatch.setenv('COLUMNS', '80')
    with pytest.raises(SystemExit):
        sensor_test_benchmark.main(['--help'])
    text = capsys.readouterr().out
    assert 'sensorTestBenchmark' in text and '--runs' in text
    assert not [line for line in text.splitlines() if len(line) > 80]
