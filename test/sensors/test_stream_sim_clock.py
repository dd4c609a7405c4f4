"""On sim time, ROS time is the last /clock tick this node received: /clock that reaches it
late makes a few messages look stamped ahead of it. A few such messages are a warning; a
publisher stamping with another clock (ahead in most messages) still fails (sensors/stream.py)."""
import os

from pepper_interface_tests.plan import catalog, expectations, settings
from pepper_interface_tests.sensors.clock import WindowClock
from pepper_interface_tests.sensors.families import traits
from pepper_interface_tests.sensors.stream import StreamCheck

EXPECTATIONS = os.path.join(settings.package_dir(), 'config', 'sensorExpectations.yaml')


def judged(ahead_every):
    """backSonar on the simulator: 40 messages at 10 Hz of sim time, every `ahead_every`-th one
    received while the last /clock tick was 1.5 s old (the others 10 ms after their stamp)."""
    sensor = catalog.SENSORS['backSonar']
    expect = expectations.load(EXPECTATIONS, 'simulator')['backSonar']
    clock = WindowClock()
    clock.t0, clock.sim_clock, clock.sim_t0 = 0.0, (lambda: 100.0), 100.0
    check = StreamCheck(sensor, '/pepper/sonar_back', expect, traits(sensor), clock)
    check.use_sim_clock()
    check.stats.clock_start = 100.0
    for i in range(40):
        stamp = 100.0 + 0.1 * i                  # the simulator stamps with its own time
        late = ahead_every and i % ahead_every == 0
        ros_now = stamp - 1.5 if late else stamp + 0.01     # the last /clock tick received
        check.stats.add(0.1 * i / 0.6, stamp, ros_now, stamp + 0.01)
    return check.judge(4.0 / 0.6, [8.0, 30.0], None, False)


def test_a_few_stamps_ahead_of_a_late_clock_are_a_warning():
    j = judged(ahead_every=10)       # 4 of 40
    assert j.reasons == [], j.reasons
    assert j.warnings == ['4 of 40 header stamps up to 1.50 s ahead of the last /clock tick received '
                          '(max_future 1 s): /clock reached this node late'], j.warnings


def test_stamps_ahead_in_most_messages_fail_as_before():
    j = judged(ahead_every=1)        # every message: a publisher stamping with another clock
    assert any('in the future (clock skew?)' in r or 'clock offset' in r for r in j.reasons), j.reasons


def test_no_stamp_ahead_no_word():
    j = judged(ahead_every=0)
    assert j.reasons == [] and not any('/clock' in w for w in j.warnings), (j.reasons, j.warnings)
