"""Stream statistics (stats.py): rates, intervals, gaps, jitter and stamps, on explicit times."""
import json

import pytest

from pepper_interface_tests import codec
from pepper_interface_tests.stats import StreamStats


def test_stats_rates_and_intervals():
    s = StreamStats(start=10.0)
    for i in range(11):
        s.add(10.5 + 0.1 * i, 100.0 + 0.05 * i, 100.01 + 0.05 * i)
    assert s.count == 11
    assert s.rate == pytest.approx(10.0)
    assert s.stamp_rate == pytest.approx(20.0)
    assert s.first_latency == pytest.approx(0.5)
    assert s.jitter == pytest.approx(0.0, abs=1e-9)
    assert s.max_interval == pytest.approx(0.1)
    assert s.delay_summary()['mean'] == pytest.approx(0.01)
    assert s.gaps(0.2) == []


def test_stats_gaps_and_jitter():
    s = StreamStats(start=0.0)
    for t in (0.0, 0.1, 0.2, 1.7, 1.8, 3.0):
        s.add(t)
    gaps = s.gaps(1.0)
    assert [(round(a, 3), round(b, 3)) for a, b in gaps] == [(0.2, 1.5), (1.8, 1.2)]
    assert s.max_interval == pytest.approx(1.5)
    assert s.jitter > 0.5
    assert s.stamp_rate is None and s.delay_summary() is None   # no headers


def test_stats_zero_backwards_and_repeated_stamps():
    s = StreamStats(start=0.0)
    for i, stamp in enumerate([0.0, 5.0, 5.1, 5.1, 4.9, 0.0, 5.3]):
        s.add(0.1 * i, stamp, 6.0)
    assert s.zero_stamps == 2
    assert s.repeated == 1
    assert s.backwards == 1
    assert s.stamps == [5.0, 5.1, 5.1, 4.9, 5.3]
    assert s.stamp_rate is None              # not trusted once stamps went backwards
    assert s.count == 7                      # every message counts for the arrival rate


def test_stats_edge_cases():
    s = StreamStats()
    assert (s.count, s.rate, s.jitter, s.first_latency, s.max_interval) == (0, None, None, None, None)
    assert s.gaps(1.0) == [] and s.rate_series() == []
    s.add(3.0)
    assert s.rate is None                    # one message: no rate
    s.add(3.0)
    assert s.rate is None                    # no time between them: no rate, no division by zero


def test_stats_rate_series_and_summary():
    s = StreamStats(start=0.0)
    for i in range(30):
        s.add(0.05 + 0.1 * i if i < 20 else 2.05 + 0.2 * (i - 20), 1.0 + 0.1 * i, 1.02 + 0.1 * i)
    series = s.rate_series(end=4.0)
    assert [t for t, _ in series] == [0.5, 1.5, 2.5, 3.5]
    assert [hz for _, hz in series] == [10.0, 10.0, 5.0, 5.0]
    d = s.summary()
    assert d.messages == 30 and d.zero_stamps == 0 and d.delay_s.max == pytest.approx(0.02)
    json.dumps(codec.to_json(d))


# ------------------------------------------------------------------ carried_rate (issue 41)

def _carried(true_rate, handed, n=4096, count=60):
    """(handed-over time, samples so far) of `count` buffers of `n` samples made at `true_rate`,
    buffer i handed over at handed(i, made_i)."""
    from pepper_interface_tests.stats import carried_rate
    period = n / float(true_rate)
    return carried_rate([(handed(i, (i + 1) * period), float((i + 1) * n)) for i in range(count)])


def test_the_carried_rate_is_right_however_the_buffers_come():
    shapes = {
        'steady': lambda i, made: made,
        'catch-up burst at the start': lambda i, made: max(made, 8 * 0.0853),
        'pauses then bursts': lambda i, made: made if made % 2.0 < 1.6 else (made // 2.0 + 1) * 2.0,
        'two or three at a time': lambda i, made: made + (0.0853 * (2 - i % 3)),
        'a backlog in sensorTest, drained at twice the pace': lambda i, made: max(made, 2.0 + (i - 10) * 0.04)
        if i >= 10 else made,
    }
    for true_rate in (48000, 44100, 16000):
        for name, shape in shapes.items():
            found = _carried(true_rate, shape)
            assert found is not None and abs(found.rate - true_rate) <= 0.01 * true_rate, (name, true_rate, found)
            if 'backlog' not in name:   # sure enough to fail a wrong rate (the spread is ~0.1 there)
                assert found.spread < 0.02, (name, true_rate, found)


def test_the_carried_rate_needs_two_times():
    from pepper_interface_tests.stats import carried_rate
    assert carried_rate([(1.0, 4096.0), (1.0, 8192.0)]) is None
    assert carried_rate([]) is None
