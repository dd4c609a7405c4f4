"""The guided check of the touch sensors and bumpers, end to end on a real master: sensorTest
against the emulator (naoqi_driver's touch events and diagnostics) with its emulated operator
following /sensorTest/prompt, through a real pseudo-terminal (prompts read, keys typed), each
fault named in words, unattended runs, a driver's own indices, and a recorded bag."""
import json
import os
import re
import select
import subprocess
import sys
import time

import pytest
import rosbag
import rospy

from pepper_interface_tests.emulator.events import JOINTS, driver_array
from pepper_interface_tests.plan import declaration
from pepper_interface_tests.sources import naoqi_msgs
from rosmaster import NODES, Master, kill_group, script, spawn, wait_registered, wait_until

pytestmark = pytest.mark.integration     # every test here starts real processes
HERE = NODES   # the node scripts' folder (test/nodes/)
TOUCH = list(declaration.sensors_of('touch'))


class Emulator:
    def __init__(self, master, tmp, *args):
        self.log_path = str(tmp / ('emu_%d.log' % time.time_ns()))
        self.log = open(self.log_path, 'w')
        self.proc = spawn(script('pepperEmulator') + ['__name:=emu_%d' % time.time_ns(), '--audio', 'off']
                          + list(args), master.env(), stdout=self.log, stderr=subprocess.STDOUT)
        wait_until(lambda: 'publishers up' in open(self.log_path).read(), 60,
                   lambda: 'emulator did not start:\n' + open(self.log_path).read())

    def stop(self):
        kill_group(self.proc)
        self.log.close()


@pytest.fixture(scope='module')
def healthy(tmp_path_factory):
    """A master of its own with a healthy emulator and its operator."""
    with Master() as master:
        emu = Emulator(master, tmp_path_factory.mktemp('emu'), '--touch', 'true', '--operator', 'true')
        yield master
        emu.stop()


def sensor_test(master, out, *args, env=None, timeout=200):
    """sensorTest run to its end (stdin not a terminal); (exit code, stdout, {name: result})."""
    proc = subprocess.run(script('sensorTest') + list(args) + ['--output-dir', str(out), '--no-history'],
                          env=env or master.env(), stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, text=True, timeout=timeout)
    with open(os.path.join(str(out), 'sensorTestResults.json')) as f:
        data = json.load(f)
    return proc.returncode, proc.stdout, {s['name']: s for s in data['sensors']}


class Prompts:
    """A real subscriber of /sensorTest/prompt (rostopic echo), its lines collected."""

    def __init__(self, master, tmp):
        self.path = str(tmp / 'prompts.txt')
        self.file = open(self.path, 'w')
        self.proc = spawn(['rostopic', 'echo', '-p', '/sensorTest/prompt'], master.env(), stdout=self.file,
                          stderr=subprocess.STDOUT)
        wait_registered(master, subscribed=['/sensorTest/prompt'])

    def lines(self):
        if not self.file.closed:
            self.file.flush()
        with open(self.path) as f:
            return [ln.split(',', 1)[1].strip() for ln in f if ln[:1].isdigit()]

    def stop(self):
        kill_group(self.proc)
        self.file.close()


def test_guided_with_the_emulated_operator_passes_every_zone(healthy, tmp_path):
    prompts = Prompts(healthy, tmp_path)
    try:
        rc, out, res = sensor_test(healthy, tmp_path, '--guided', '--touch-wait', '6',
                                   '--sensors', ','.join(TOUCH + ['robotHealth']))
        wait_until(lambda: '[done]' in prompts.lines(), 10, lambda: 'no [done]: %s' % prompts.lines())
    finally:
        prompts.stop()
    assert rc == 0, out
    assert {n: r['verdict'] for n, r in res.items()} == dict.fromkeys(TOUCH + ['robotHealth'], 'PASS'), out
    assert prompts.lines() == [
        '[headTouch/front] Touch the front of my head', '[headTouch/middle] Touch the middle of my head',
        '[headTouch/rear] Touch the back of my head', '[handTouch/rightBack] Touch the back of my right hand',
        '[handTouch/leftBack] Touch the back of my left hand', '[bumper/right] Press my front right bumper',
        '[bumper/left] Press my front left bumper', '[bumper/back] Press my back bumper', '[done]']
    for name in TOUCH:
        zones = [z for z in res[name]['values']['zones'] if z['outcome'] != 'not asked (Pepper has none)']
        assert [z['outcome'] for z in zones] == ['passed'] * len(zones), zones
        assert all(z['pressed_at'] is not None and 0.2 < z['held_s'] < 1.5 for z in zones), zones
    health = res['robotHealth']
    assert health['values']['battery_percent'] == 85
    assert any(n.startswith('hottest joints: ') for n in health['notes'])
    assert '  >>> [headTouch/front] Touch the front of my head' in out
    assert 'robotHealth OK: battery 85%, not charging (driver: OK); hottest joints:' in out.replace('\n    ', ' ')


def test_unattended_nobody_touching_is_skipped_and_the_exit_code_unaffected(healthy, tmp_path):
    rc, out, res = sensor_test(healthy, tmp_path, '--sensors', ','.join(TOUCH + ['jointState']),
                               '--duration', '2', '--mode', 'parallel')
    assert rc == 0, out
    for name in TOUCH:
        assert res[name]['verdict'] == 'SKIPPED', res[name]
        assert res[name]['reasons'][0].startswith('not touched: nobody was asked to'), res[name]
    assert res['jointState']['verdict'] == 'PASS'
    assert '>>>' not in out


@pytest.fixture(scope='module')
def faulty(tmp_path_factory):
    """A master of its own with an emulator with one fault of each kind, and its operator."""
    with Master() as master:
        emu = Emulator(master, tmp_path_factory.mktemp('emu'), '--touch', 'true', '--operator', 'true', '--faults',
                       'headTouch:dead_zone=middle;bumper:jammed=back;robotHealth:hot_joint=76,empty_battery')
        yield master
        emu.stop()


def test_each_fault_fails_the_right_zone_or_joint_in_words(faulty, tmp_path):
    rc, out, res = sensor_test(faulty, tmp_path, '--guided', '--touch-wait', '4',
                               '--sensors', ','.join(TOUCH + ['robotHealth']), env=faulty.env(COLUMNS='80'))
    assert rc == 1, out
    assert res['handTouch']['verdict'] == 'PASS'
    head = res['headTouch']
    assert head['verdict'] == 'FAIL' and head['reasons'] == [
        'the middle of the head (button 1) was not pressed within 4 s of asking (a dead sensor, or a zone '
        'already held down before the run: the driver sends only changes)']
    bumper = res['bumper']
    assert bumper['verdict'] == 'FAIL' and len(bumper['reasons']) == 1
    assert bumper['reasons'][0].startswith('the back bumper (bumper 2) stuck: pressed at t = ')
    assert [z['outcome'] for z in bumper['values']['zones']][:2] == ['passed', 'passed']
    # the jammed bumper (held down 1 s after its first subscriber, never released) is given up
    # once stuck, and said so
    assert '  >>> [bumper/back] stuck: pressed, not released within 8 s, no zone left' in out, out
    health = res['robotHealth']
    assert health['verdict'] == 'FAIL'
    assert 'HipPitch 76°C: let the robot cool down' in health['reasons'][0]
    # the dead zone given up is said before the next zone is asked (the emulated operator, who
    # touches what it is asked for, does not take the note for a request)
    said = [ln.split(' (type s')[0] for ln in out.splitlines() if ln.startswith('  >>> [headTouch')]
    assert said == ['  >>> [headTouch/front] Touch the front of my head',
                    '  >>> [headTouch/middle] Touch the middle of my head',
                    '  >>> [headTouch/middle] not pressed within 4 s, next zone',
                    '  >>> [headTouch/rear] Touch the back of my head'], out
    battery = health['reasons'][1]
    assert 'battery almost empty: 12% left' in battery and 'charge it before testing' in battery
    # the health headline comes first, above the table
    summary = out[out.index('ROBOT HEALTH FAIL'):]
    assert re.search(r'^headTouch +FAIL', summary, re.M) and re.search(r'^robotHealth +FAIL', summary, re.M)
    # every line fits, or is one unbreakable word (a long temporary path stands alone on its line)
    assert all(len(line) <= 80 or len(line.split()) == 1 for line in out.splitlines()), out


def test_a_driver_without_touch_converters_fails_by_its_setting_and_nobody_is_asked(master, tmp_path):
    """The CSSR4Africa fork's boot_config.json disables the touch events (the emulator's robot
    profile follows it): guided, nobody is asked to touch, and each sensor fails naming the
    driver setting, not a dead zone."""
    emu = Emulator(master, tmp_path, '--operator', 'true')
    try:
        rc, out, res = sensor_test(master, tmp_path, '--guided', '--sensors', 'headTouch,bumper,robotHealth')
    finally:
        emu.stop()
    assert rc == 1, out
    assert '>>> [headTouch' not in out and '>>> [bumper' not in out and '[done]' in out, out
    for name, converter in (('headTouch', 'touch_head'), ('bumper', 'bumper')):
        assert res[name]['verdict'] == 'FAIL'
        assert len(res[name]['reasons']) == 1, res[name]['reasons']
        reason = res[name]['reasons'][0]
        assert reason.startswith('no publisher on /naoqi_driver/') and 'converters %s enabled' % converter in reason
    assert res['robotHealth']['verdict'] == 'PASS'


def read_until(fd, text, buf, timeout):
    deadline = time.monotonic() + timeout
    while text not in buf[0]:
        left = deadline - time.monotonic()
        if left <= 0:
            raise AssertionError('never saw %r in the terminal:\n%s' % (text, buf[0]))
        ready, _, _ = select.select([fd], [], [], left)
        if ready:
            try:
                chunk = os.read(fd, 4096)
            except OSError:
                chunk = b''
            if not chunk:
                raise AssertionError('terminal closed before %r:\n%s' % (text, buf[0]))
            buf[0] += chunk.decode('utf-8', 'replace')


def test_guided_through_a_real_terminal_the_operator_skips_a_zone(faulty, tmp_path):
    """No --guided: a terminal means a person is there. The middle zone is dead in this emulator;
    the person types s and Enter when it is asked: skipped by the operator, not failed, not passed."""
    master_fd, slave_fd = os.openpty()
    proc = spawn(script('sensorTest') + ['--sensors', 'headTouch', '--touch-wait', '20', '--output-dir',
                                         str(tmp_path), '--no-history'],
                 faulty.env(COLUMNS='100'), stdin=slave_fd, stdout=slave_fd, stderr=slave_fd)
    os.close(slave_fd)
    buf = ['']
    try:
        read_until(master_fd, '[headTouch/front] Touch the front of my head', buf, 60)
        read_until(master_fd, '[headTouch/middle] Touch the middle of my head', buf, 30)
        asked = time.monotonic()
        os.write(master_fd, b's\n')
        read_until(master_fd, '[headTouch/middle] skipped by the operator', buf, 10)
        read_until(master_fd, '[headTouch/rear] Touch the back of my head', buf, 30)
        assert time.monotonic() - asked < 10, 'the skip did not end the zone: it waited for --touch-wait'
        read_until(master_fd, '1 passed, 0 failed', buf, 60)
        proc.wait(30)
    finally:
        kill_group(proc)
        os.close(master_fd)
    assert proc.returncode == 0, buf[0]
    with open(os.path.join(str(tmp_path), 'sensorTestResults.json')) as f:
        head = json.load(f)['sensors'][0]
    assert head['verdict'] == 'PASS'
    assert [z['outcome'] for z in head['values']['zones']] == ['passed', 'skipped by the operator', 'passed']
    assert head['warnings'] == ['skipped by the operator (not tested): the middle of the head']


def test_a_zone_given_up_is_said_before_the_next_and_a_late_press_is_named(master, tmp_path):
    """At 80 columns, a person (touch_publisher.py operator: a real rospy node following
    /sensorTest/prompt) presses the front of the head 4.5 s after it is asked (1.5 s after the
    3 s wait), the middle at once, the rear never. Each zone given up is said on the terminal and
    on the prompt topic before the next is asked; the late press is named with its delay (a FAIL
    still), the rear is not pressed."""
    op = spawn([sys.executable, os.path.join(HERE, 'touch_publisher.py'), 'operator', 'HeadTouch', '/t/head',
                'front=4.5,middle=0.5'], master.env())
    topics = tmp_path / 'topics.dat'
    topics.write_text('headTouch /t/head\n')
    try:
        wait_registered(master, published=['/t/head'], subscribed=['/sensorTest/prompt'])
        prompts = Prompts(master, tmp_path)
        try:
            rc, out, res = sensor_test(master, tmp_path, '--topics', str(topics), '--guided', '--touch-wait', '3',
                                       '--sensors', 'headTouch', env=master.env(COLUMNS='80'))
            wait_until(lambda: '[done]' in prompts.lines(), 10, lambda: 'no [done]: %s' % prompts.lines())
        finally:
            prompts.stop()
    finally:
        kill_group(op)
    assert rc == 1, out
    assert prompts.lines() == [
        '[headTouch/front] Touch the front of my head', '[headTouch/front] not pressed within 3 s, next zone',
        '[headTouch/middle] Touch the middle of my head', '[headTouch/rear] Touch the back of my head',
        '[headTouch/rear] not pressed within 3 s, no zone left', '[done]'], out
    said = [ln.split(' (type s')[0] for ln in out.splitlines() if ln.startswith('  >>> ')]
    assert said == [
        '  >>> [headTouch/front] Touch the front of my head',
        '  >>> [headTouch/front] not pressed within 3 s, next zone',
        '  >>> [headTouch/middle] Touch the middle of my head',
        '  >>> [headTouch/rear] Touch the back of my head',
        '  >>> [headTouch/rear] not pressed within 3 s, no zone left',
        '  >>> [done] guided check finished'], out
    head = res['headTouch']
    assert head['verdict'] == 'FAIL'
    assert head['reasons'][0] == ('the rear of the head (button 2) was not pressed within 3 s of asking (a dead '
                                  'sensor, or a zone already held down before the run: the driver sends only '
                                  'changes)'), head['reasons']
    late = re.fullmatch(r'the front of the head \(button 0\) was pressed ([0-9.]+) s after the 3 s wait: '
                        r'touch sooner, or raise --touch-wait', head['reasons'][1])
    assert late, head['reasons']
    # pressed 4.5 s after its prompt was received, which is after it was asked: 1.5 s after the
    # wait at the least (0.1 s for the rounding); a loaded machine only delays the press more,
    # up to the rear zone's end (3 s later), when the window closes
    assert 1.4 <= float(late.group(1)) < 4.5, head['reasons']
    front, middle, rear = head['values']['zones']
    assert front['outcome'] == 'too late: pressed %s s after the 3 s wait' % late.group(1) and front['presses'] == 1
    assert (middle['outcome'], rear['outcome'], rear['presses']) == ('passed', 'not pressed within 3 s', 0)
    assert all(len(line) <= 80 or len(line.split()) == 1 for line in out.splitlines()), out


def test_a_driver_s_own_indices_are_judged_and_own_diagnostics_never_count(master, tmp_path):
    """Events as naoqi_driver sends them (naoqi_bridge_msgs types, index = position in its list),
    unattended; /diagnostics carries only other nodes' statuses, sensorTest's own among them."""
    procs = [spawn([sys.executable, os.path.join(HERE, 'touch_publisher.py'), 'HeadTouch', '/t/head',
                    '0:1@0.3,0:0@0.6,2:1@0.9,2:0@1.1'], master.env()),
             spawn([sys.executable, os.path.join(HERE, 'touch_publisher.py'), 'Bumper', '/t/bumper',
                    '3:1@0.3'], master.env()),
             spawn([sys.executable, os.path.join(HERE, 'touch_publisher.py'), 'diagnostics', 'sensorTest'],
                   master.env()),
             spawn(['rostopic', 'pub', '-r', '2', '/t/hand', 'std_msgs/String', 'data: touched'], master.env(),
                   stdout=subprocess.DEVNULL)]
    topics = tmp_path / 'topics.dat'
    topics.write_text('headTouch /t/head\nhandTouch /t/hand\nbumper /t/bumper\nrobotHealth /diagnostics\n')
    try:
        wait_registered(master, published=['/t/head', '/t/hand', '/t/bumper', '/diagnostics'])
        rc, out, res = sensor_test(master, tmp_path, '--topics', str(topics), '--mode', 'parallel',
                                   '--sensors', 'headTouch,handTouch,bumper,robotHealth', '--duration', '4',
                                   '--wait', '3')
    finally:
        for p in procs:
            kill_group(p)
    assert res['headTouch']['verdict'] == 'PASS', res['headTouch']
    zones = {z['id']: z['outcome'] for z in res['headTouch']['values']['zones']}
    assert zones == {'headTouch/front': 'touched', 'headTouch/middle': 'not touched', 'headTouch/rear': 'touched'}
    assert res['handTouch']['verdict'] == 'FAIL'     # a wrong type fails as for every sensor
    assert res['handTouch']['reasons'] == ['topic /t/hand carries std_msgs/String, expected '
                                           'naoqi_bridge_msgs/HandTouch or pepper_interface_tests/HandTouch']
    assert res['bumper']['verdict'] == 'FAIL'
    assert 'bumper 3 is outside the driver\'s list (0-2: right, left, back)' in res['bumper']['reasons'][0]
    health = res['robotHealth']
    assert health['verdict'] == 'FAIL' and health['reasons'][0].startswith(
        'no naoqi_driver diagnostics on /diagnostics within 3 s (')
    assert 'from other nodes only' in health['reasons'][0]
    assert rc == 1


def test_a_bag_is_judged_unattended(tmp_path):
    path = str(tmp_path / 'touch.bag')
    head = naoqi_msgs.known_class('naoqi_bridge_msgs/HeadTouch')
    t0 = 1000.0
    with rosbag.Bag(path, 'w') as bag:
        for i, (button, state) in enumerate([(0, 1), (0, 0), (1, 1), (1, 0)]):
            at = rospy.Time.from_sec(t0 + 0.5 + i * 0.3)
            bag.write('/naoqi_driver/head_touch', head(button=button, state=state), at)
        for k in range(4):
            temps = {j: 36.0 for j in JOINTS}
            temps['KneePitch'] = 70.0
            array = driver_array(temps, 50, False)
            array.header.stamp = rospy.Time.from_sec(t0 + k)
            bag.write('/diagnostics', array, rospy.Time.from_sec(t0 + k))
    proc = subprocess.run(script('sensorTest') + ['--bag', path, '--sensors', 'headTouch,bumper,robotHealth',
                                                  '--output-dir', str(tmp_path), '--no-history'],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=120,
                          env=dict(os.environ, ROS_MASTER_URI='http://127.0.0.1:1'))
    with open(os.path.join(str(tmp_path), 'sensorTestResults.json')) as f:
        res = {s['name']: s for s in json.load(f)['sensors']}
    assert proc.returncode == 0, proc.stdout
    assert res['headTouch']['verdict'] == 'PASS' and res['headTouch']['values']['mode'] == 'unattended'
    assert res['bumper']['verdict'] == 'SKIPPED'
    health = res['robotHealth']
    assert health['verdict'] == 'PASS'
    assert 'hot (the driver\'s WARN, 68-74 °C): KneePitch 70°C' in health['warnings']
    assert 'battery discharging: 50% left' in ' '.join(health['warnings'])
    assert 'ROBOT HEALTH WARN' in proc.stdout
