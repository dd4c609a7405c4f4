"""On sim time, ROS time is the last /clock tick this node received: /clock that reaches it
late makes a few messages look stamped ahead of it. A few such messages are a warning; a
publisher stamping with another clock (ahead in most messages) still fails (sensors/stream.py)."""
import os

import rospy
from std_msgs.msg import Header

from pepper_interface_tests.plan import catalog, expectations, settings
from pepper_interface_tests.sensors.clock import WindowClock
from pepper_interface_tests.sensors.families import traits
from pepper_interface_tests.sensors.stream import StreamCheck

EXPECTATIONS = os.path.join(settings.package_dir(), 'config', 'sensorExpectations.yaml')


def sim_check(name, platform, topic, sim_t0):
    """The stream check of sensor `name` on sim time, listening since simulation time `sim_t0`:
    (check, its window clock, its expectations)."""
    sensor = catalog.SENSORS[name]
    expect = expectations.load(EXPECTATIONS, platform)[name]
    clock = WindowClock()
    clock.t0, clock.sim_clock, clock.sim_t0 = 0.0, (lambda: sim_t0), sim_t0
    check = StreamCheck(sensor, topic, expect, traits(sensor), clock)
    check.use_sim_clock()
    return check, clock, expect


def judged(ahead_every):
    """backSonar on the simulator: 40 messages at 10 Hz of sim time, every `ahead_every`-th one
    received while the last /clock tick was 1.5 s old (the others 10 ms after their stamp)."""
    check, _, _ = sim_check('backSonar', 'simulator', '/pepper/sonar_back', 100.0)
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


def test_a_message_before_the_first_clock_tick_is_counted_off_the_sim_clock():
    """rosbag play --clock sends a topic's first message and its first /clock on separate
    connections: the message can arrive while rospy's ROS time is still 0. It counts, but has
    no sim time and no delay: once it gave 1.7e9 s of span and a rate of 0.00 Hz (a false FAIL)."""
    check, clock, expect = sim_check('realsenseRGBCamera', 'robot', '/camera/color/image_raw', 1.7e9)
    for i in range(61):
        stamp = 1.7e9 + i / 15.0
        ros_now = 0.0 if i == 0 else stamp + 0.01     # no /clock tick yet for the first one
        check.add(i / 15.0, ros_now, Header(stamp=rospy.Time.from_sec(stamp),
                                            frame_id=expect.frame_id or 'camera_color_optical_frame'))
    clock.sim_stopped_at = 1.7e9 + 4.05
    assert abs(check.stats.rate - 15.0) < 0.01, check.stats.rate
    assert check.stats.count == 61 and check.stats.before_clock == 1
    j = check.judge(4.0, [3.0, 35.0], None, False)
    assert j.reasons == [] and j.warnings == [], (j.reasons, j.warnings)


def test_a_stream_whose_every_message_came_before_the_first_tick_is_judged_without_a_crash():
    """/clock that starts only after the last message: no sim times at all. The silence rule
    falls back to the receive times; the rate on the sim clock is unknown, not 0 Hz."""
    check, clock, expect = sim_check('backSonar', 'simulator', '/pepper/sonar_back', 100.0)
    for i in range(30):
        check.add(0.1 * i, 0.0, Header(stamp=rospy.Time.from_sec(90.0 + 0.1 * i),
                                       frame_id=expect.frame_id or 'SonarBack_frame'))
    clock.sim_stopped_at = 103.0
    assert check.stats.rate is None and check.stats.before_clock == 30
    j = check.judge(3.0, [8.0, 30.0], None, False)
    assert j.reasons == [], j.reasons
