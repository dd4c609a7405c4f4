"""The touch check (sensors/touch.py) on messages built as naoqi_driver builds them, and the
message types the package carries (msg/Bumper.msg, HandTouch.msg, HeadTouch.msg) against the
upstream definitions. Pure: no ROS master (the guided part uses an operator of its own here;
the real one, through a terminal and /sensorTest/prompt, is in test_guide.py)."""
import os

import genpy.dynamic
import pytest

from pepper_interface_tests.plan import settings
from pepper_interface_tests.results import FAIL, PASS, SKIPPED
from pepper_interface_tests.sensors import check_class, touch
from pepper_interface_tests.sensors.base import RunContext, Services
from pepper_interface_tests.sources import messages, naoqi_msgs

# ros-naoqi/naoqi_bridge_msgs master (ec254a9), msg/*.msg as published, comments and all: the
# md5sum of the real package's types is computed from exactly this text
UPSTREAM = {
    'Bumper': """# A message for Nao's bumpers on the feet

uint8 bumper            # which bumper (left or right)
uint8 state             # state of the bumper (pressed or released)

uint8 right=0
uint8 left=1
uint8 back=2

uint8 stateReleased=0
uint8 statePressed=1
""",
    'HandTouch': """# A message for Nao and Pepper's hand touch interface (touched tactile sensors on the hands)

uint8 hand            # which hand (left or right)
uint8 state           # state of the hands (pressed or released)

uint8 RIGHT_BACK=0
uint8 RIGHT_LEFT=1
uint8 RIGHT_RIGHT=2
uint8 LEFT_BACK=3
uint8 LEFT_LEFT=4
uint8 LEFT_RIGHT=5

uint8 stateReleased=0
uint8 statePressed=1
""",
    'HeadTouch': """# A message for Nao's tactile interface (toucht buttons on the head)

uint8 button            # which of the three segments is touched
uint8 state             # pressed or released, see below

uint8 buttonFront=1
uint8 buttonMiddle=2
uint8 buttonRear=3

uint8 stateReleased=0
uint8 statePressed=1
""",
}



def vals(check):
    """The values the check hands over, as the run's JSON holds them (keys and lists)."""
    from pepper_interface_tests import codec
    return codec.to_json(check.result_values())


@pytest.mark.parametrize('name', sorted(UPSTREAM))
def test_the_package_types_have_the_upstream_md5sums(name):
    upstream = genpy.dynamic.generate_dynamic('naoqi_bridge_msgs/' + name, UPSTREAM[name])
    want = upstream['naoqi_bridge_msgs/' + name]._md5sum
    # read without naoqi_bridge_msgs installed (a live connection or a bag carries the text)
    assert messages.message_class('naoqi_bridge_msgs/' + name)._md5sum == want
    # built by catkin from msg/<name>.msg
    own = messages.message_class('pepper_interface_tests/' + name)
    assert own._md5sum == want and own._type == 'pepper_interface_tests/' + name
    assert set(naoqi_msgs.TOUCH_DEFINITIONS) == {"naoqi_bridge_msgs/" + n for n in UPSTREAM}


def make(sensor, tmp_path, operator=None, **expect):
    names = ['headTouch', 'handTouch', 'bumper', 'robotHealth']
    topics = os.path.join(str(tmp_path), 'touchTopics.dat')
    with open(topics, 'w') as f:
        f.writelines('%s /t/%s\n' % (n, n) for n in names)
    plan = settings.load_plan(settings.Options(platform='robot', sensors=(sensor,), topics=topics,
                                               output_dir=str(tmp_path / 'out'), touch_wait=3.0))
    sp = plan.sensors[0]
    if expect:
        sp = settings.SensorPlan(sp.sensor, sp.topic, sp.expect.but(**expect))
    ctx = RunContext(plan.output_dir, plan.platform, plan.options, Services(operator=operator))
    return check_class(sp.sensor.family)(sp, ctx)


def msg(sensor_type, index, state):
    cls = messages.message_class('naoqi_bridge_msgs/' + sensor_type)
    m = cls()
    setattr(m, touch.zones_of(sensor_type)[0], index)
    m.state = state
    return m


def events(check, kind, items):
    """items: (t, index, state); poll() before each event, as the window does."""
    for t, i, s in items:
        check.poll(t)
        check.feed(msg(kind, i, s), t)


def judged(check, end):
    check.poll(end)
    check.close()
    return check.judgement()


def test_the_driver_index_0_is_the_front_of_the_head_not_invalid(tmp_path):
    """HeadTouch.msg declares buttonFront=1, the driver sends 0 (naoqi_driver.cpp:882)."""
    c = make('headTouch', tmp_path)
    events(c, 'HeadTouch', [(1.0, 0, 1), (1.3, 0, 0), (2.0, 2, 1), (2.2, 2, 0)])
    j = judged(c, 5.0)
    assert j.verdict == PASS and not j.warnings, j
    zones = {z['id']: z for z in vals(c)['zones']}
    assert zones['headTouch/front']['outcome'] == 'touched' and zones['headTouch/front']['held_s'] == 0.3
    assert zones['headTouch/rear']['pressed_at'] == 2.0 and zones['headTouch/middle']['outcome'] == 'not touched'
    assert any('not touched: the middle of the head' in n for n in c.notes)


def test_an_index_outside_the_driver_list_fails_naming_it(tmp_path):
    c = make('headTouch', tmp_path)
    events(c, 'HeadTouch', [(1.0, 3, 1)])        # buttonRear=3 of the file: never sent by the driver
    j = judged(c, 2.0)
    assert j.verdict == FAIL
    assert 'button 3 is outside the driver\'s list (0-2: front, middle, rear)' in j.reasons[0]


def test_a_state_other_than_released_or_pressed_fails(tmp_path):
    c = make('bumper', tmp_path)
    events(c, 'Bumper', [(1.0, 1, 2)])
    j = judged(c, 2.0)
    assert j.verdict == FAIL and 'state 2 of the front left bumper (bumper 1)' in j.reasons[0]


def test_hand_indices_follow_the_driver(tmp_path):
    c = make('handTouch', tmp_path)
    events(c, 'HandTouch', [(0.5, 3, 1), (0.9, 3, 0)])
    j = judged(c, 2.0)
    assert j.verdict == PASS
    assert [z['outcome'] for z in vals(c)['zones'] if z['presses']] == ['touched']
    assert vals(c)['zones'][3]['zone'] == 'the back of the left hand'


def test_a_zone_pressed_and_never_released_fails_as_stuck(tmp_path):
    c = make('bumper', tmp_path, max_press=2.0)
    events(c, 'Bumper', [(1.0, 2, 1)])
    j = judged(c, 3.5)
    assert j.verdict == FAIL
    assert 'the back bumper (bumper 2) stuck: pressed at t = 1 s and not released within 2 s' in j.reasons[0]
    assert vals(c)['zones'][2]['outcome'] == 'stuck'


def test_a_release_after_the_stuck_limit_still_fails(tmp_path):
    c = make('bumper', tmp_path, max_press=2.0)
    c.feed(msg('Bumper', 0, 1), 1.0)
    c.feed(msg('Bumper', 0, 0), 4.5)
    j = judged(c, 5.0)
    assert j.verdict == FAIL and 'released only 3.5 s later' in j.reasons[0]


def test_a_press_inside_the_limit_at_the_end_is_a_warning_only(tmp_path):
    c = make('bumper', tmp_path)
    events(c, 'Bumper', [(1.0, 0, 1)])
    j = judged(c, 2.0)
    assert j.verdict == PASS and 'still pressed at the end of the window' in j.warnings[0]


def test_presses_with_no_release_between_are_a_warning(tmp_path):
    c = make('headTouch', tmp_path)
    events(c, 'HeadTouch', [(1.0, 1, 1), (1.2, 1, 1), (1.4, 1, 0)])
    j = judged(c, 2.0)
    assert j.verdict == PASS
    assert 'the middle of the head (button 1) pressed again with no release in between' in j.warnings[0]


def test_unattended_nobody_touching_is_skipped_never_failed(tmp_path):
    c = make('bumper', tmp_path)
    j = judged(c, 10.0)
    assert j.verdict == SKIPPED and j.skip.startswith('not touched') and not j.reasons


class Person:
    """An operator of this test: does what `plan` says for each zone it is asked for."""

    def __init__(self, check, plan):
        self.check, self.plan, self.asked, self.owner, self.skip = check, plan, [], None, False
        self.said = []      # (zone_id, why, more): the zones given up, as the guide is told
        self.budget = 100.0

    def turn(self, owner):
        if self.owner in (None, owner):
            self.owner = owner
            return True
        return False

    def publishing(self, topic):
        return self.plan.get('publishing', True)

    def ask(self, zone_id, text):
        self.asked.append((zone_id, text))
        self.skip = self.plan.get(zone_id) == 'skip'

    def skipped(self):
        skip, self.skip = self.skip, False
        return skip

    def moved_on(self, zone_id, why, more):
        self.said.append((zone_id, why, more))

    def finished(self, owner):
        self.owner = None


def run_guided(check, person, kind, hold=0.3, step=0.1, limit=60.0):
    """Poll like the window; the person touches a zone 0.5 s after it was asked (unless dead)."""
    t, done_at = 0.0, {}
    while not check.done() and t < limit:
        check.poll(t)
        if person.asked:
            zone_id = person.asked[-1][0]
            zone = zone_id.split('/')[1]
            index = [z.id for z in touch.zones_of(kind)[1]].index(zone)
            action = person.plan.get(zone_id, 'touch')
            start = done_at.setdefault(zone_id, t + 0.5)
            if action in ('touch', 'hold') and abs(t - start) < step / 2:
                check.feed(msg(kind, index, 1), t)
            if action == 'touch' and abs(t - start - hold) < step / 2:
                check.feed(msg(kind, index, 0), t)
        t = round(t + step, 3)
    check.close()
    return check.judgement()


def test_guided_every_zone_touched_passes_and_asks_in_words(tmp_path):
    c = make('headTouch', tmp_path)
    person = Person(c, {})
    c.operator = person
    j = run_guided(c, person, 'HeadTouch')
    assert j.verdict == PASS, j
    assert person.asked == [('headTouch/front', 'Touch the front of my head'),
                            ('headTouch/middle', 'Touch the middle of my head'),
                            ('headTouch/rear', 'Touch the back of my head')]
    assert [z['outcome'] for z in vals(c)['zones']] == ['passed'] * 3 and vals(c)['mode'] == 'guided'


def test_guided_hands_ask_only_the_back_of_each_hand(tmp_path):
    c = make('handTouch', tmp_path)
    person = Person(c, {})
    c.operator = person
    assert run_guided(c, person, 'HandTouch').verdict == PASS
    assert [a[1] for a in person.asked] == ['Touch the back of my right hand', 'Touch the back of my left hand']


def test_guided_a_dead_zone_fails_by_name_and_a_skipped_one_is_not_passed(tmp_path):
    c = make('bumper', tmp_path)
    person = Person(c, {'bumper/left': 'dead', 'bumper/back': 'skip'})
    c.operator = person
    j = run_guided(c, person, 'Bumper')
    assert j.verdict == FAIL
    assert j.reasons == ['the front left bumper (bumper 1) was not pressed within 3 s of asking (a dead '
                         'sensor, or a zone already held down before the run: the driver sends only changes)']
    assert 'skipped by the operator (not tested): the back bumper' in j.warnings
    assert [z['outcome'] for z in vals(c)['zones']] == ['passed', 'not pressed within 3 s',
                                                         'skipped by the operator']
    # the person is told when the dead zone is given up, before the back bumper is asked
    assert person.said == [('bumper/left', 'not pressed within 3 s', True)]
    assert person.asked[-1][0] == 'bumper/back'


def test_guided_a_zone_given_up_is_said_and_a_press_after_its_wait_is_named(tmp_path):
    """The front zone is pressed 1.2 s after its 3 s wait, while the middle one is asked: still a
    FAIL (the wait is the rule), named as a late press with its delay, not as an unpressed zone;
    the rear zone is never pressed: the last zone given up says there is no zone left."""
    c = make('headTouch', tmp_path)
    person = Person(c, {})
    c.operator = person
    c.poll(0.0)
    assert person.asked == [('headTouch/front', 'Touch the front of my head')]
    c.poll(2.95)
    assert person.said == []
    c.poll(3.0)
    assert person.said == [('headTouch/front', 'not pressed within 3 s', True)]
    c.poll(3.05)
    assert person.asked[-1][0] == 'headTouch/middle'
    events(c, 'HeadTouch', [(4.2, 0, 1), (4.5, 0, 0), (4.6, 1, 1), (4.9, 1, 0)])
    c.poll(5.0)
    c.poll(5.05)
    assert person.asked[-1][0] == 'headTouch/rear'
    c.poll(8.05)
    assert person.said[1:] == [('headTouch/rear', 'not pressed within 3 s', False)]
    j = judged(c, 8.1)
    assert j.verdict == FAIL
    assert j.reasons == [
        'the rear of the head (button 2) was not pressed within 3 s of asking (a dead sensor, or a zone already '
        'held down before the run: the driver sends only changes)',
        'the front of the head (button 0) was pressed 1.2 s after the 3 s wait: touch sooner, or raise '
        '--touch-wait']
    zones = vals(c)['zones']
    assert [z['outcome'] for z in zones] == ['too late: pressed 1.2 s after the 3 s wait', 'passed',
                                             'not pressed within 3 s']
    assert zones[0]['presses'] == 1


def test_guided_several_late_presses_are_named_in_one_reason(tmp_path):
    c = make('handTouch', tmp_path)
    person = Person(c, {})
    c.operator = person
    c.poll(0.0)
    c.poll(3.0)
    c.poll(3.05)
    events(c, 'HandTouch', [(3.5, 0, 1), (3.7, 0, 0)])
    c.poll(6.05)
    events(c, 'HandTouch', [(7.05, 3, 1), (7.25, 3, 0)])
    assert [s[0] for s in person.said] == ['handTouch/rightBack', 'handTouch/leftBack']
    j = judged(c, 7.3)
    assert j.reasons == ['pressed after the 3 s wait: the back of the right hand (hand 0) 0.5 s after, the back '
                         'of the left hand (hand 3) 1 s after; touch sooner, or raise --touch-wait']


def test_guided_every_zone_skipped_is_skipped(tmp_path):
    c = make('handTouch', tmp_path)
    person = Person(c, {'handTouch/rightBack': 'skip', 'handTouch/leftBack': 'skip'})
    c.operator = person
    j = run_guided(c, person, 'HandTouch')
    assert j.verdict == SKIPPED and 'skipped by the operator' in j.skip


def test_guided_a_zone_held_down_fails_as_stuck_and_the_next_is_asked(tmp_path):
    c = make('bumper', tmp_path, max_press=2.0)
    person = Person(c, {'bumper/right': 'hold'})
    c.operator = person
    j = run_guided(c, person, 'Bumper')
    assert j.verdict == FAIL and 'the front right bumper (bumper 0) stuck' in j.reasons[0]
    assert len(person.asked) == 3 and vals(c)['zones'][0]['outcome'].startswith('stuck')
    assert person.said == [('bumper/right', 'stuck: pressed, not released within 2 s', True)]


def test_guided_a_zone_stuck_before_it_is_asked_is_given_up_at_once(tmp_path):
    c = make('bumper', tmp_path, max_press=2.0)
    person = Person(c, {})
    c.operator = person
    events(c, 'Bumper', [(0.5, 2, 1)])      # the back bumper jams while the front right is asked
    for t in (2.6, 2.65):
        c.poll(t)
    events(c, 'Bumper', [(2.7, 0, 1), (2.9, 0, 0)])
    for t in (3.0, 3.05, 3.1, 3.15):
        c.poll(t)
    events(c, 'Bumper', [(3.2, 1, 1), (3.4, 1, 0)])
    for t in (3.5, 3.55, 3.6, 3.65):
        c.poll(t)
    assert [a[0] for a in person.asked] == ['bumper/right', 'bumper/left', 'bumper/back']
    assert person.said == [('bumper/back', 'stuck: held down since before it was asked', False)]
    assert c.done()


def test_guided_nobody_is_asked_when_nothing_publishes_the_topic(tmp_path):
    """The CSSR4Africa fork disables the touch converters: no prompt for a topic with no publisher
    (the stream rules fail it, naming the driver setting)."""
    c = make('headTouch', tmp_path)
    person = Person(c, {'publishing': False})
    c.operator = person
    j = run_guided(c, person, 'HeadTouch', limit=5.0)
    assert person.asked == [] and c.done()
    assert [z['outcome'] for z in vals(c)['zones']] == ['not asked: no publisher on the topic'] * 3
    assert not j.reasons and j.skip is None     # the generic rule's reason comes from the stream


def test_the_guided_window_is_the_operator_budget(tmp_path):
    c = make('bumper', tmp_path)
    assert c.window(10.0) == 10.0
    c = make('bumper', tmp_path, operator=Person(None, {}))
    assert c.window(10.0) == 100.0


def test_the_report_shows_a_table_of_zones(tmp_path):
    """What the check measured, through JSON-like values, becomes the report's zone table."""
    import json

    from pepper_interface_tests import codec
    from pepper_interface_tests.outputs.report import views
    from pepper_interface_tests.outputs.report.blocks import Table
    from pepper_interface_tests.results import SensorResult
    from pepper_interface_tests.sensors.values.touch import TouchValues, ZoneRow
    c = make('bumper', tmp_path, max_press=2.0)
    events(c, 'Bumper', [(1.0, 0, 1), (1.25, 0, 0), (2.0, 2, 1)])
    judged(c, 5.0)
    values = codec.from_json(TouchValues, json.loads(json.dumps(vals(c))))     # as the JSON file keeps them
    r = SensorResult('bumper', 'BUMPER', '/t/bumper', 'naoqi_bridge_msgs/Bumper', FAIL, values=values)
    blocks = views.render('touch', r, r.values, None)
    table = [b for b in blocks if isinstance(b, Table)][0]
    assert table.head == ['zone', 'id / index', 'presses', 'pressed at', 'released at', 'held for', 'outcome']
    rows = [[getattr(cell, 'text', cell) for cell in row] for row in table.rows]
    assert rows[0] == ['the front right bumper', 'bumper/right 0', '1', '1.00 s', '1.25 s', '0.25 s', 'touched']
    assert rows[2][0] == 'the back bumper' and rows[2][-1] == 'stuck' and rows[2][4] == '-'
    # a press after its zone's wait is a failure in the table too, as "not pressed" is
    late = views.render('touch', r, TouchValues('guided', [ZoneRow(
        'the front right bumper', 'bumper/right', 0, 1, 4.2, 4.5, 0.3, 'too late: pressed 1.2 s after the 3 s wait')]),
        None)
    cell = [b for b in late if isinstance(b, Table)][0].rows[0][-1]
    assert cell.text == 'too late: pressed 1.2 s after the 3 s wait' and cell.cls == 'fail-text'


def test_files_older_than_the_new_sensors_keep_working(tmp_path):
    """An input file without the new keys does not run them; a topics file without them gives
    the robot's driver topics (with a note saying so)."""
    old_topics = tmp_path / 'oldTopics.dat'
    old_topics.write_text('BackSonar /naoqi_driver/sonar/back\nLaser /naoqi_driver/laser\n')
    old_input = tmp_path / 'oldInput.ini'
    old_input.write_text('backSonar true\nlaser true\n')
    plan = settings.load_plan(settings.Options(platform='robot', topics=str(old_topics), input=str(old_input),
                                               output_dir=str(tmp_path / 'out')))
    assert [s.name for s in plan.sensors] == ['backSonar', 'laser']
    assert 'headTouch, handTouch, bumper, robotHealth, tf (not in oldInput.ini)' in plan.notes[0]
    plan = settings.load_plan(settings.Options(platform='robot', topics=str(old_topics), output_dir=str(tmp_path),
                                               sensors=('laser', 'headTouch', 'robotHealth')))
    assert {s.name: s.topic for s in plan.sensors} == {
        'laser': '/naoqi_driver/laser', 'headTouch': '/naoqi_driver/head_touch', 'robotHealth': '/diagnostics'}
    assert "headTouch: no key in oldTopics.dat, listening on naoqi_driver's /naoqi_driver/head_touch" in plan.notes


def test_guided_mode_needs_a_person_or_the_option():
    class Tty:
        def __init__(self, tty):
            self.tty = tty

        def isatty(self):
            return self.tty
    from pepper_interface_tests.sensors.guide import guided_mode
    assert guided_mode(None, Tty(True), Tty(True))
    assert not guided_mode(None, Tty(True), Tty(False))          # output to a pipe or a file
    assert not guided_mode(None, Tty(False), Tty(True))          # no keyboard (CI, a service)
    assert not guided_mode(None, Tty(True), Tty(True), launched=True)   # roslaunch's terminal
    assert guided_mode(True, Tty(False), Tty(False), launched=True)
    assert not guided_mode(False, Tty(True), Tty(True))


@pytest.mark.parametrize('keys_tty', [True, False])
def test_a_typed_line_clears_the_echo_only_when_the_keys_come_from_a_terminal(keys_tty):
    """A terminal echoes what is typed onto the progress line: that row is cleared (ESC [F) before
    the answer. Keys from a pipe (--guided with a script typing) echo nothing: no row is cleared."""
    import io

    from pepper_interface_tests.sensors.guide import Guide

    class Stream(io.StringIO):
        def __init__(self, tty):
            super().__init__()
            self.tty = tty

        def isatty(self):
            return self.tty
    out = Stream(True)
    guide = Guide(10.0, None, out=out, keys=Stream(keys_tty))
    guide._heard('s')
    assert out.getvalue().startswith('\033[F\033[K') == keys_tty, repr(out.getvalue())
    assert 'nothing to skip: no zone is being asked' in out.getvalue()
    guide.close()


def test_a_touch_window_waiting_for_a_touch_is_not_a_silent_sensor():
    """/diagnostics and the terminal's progress line: an event topic with nothing yet is listening
    (OK), not 'waiting for data' (STALE) nor 'silent' as a stream would be."""
    from pepper_interface_tests.outputs.diagnostics import OK, STALE, live_status
    from pepper_interface_tests.outputs.terminal import progress_text
    from pepper_interface_tests.progress import Progress

    def progress(name, periodic):
        return Progress(name, 'touch', '/t', 't/T', False, 60.0, 5.0, 12.0, 0, 0, None, None, None, None,
                        (), False, periodic)
    touch_p, laser_p = progress('bumper', False), progress('laser', True)
    assert live_status(touch_p).level == OK and 'listening for events' in live_status(touch_p).message
    assert live_status(laser_p).level == STALE
    assert '1 silent (laser)' in progress_text([touch_p, laser_p], 0.0)


def test_the_emulator_faults_name_the_driver_zones():
    from pepper_interface_tests.emulator.faults import FaultError, parse_faults
    f = parse_faults('bumper:jammed=back;headTouch:dead_zone=Middle|rear;robotHealth:hot_joint=76,empty_battery')
    assert f['bumper'].jammed == ('back',) and f['headTouch'].dead_zone == ('middle', 'rear')
    assert f['robotHealth'].hot_joint == 76.0 and f['robotHealth'].empty_battery
    with pytest.raises(FaultError, match='unknown zone "front" of bumper; valid zones: right, left, back'):
        parse_faults('bumper:jammed=front')
    with pytest.raises(FaultError, match='does not apply to headTouch'):
        parse_faults('headTouch:hot_joint=70')


def test_guided_a_touch_before_the_prompt_does_not_pass_the_zone(tmp_path):
    """A zone touched (and released) before it is asked for must be touched again when asked;
    nothing then: it fails after --touch-wait, it does not wait for ever."""
    c = make('bumper', tmp_path)
    person = Person(c, {'bumper/right': 'dead', 'bumper/left': 'dead', 'bumper/back': 'dead'})
    c.operator = person
    c.feed(msg('Bumper', 1, 1), 0.0)
    c.feed(msg('Bumper', 1, 0), 0.05)
    j = run_guided(c, person, 'Bumper', limit=20.0)
    assert c.done()
    assert [z['outcome'] for z in vals(c)['zones']] == ['not pressed within 3 s'] * 3
    assert j.reasons == ['not pressed within 3 s of asking: the front right bumper (bumper 0), the front '
                         'left bumper (bumper 1), the back bumper (bumper 2) (each a dead sensor, or a zone '
                         'already held down before the run: the driver sends only changes)']
