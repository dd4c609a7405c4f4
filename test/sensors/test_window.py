"""A sensor's listening window (sensors/window.py): when it ends, what it takes in, and a message
or a check it cannot handle, with real serialized messages fed at explicit times."""
from std_msgs.msg import String

from check_runs import R0, ROBOT, T0, N, close, feed, make_run, one_reason_with
from fake_pepper import serialized, sonar
from pepper_interface_tests.plan import catalog
from pepper_interface_tests.plan.settings import Options, SensorPlan
from pepper_interface_tests.results import FAIL
from pepper_interface_tests.sensors.base import RunContext
from pepper_interface_tests.sensors.window import SensorRun


def test_wrong_message_type_names_both_types(tmp_path):
    run = make_run('backSonar', tmp_path, topic='/naoqi_driver/sonar/back')
    for i in range(10):
        run.feed_raw('std_msgs/String', serialized(String(data='x')), T0 + 0.1 * i, R0 + 0.1 * i)
    r = close(run, lookup=lambda topic: ('std_msgs/String', ['/talker']))
    assert r.verdict == FAIL and r.messages == 0
    assert r.reasons[0] == ('topic /naoqi_driver/sonar/back carries std_msgs/String, '
                            'expected sensor_msgs/Range')
    assert r.received_type == 'std_msgs/String'


def test_corrupt_message_is_a_finding_not_a_crash(tmp_path):
    run = make_run('backSonar', tmp_path)
    feed(run, [sonar(i) for i in range(N)])
    run.feed_raw('sensor_msgs/Range', b'\x01\x02\x03', T0 + 2.9, R0 + 2.9)
    r = close(run)
    assert r.verdict == FAIL
    one_reason_with(r, 'message could not be decoded')


def test_when_a_window_ends(tmp_path):
    run = make_run('backSonar', tmp_path, wait=2.0, duration=3.0)
    feed(run, [sonar(i) for i in range(5)])
    assert run.due(T0 + 2.5) == ''              # messages came: the wait does not apply
    assert run.due(T0 + 3.0) == 'window ended'


def test_late_first_message_extends_the_window(tmp_path):
    run = make_run('backSonar', tmp_path, wait=5.0, duration=2.0)
    assert run.due(T0 + 2.5) == ''
    feed(run, [sonar(i) for i in range(3)], start=3.0)
    assert run.due(T0 + 4.9) == ''
    assert run.due(T0 + 5.0) == 'window ended'  # first message + min(window, 2 s)


def test_quick_ends_once_settled(tmp_path):
    quick = make_run('backSonar', tmp_path, quick=True, duration=10.0)
    slow = make_run('backSonar', tmp_path, quick=False, duration=10.0)
    for run in (quick, slow):
        feed(run, [sonar(i) for i in range(9)])
        assert run.due(T0 + 1.0) == ''           # 9 < quick_messages (10)
        feed(run, [sonar(i) for i in range(1)], start=0.95)
    assert quick.due(T0 + 1.0) == 'verdict settled (--quick)'
    assert slow.due(T0 + 1.0) == ''


def test_interrupted_window_says_so(tmp_path):
    run = make_run('backSonar', tmp_path)
    feed(run, [sonar(i) for i in range(12)])
    r = close(run, at=1.2, reason='interrupted')
    assert r.stopped_because == 'interrupted'
    assert r.verdict == 'INTERRUPTED'     # not judged: never a FAIL blaming the robot
    assert r.reasons == ['interrupted after 1.2 s of the 3.0 s window (12 messages)']


def test_messages_outside_the_window_are_ignored(tmp_path):
    plan = SensorPlan(catalog.SENSORS['backSonar'], '/t', ROBOT['backSonar'])
    run = SensorRun(plan, RunContext(str(tmp_path), 'robot', Options()), T0)
    run.feed_raw('sensor_msgs/Range', serialized(sonar(0)), T0, R0)       # before begin()
    run.begin(T0)
    feed(run, [sonar(i) for i in range(N)])
    r = close(run)
    run.feed_raw('sensor_msgs/Range', serialized(sonar(0)), T0 + 3.1, R0 + 3.1)   # after close()
    assert r.messages == N and run.stats.count == N
    assert run.close(T0 + 4, 'again') is r                       # closing twice: same result


def test_a_check_that_raises_fails_its_sensor_by_name(tmp_path):
    """A message a check cannot handle must not die silently in the subscriber thread."""
    run = make_run('backSonar', tmp_path)

    def broken(msg, t):
        raise ValueError('cannot handle this reading')
    run.check.on_message = broken
    feed(run, [sonar(i) for i in range(20)])
    r = close(run)
    assert r.verdict == FAIL and r.messages == 20
    assert any('could not be checked (ValueError: cannot handle this reading)' in x for x in r.reasons), r.reasons
