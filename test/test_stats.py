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
