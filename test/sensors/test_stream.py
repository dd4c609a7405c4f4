"""The generic stream judgement (sensors/stream.py: arrival, message count, rate, header stamps,
clock offset, publishers), with real serialized messages fed to the window at explicit times."""
import pytest

from check_runs import R0, T0, N, close, feed, judged, make_run, one_reason_with
from fake_pepper import sonar
from pepper_interface_tests.results import FAIL, PASS, SKIPPED


@pytest.mark.parametrize('lookup, words', [
    (lambda topic: (None, []), 'no publisher on /t (is the driver running'),
    (lambda topic: ('sensor_msgs/Image', []), 'topic /t is advertised as sensor_msgs/Image, expected '
                                              'sensor_msgs/Range'),
    (lambda topic: ('sensor_msgs/Range', ['/sonar_node']), 'no message on /t within 2.0 s although '
                                                           '/sonar_node publishes it'),
    (lambda topic: None, 'no message on /t within 2.0 s'),
    (None, 'no message on /t within 2.0 s'),
])
def test_no_messages_names_the_cause(tmp_path, lookup, words):
    run = make_run('backSonar', tmp_path)
    assert run.due(T0 + 1.0) == ''
    reason = run.due(T0 + 2.0)
    assert reason == 'no message within 2.0 s'
    r = close(run, at=2.0, reason=reason, lookup=lookup)
    assert r.verdict == FAIL and r.messages == 0
    assert len(r.reasons) == 1 and r.reasons[0].startswith(words), r.reasons
    assert r.stopped_because == reason and r.rate_hz is None


STEREO = '/naoqi_driver/camera/stereo/image_raw'
IR = '/naoqi_driver/camera/ir/image_raw'


@pytest.mark.parametrize('topics, verdict, words', [
    # live: the Xtion head's IR camera has a publisher, the stereo topic none
    ({IR: ('sensor_msgs/Image', ['/naoqi_driver'])}, SKIPPED,
     'this robot has an Xtion head (Pepper 1.7): naoqi_driver publishes its infrared camera on ' + IR),
    # a bag: the IR topic is in it, the stereo topic is not
    ({IR: ('sensor_msgs/Image', ['the bag'])}, SKIPPED, 'this robot has an Xtion head'),
    # no sign of an Xtion head: still a failure, with the hint
    ({}, FAIL, 'no publisher on ' + STEREO),
    ({IR: (None, [])}, FAIL, 'no publisher on ' + STEREO),
    # the stereo topic has a publisher that sent nothing: judged, whatever the IR says
    ({STEREO: ('sensor_msgs/Image', ['/naoqi_driver']), IR: ('sensor_msgs/Image', ['/naoqi_driver'])},
     FAIL, 'no message on ' + STEREO),
])
def test_a_missing_stereo_camera_on_an_xtion_head_is_skipped(tmp_path, topics, verdict, words):
    """naoqi_driver publishes camera/ir and no camera/stereo without "CameraStereo" in ALMotion's
    sensor names (src/naoqi_driver.cpp:607-613, 733-762): a healthy Pepper 1.7 is not failed."""
    run = make_run('stereoCamera', tmp_path, topic=STEREO)
    r = close(run, at=2.0, reason=run.due(T0 + 2.0), lookup=lambda t: topics.get(t, (None, [])))
    assert r.verdict == verdict, r.reasons
    assert r.reasons[0].startswith(words), r.reasons


def test_too_few_messages(tmp_path):
    r = judged('backSonar', tmp_path, [sonar(i) for i in range(2)], start=2.5, rate=5.0)
    assert r.verdict == FAIL
    one_reason_with(r, 'only 2 messages in 3.0 s (at least 3 expected)')


@pytest.mark.parametrize('rate, words', [(2.0, 'rate 2.00 Hz outside the expected 4-16 Hz'),
                                         (40.0, 'rate 40.00 Hz outside the expected 4-16 Hz')])
def test_rate_outside_band(tmp_path, rate, words):
    n = int(2.8 * rate)
    r = judged('backSonar', tmp_path, [sonar(i) for i in range(n)], rate=rate)
    assert r.verdict == FAIL
    one_reason_with(r, words)
    one_reason_with(r, 'header stamp rate')


def test_header_stamp_rate_is_checked_apart_from_arrival_rate(tmp_path):
    """Messages arrive at 10 Hz, but their stamps advance as if the sensor ran at 30 Hz."""
    r = judged('backSonar', tmp_path, [sonar(i) for i in range(N)], stamp=lambda i, ros: R0 + i / 30.0)
    assert 9 < r.rate_hz < 11
    assert r.verdict == FAIL
    one_reason_with(r, 'header stamp rate 30.00 Hz outside')


def test_zero_stamps(tmp_path):
    r = judged('backSonar', tmp_path, [sonar(i) for i in range(N)], stamp=lambda i, ros: 0)
    assert r.verdict == FAIL
    one_reason_with(r, '25 messages with a zero header stamp')
    assert r.stats.zero_stamps == N and r.stamp_rate_hz is None


def test_backwards_stamps(tmp_path):
    r = judged('backSonar', tmp_path, [sonar(i) for i in range(N)],
               stamp=lambda i, ros: ros - (0.5 if i == 10 else 0.01))
    assert r.verdict == FAIL
    one_reason_with(r, 'header stamps went backwards 1 time')


def test_repeated_stamps_are_a_warning(tmp_path):
    r = judged('backSonar', tmp_path, [sonar(i) for i in range(N)],
               stamp=lambda i, ros: R0 + (i - (i == 10)) / 10.0)
    assert r.verdict == PASS, r.reasons
    assert '1 repeated header stamp' in r.warnings


@pytest.mark.parametrize('delay, words', [(30.0, 'clock offset: header stamps are a constant 30.0 s behind'),
                                          (-3.0, 'clock offset: header stamps are a constant 3.0 s ahead of')])
def test_stale_and_future_stamps(tmp_path, delay, words):
    r = judged('backSonar', tmp_path, [sonar(i) for i in range(N)], delay=delay)
    assert r.verdict == FAIL
    one_reason_with(r, words)


def test_publisher_that_stops_mid_window(tmp_path):
    run = make_run('backSonar', tmp_path)
    run.observe_connections(1, T0 + 0.1)
    feed(run, [sonar(i) for i in range(10)])          # 0.05 .. 0.95 s
    run.observe_connections(0, T0 + 1.2)
    r = close(run, at=2.95)
    assert r.verdict == FAIL
    reason = one_reason_with(r, 'messages stopped 0.9 s after the first one; nothing for the last 2.0 s')
    assert reason.endswith('(publisher left at 1.2 s)')


def test_pause_in_the_middle_is_a_warning(tmp_path):
    run = make_run('backSonar', tmp_path)
    t = feed(run, [sonar(i) for i in range(10)])
    feed(run, [sonar(i) for i in range(10)], start=t - T0 + 1.3)   # 1.3 s pause
    r = close(run)
    assert r.verdict == PASS, r.reasons
    assert any('1 pause longer than 1.00 s (longest 1.30 s' in w for w in r.warnings), r.warnings


def test_suspicious_but_possible_conditions_are_warnings(tmp_path):
    """A constant 2 s clock offset (inside max_delay 5 s) and a rate near the band's edge
    keep the PASS and are named as warnings."""
    r = judged('backSonar', tmp_path, [sonar(i) for i in range(N)], delay=2.0)
    assert r.verdict == PASS, r.reasons
    assert any(w.startswith('clock offset: header stamps a constant 2.0 s behind') for w in r.warnings), r.warnings
    r = judged('backSonar', tmp_path, [sonar(i) for i in range(12)], rate=4.2)
    assert r.verdict == PASS, r.reasons
    assert any('near the edge of the expected 4-16 Hz' in w for w in r.warnings), r.warnings
