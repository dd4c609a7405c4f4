"""The sonar (range family) check, with real sensor_msgs/Range messages serialized as they come off
the wire and fed to the window at explicit times."""
import pytest

from check_runs import N, judged, one_reason_with
from fake_pepper import sonar
from pepper_interface_tests.results import FAIL, PASS


def test_sonar_fields_hold_the_first_message(tmp_path):
    r = judged('backSonar', tmp_path, [sonar(i, range=1.25 if i == 0 else 2.0) for i in range(N)])
    assert dict(r.fields)['Range value'] == '1.25'
    assert dict(r.fields)['Frame id'] == 'SonarBack_frame'
    assert r.values.range_m.min == 1.25 and r.values.range_m.max == 2.0


@pytest.mark.parametrize('fault, words', [
    (dict(range=float('nan')), 'range is NaN in 25 of 25 messages'),
    (dict(range=5.5), "range outside the sensor's physical limits [0, 5] m in 25 of 25 messages (e.g. 5.5)"),
    (dict(range=-0.3), 'range is negative'),
    (dict(min_range=3.0, max_range=1.0), 'min_range 3 is not below max_range 1'),
    (dict(max_range=float('inf')), 'min_range 0.25 is not below max_range inf'),
    (dict(field_of_view=0.0), 'field of view is not positive'),
    (dict(field_of_view=2.0), 'field of view outside the expected [0.1, 1.2] rad'),
    (dict(frame_id='SonarFront_frame'), 'frame_id is "SonarFront_frame", expected "SonarBack_frame"'),
])
def test_sonar_faults(tmp_path, fault, words):
    r = judged('backSonar', tmp_path, [sonar(i, **fault) for i in range(N)])
    assert r.verdict == FAIL
    one_reason_with(r, words)


def test_sonar_beyond_the_advertised_range_is_a_real_distance(tmp_path):
    """naoqi_driver advertises max_range 2.55 but publishes the raw distance (sonar.cpp:114):
    4 m with nothing in front is a healthy reading, shown as information."""
    r = judged('backSonar', tmp_path, [sonar(i, range=4.0 + 0.01 * (i % 3)) for i in range(N)])
    assert r.verdict == PASS, r.reasons
    assert r.values.beyond_advertised_max == N
    assert any('25 of 25 readings beyond the advertised range (up to 4.02 m' in n for n in r.notes)
    r = judged('backSonar', tmp_path, [sonar(i, range=0.1) for i in range(N)])
    assert r.verdict == PASS, r.reasons
    assert r.values.below_advertised_min == N


def test_sonar_without_physical_limits_uses_the_advertised_ones(tmp_path):
    r = judged('backSonar', tmp_path, [sonar(i, range=4.0) for i in range(N)],
               expect={'physical_range': None})
    assert r.verdict == FAIL
    one_reason_with(r, 'range outside [0.25, 2.55] m in 25 of 25 messages (e.g. 4)')


def test_sonar_infinite_ranges_are_valid_readings(tmp_path):
    """REP 117: +inf = nothing in range, -inf = too close."""
    r = judged('backSonar', tmp_path, [sonar(i, range=float('inf') if i % 2 else float('-inf'))
                                       for i in range(N)])
    assert r.verdict == PASS, r.reasons
    assert r.values.infinite_ranges == N


def test_sonar_one_bad_message_is_counted(tmp_path):
    r = judged('backSonar', tmp_path, [sonar(i, range=9.5 if i == 7 else 1.0) for i in range(N)])
    assert r.verdict == FAIL
    assert one_reason_with(r, 'physical limits').endswith('in 1 of 25 messages (e.g. 9.5)')
