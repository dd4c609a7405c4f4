"""How this process handles a live source's messages (sources/handling.py, issue 41): the wait is
counted per thread, as rospy (a thread per topic) and rclpy's executor (one thread for every
topic) run callbacks, so on ROS 2 a topic's message waits for the other topics' callbacks."""
import threading

from pepper_interface_tests.sensors.lag import OwnLag
from pepper_interface_tests.sources import handling


def on_a_new_thread(fn):
    out = []
    t = threading.Thread(target=lambda: out.append(fn()))
    t.start()
    t.join()
    return out[0]


def test_a_callback_right_after_another_on_its_thread_found_its_message_waiting():
    def run():
        a = handling.begin(100.0)
        handling.finish(a, 100.3)
        b = handling.begin(100.3 + handling.GAP / 2)     # another topic's, on the same thread
        handling.finish(b, 100.5)
        c = handling.begin(100.5 + 2 * handling.GAP)     # after a break: read as it came
        handling.finish(c, 100.6)
        return a, b, c
    a, b, c = on_a_new_thread(run)
    assert a.since == 100.0 and b.since == 100.0 and c.since == c.t0
    assert abs(b.thread_busy - 0.3) < 1e-9 and abs(c.thread_busy - (0.3 + 0.2 - handling.GAP / 2)) < 1e-9


def test_threads_are_counted_apart():
    """rospy: each topic's callbacks on a thread of their own; one busy thread delays no other."""
    def busy():
        h = handling.begin(200.0)
        handling.finish(h, 205.0)
        return handling.begin(205.0 + handling.GAP / 2)

    def idle():
        return handling.begin(205.0 + handling.GAP / 2)
    assert on_a_new_thread(busy).since == 200.0
    assert on_a_new_thread(idle).since == 205.0 + handling.GAP / 2


def test_a_topic_on_a_shared_thread_is_saturated_by_the_others_callbacks():
    """rclpy: a light topic whose thread was busy with other topics' callbacks for most of its
    window could not be kept up with (its DDS queue drops); its own callbacks alone say nothing."""
    def run():
        lag = OwnLag()
        t = 300.0
        for _ in range(10):                 # 10 s: this topic's callback 1 ms, the others' 0.9 s
            mine = handling.begin(t)
            lag.start(mine)
            lag.end(mine, t + 0.001)
            handling.finish(mine, t + 0.001)
            other = handling.begin(t + 0.001)
            handling.finish(other, t + 0.901)
            t += 1.0
        return lag
    lag = on_a_new_thread(run)
    assert lag.wall < 0.02 and lag.thread_wall > 8.0
    assert lag.saturated(10.0) and not lag.saturated(20.0)
    assert '(8.1 s with the other topics\' on their thread)' in lag.describe(), lag.describe()


def test_timed_wraps_a_callback_that_feeds_no_window():
    seen = []

    def run():
        handling.timed(seen.append)('x')
        return handling.current()
    th = on_a_new_thread(run)
    assert seen == ['x'] and th.last_end is not None and th.busy >= 0.0
