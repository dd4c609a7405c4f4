"""Unit: the motion check's sequence (motion/sequence.py) with a stand-in for the publishers
that records what would be sent: the steps, the stop and what follows it."""
from pepper_interface_tests.motion.record import Recording
from pepper_interface_tests.motion.sequence import Sequence
from pepper_interface_tests.plan.expectations import MotionExpect


class Sent:
    """What Commands would publish (the real one needs a ROS master: test/sensors/test_motion.py)."""

    def __init__(self):
        self.log, self.closed = [], False

    def turn(self, yaw):
        assert not self.closed
        self.log.append(('turn', yaw))

    def head(self, yaw, speed):
        assert not self.closed
        self.log.append(('head', round(yaw, 3)))

    def stop(self):
        assert not self.closed
        self.log.append(('stop',))

    def close(self):
        self.closed = True


def ready(head=0.1):
    rec = Recording()
    rec.joints.append((0.0, {'HeadYaw': head}))
    rec.laser_nearest = (0.0, 2.0, 0.0)
    rec.stiffness = {'HeadYaw': 1.0, 'WheelB': 1.0}
    clock = [0.0]
    seq = Sequence(MotionExpect(), rec, Sent(), lambda: clock[0])
    seq.begin()
    seq.prepare(heard_laser=True, heard_sonar=False, heard_joints=True)
    seq.state = 'move'
    return seq, clock


def test_the_plan_is_head_there_and_back_then_a_turn_and_back():
    seq, _ = ready(head=0.1)
    assert [(s.part, round(s.target, 2), round(s.commanded, 2)) for s in seq.steps] == [
        ('head', 0.6, 0.5), ('head', -0.4, -1.0), ('head', 0.1, 0.5), ('base', 0.5, 0.5), ('base', -0.5, -0.5)]


def test_a_stop_mid_turn_sends_a_zero_twist_then_the_head_home_and_nothing_after():
    seq, clock = ready(head=0.1)
    seq.index = 3                      # the head steps done
    seq.poll(0.0)                      # sends the turn
    assert seq.commands.log == [('turn', 0.5)]
    clock[0] = 1.0
    seq.abort('the back bumper is pressed', 1.0)
    assert seq.commands.log == [('turn', 0.5), ('stop',)]      # the head never moved: not sent
    assert seq.stopped == ('stopped during "base turn +0.50 rad" (1.0 s into the step): the back '
                           'bumper is pressed; the base was stopped (zero /cmd_vel)')
    seq.finish()
    assert seq.commands.closed
    seq.poll(2.0)                      # a tick after the stop sends nothing
    assert seq.commands.log == [('turn', 0.5), ('stop',)]


def test_a_stop_after_the_head_moved_sends_it_home():
    seq, clock = ready(head=0.1)
    seq.poll(0.0)
    seq.abort('interrupted', 0.5)
    assert seq.commands.log == [('head', 0.6), ('stop',), ('head', 0.1)]
    assert seq.stopped.endswith('and the head sent back to its start')


def test_an_obstacle_seen_during_the_turn_stops_it():
    seq, clock = ready()
    seq.index = 3
    seq.poll(0.0)
    seq.rec.laser_nearest = (0.5, 0.25, 0.3)
    seq.poll(0.5)
    assert seq.state == 'stopped' and seq.commands.log[1] == ('stop',)
    assert 'obstacle closer than 0.30 m' in seq.stopped


def test_the_end_of_the_window_mid_step_stops_it_and_closes():
    seq, clock = ready()
    seq.poll(0.0)                      # head step sent
    seq.finish()
    assert seq.commands.log == [('head', 0.6), ('stop',), ('head', 0.1)]
    assert seq.commands.closed and "the check's window ended" in seq.stopped
