"""sensorTest live on ROS 2 (rclpy, the Humble core of tools/platform/ros2.sh): the same data as
a ROS 1 bag, published by naoqi_driver2-shaped rclpy publishers (test/helpers/ros2_live.py),
gets the same verdicts. Run by the ROS 2 tier
(tools/ros2/tests.sh), in a ROS 2 environment (ROS_VERSION=2)."""
import os
import subprocess
import sys
import time

import pytest

import ros2_recordings as rr
from ros2_runs import domain_env, program, results, ros1_env
from rosmaster import kill_group, pause_group, script, spawn, wait_until

HERE = os.path.dirname(os.path.abspath(__file__))
LIVE = [sys.executable, os.path.join(HERE, '..', 'helpers', 'ros2_live.py')]
# a topic missing from a bag is, live, a topic nobody publishes
LIVE_WORDS = {'backSonar': 'no publisher on /sonar/back'}
QUIET = ['--no-history', '--no-report', '--no-record', '--no-show']


def bag_verdicts(tmp, faulty):
    """sensorTest --bag on ROS 1 (rospy cannot import next to ROS 2's messages: its own process)."""
    env = dict(ros1_env(), ROS_MASTER_URI='http://127.0.0.1:1')
    bag = str(tmp / 'pepper.bag')
    subprocess.run([sys.executable, '-c', 'import sys; sys.path.insert(0, %r); import ros2_recordings as rr; '
                    'rr.write_ros1(%r, rr.records(faulty=%r))' % (os.path.join(HERE, '..', 'helpers'), bag, faulty)],
                   env=env, check=True, timeout=120)
    p = subprocess.run(script('sensorTest') + ['--bag', bag, '--sensors', rr.SENSORS, '--output-dir',
                       str(tmp / 'bag')] + QUIET + ['--no-diagnostics'], env=env, capture_output=True,
                       text=True, timeout=120)
    assert p.returncode == (1 if faulty else 0), p.stdout + p.stderr
    return results(tmp / 'bag')[1]


def live_run(tmp, faulty, extra=()):
    env = domain_env()
    log = open(str(tmp / 'publisher.log'), 'w')
    pub = spawn(LIVE + (['--faulty'] if faulty else []) + ['--seconds', '12'], env,
                stdout=log, stderr=subprocess.STDOUT)
    try:
        p = subprocess.run(program('sensorTest') + ['--sensors', rr.SENSORS, '--mode', 'parallel',
                           '--duration', '4', '--output-dir', str(tmp / 'live')] + QUIET + list(extra),
                           env=env, capture_output=True, text=True, timeout=120)
    finally:
        kill_group(pub)
        log.close()
    assert 'Traceback' not in p.stdout + p.stderr, p.stdout + p.stderr
    return p, results(tmp / 'live')[1]


@pytest.mark.parametrize('faulty', [False, True], ids=['healthy', 'faulty'])
def test_live_on_ros2_same_verdicts_as_the_same_data_in_a_ros1_bag(tmp_path, faulty):
    expected = bag_verdicts(tmp_path, faulty)
    p, got = live_run(tmp_path, faulty, ['--no-diagnostics'])
    assert p.returncode == (1 if faulty else 0), p.stdout + p.stderr
    assert 'ROS 2: topics of naoqi_driver2' in p.stdout, p.stdout
    assert {n: s['verdict'] for n, s in got.items()} == {n: s['verdict'] for n, s in expected.items()}, \
        p.stdout
    for name, s in got.items():
        if faulty and name in rr.FAULTS:     # each fault fails by its name, as in the bag
            words = LIVE_WORDS.get(name, rr.FAULTS[name])
            assert any(words in r for r in s['reasons']), s
        else:
            assert s['verdict'] == 'PASS' and s['messages'] > 0, s


SPIN = '''
import os, sys, time
from std_msgs.msg import String
from pepper_interface_tests.plan.settings import package_dir
from pepper_interface_tests.sources.live2 import Ros2Graph, Ros2LiveSource

class Window:                  # a sources.Listener: the first message it is fed raises
    topic, listens, queue_size, fed = '/chatter', True, 10, 0
    def feed_raw(self, *args):
        self.fed += 1
        if self.fed == 1:
            raise ValueError('a broken message')
    def observe_connections(self, n, now):
        pass

graph = Ros2Graph('spin_test')
pub = graph.node.create_publisher(String, '/chatter', 10)
source, window = Ros2LiveSource(graph, os.path.join(package_dir(), 'msg')), Window()
source.attach(window)
end = time.monotonic() + 20
while time.monotonic() < end and window.fed < 10:
    source.poll(window, time.monotonic())
    pub.publish(String(data='x'))
    time.sleep(0.05)
print('fed', window.fed, flush=True)
graph.shutdown()
'''


def test_a_callback_that_raises_does_not_end_the_listening(tmp_path):
    """rclpy's spin() ends on the first callback that raises, and every subscription with it:
    the run's spinning says so once and goes on."""
    p = subprocess.run([sys.executable, '-c', SPIN], env=domain_env(), capture_output=True, text=True,
                       timeout=60)
    assert 'fed 10' in p.stdout, p.stdout + p.stderr
    assert p.stderr.count('a ROS 2 callback failed (ValueError: a broken message); listening goes on') == 1, \
        p.stderr


CHURN = '''
import os, threading, time
from std_msgs.msg import String
from pepper_interface_tests.plan.settings import package_dir
from pepper_interface_tests.sources.live2 import Ros2Graph, Ros2LiveSource

class Window:                  # a sources.Listener that counts what it is fed
    def __init__(self):
        self.topic, self.listens, self.queue_size, self.fed = '/chatter', True, 10, 0
    def feed_raw(self, *args):
        self.fed += 1
    def observe_connections(self, n, now):
        pass

graph = Ros2Graph('churn_test')
pub = graph.node.create_publisher(String, '/chatter', 10)
done = threading.Event()
def publish():
    while not done.is_set():
        pub.publish(String(data='x'))
        time.sleep(0.001)
threading.Thread(target=publish, daemon=True).start()
source = Ros2LiveSource(graph, os.path.join(package_dir(), 'msg'))
for _ in range(150):           # windows ending while messages flow, as a run's 10 s windows do
    w = Window()
    source.attach(w)
    start = time.monotonic()
    while w.fed == 0 and time.monotonic() - start < 2:
        source.poll(w, time.monotonic())
        time.sleep(0.002)
    source.detach(w)
last = Window()
source.attach(last)
time.sleep(1.0)
source.poll(last, time.monotonic())
time.sleep(0.5)
print('last fed', last.fed, flush=True)
done.set()
graph.shutdown()
'''


def test_windows_ending_while_messages_flow_leave_the_others_listening(tmp_path):
    """A subscription destroyed from the run's thread while rclpy's executor waits made Humble's
    rclpy raise InvalidHandle in the wait, which ended the spinning and every later window heard
    nothing (a guided touch check after the 10 s windows ended). Subscriptions are destroyed on
    the spinning thread (Ros2Graph.destroy)."""
    p = subprocess.run([sys.executable, '-c', CHURN], env=domain_env(), capture_output=True, text=True,
                       timeout=120)
    fed = [int(line.split()[-1]) for line in p.stdout.splitlines() if line.startswith('last fed')]
    assert fed and fed[0] > 0, p.stdout + p.stderr
    assert 'callback failed' not in p.stderr, p.stderr


ROS1_FIRST = '''
import struct
from pepper_interface_tests.sources import tf_buffer
from pepper_interface_tests.sources.messages import message_class
cls = message_class('tf2_msgs/TFMessage')
one = cls()
one.deserialize(struct.pack('<IIIIII7d', 1, 0, 0, 0, 0, 0, *([0.0] * 7)))
print('module', cls.__module__, 'missing', repr(tf_buffer.TF2_MISSING), flush=True)
'''


def test_a_ros1_message_package_first_on_the_path_is_not_used_on_ros2():
    """Debian's python3-tf2-msgs (ROS 1, genpy) first on the path: its TFMessage imports its
    Header by name and finds ROS 2's, which broke every sensorTest start on a machine without
    ROS 2's tf2_msgs. On ROS 2 every genpy class is built from its definition."""
    env = domain_env()
    env['PYTHONPATH'] = '/usr/lib/python3/dist-packages' + os.pathsep + env.get('PYTHONPATH', '')
    p = subprocess.run([sys.executable, '-c', ROS1_FIRST], env=env, capture_output=True, text=True, timeout=60)
    assert p.returncode == 0, p.stdout + p.stderr
    assert "missing ''" in p.stdout and 'module tf2_msgs' not in p.stdout, p.stdout


def test_messages_held_in_a_stopped_sensor_test_are_not_judged_stale_on_ros2(tmp_path):
    """sensorTest's own lag on ROS 2 (sources/handling.py, sensors/lag.py, issue 41), as on ROS 1
    (test/sensors/test_own_lag.py): sensorTest stopped by a real SIGSTOP for longer than
    max_delay (5 s) while an IMU publishes on time over rclpy (reliable, keep-last 10: the DDS
    reader holds the last 10 for it) finds the held messages' stamps old once it runs again:
    NOT JUDGED naming the PC, exit code 4, never "stale data"."""
    env = domain_env()
    others = ','.join(s for s in rr.SENSORS.split(',') if s != 'imu')
    log = open(str(tmp_path / 'publisher.log'), 'w')
    pub = spawn(LIVE + ['--seconds', '40', '--leave-out', others], env, stdout=log, stderr=subprocess.STDOUT)
    out, said = tmp_path / 'out', tmp_path / 'sensorTest.out'
    try:
        with open(str(said), 'w') as f:
            proc = spawn(program('sensorTest') + ['--sensors', 'imu', '--duration', '12', '--wait', '3',
                                                  '--output-dir', str(out)] + QUIET, env,
                         stdout=f, stderr=subprocess.STDOUT)
        try:
            wait_until(lambda: 'start  imu' in said.read_text(), 60, lambda: said.read_text())
            time.sleep(2.0)      # the subscription matched, some messages handled on time first
            pause_group(proc, 6.5)  # the stall under test: longer than max_delay (5 s)
            rc = proc.wait(90)
        finally:
            if proc.poll() is None:
                kill_group(proc)
    finally:
        kill_group(pub)
        log.close()
    text = said.read_text()
    assert 'Traceback' not in text, text
    data, rows = results(out)
    imu = rows['imu']
    assert imu['verdict'] == 'NOT JUDGED' and rc == 4, (text, imu)
    assert not any('stale data' in x for x in imu['reasons'] + imu['warnings']), imu
    reason = imu['reasons'][0]
    assert reason.startswith('PC busy: header stamps up to ') and 'waited in sensorTest itself' in reason, reason
    assert 'load average' in reason and 'sensorTest up to' in reason, reason
    assert data['exit_code'] == 4 and 'could not judge everything' in text, text
    print(reason)


def test_nothing_published_on_ros2_names_the_dds_domain_not_a_ros_master(tmp_path):
    """Robot off on ROS 2: a domain where nobody publishes. The one 'nothing is published' line
    and every sensor's reason speak of the DDS domain and what puts a driver out of reach
    (ROS_DOMAIN_ID, RMW_IMPLEMENTATION, ROS_LOCALHOST_ONLY), never of a ROS master, which ROS 2
    does not have."""
    env = domain_env()
    p = subprocess.run(program('sensorTest') + ['--sensors', 'backSonar,laser,imu', '--mode', 'sequential',
                       '--duration', '3', '--wait', '3', '--output-dir', str(tmp_path / 'out')] + QUIET
                       + ['--no-diagnostics'], env=env, capture_output=True, text=True, timeout=120)
    assert p.returncode == 1, p.stdout + p.stderr
    assert 'nothing is published' in p.stdout, p.stdout
    said = ' '.join(p.stdout.split('nothing is published', 1)[1].split())
    assert 'in ROS 2 DDS domain %s' % env['ROS_DOMAIN_ID'] in said and 'ROS_DOMAIN_ID' in said, said
    assert 'master' not in p.stdout.lower(), p.stdout
    for s in results(tmp_path / 'out')[1].values():
        assert s['verdict'] == 'FAIL' and 'in ROS 2 DDS domain' in s['reasons'][0], s
        assert 'another ROS_DOMAIN_ID' in s['reasons'][0] and 'master' not in s['reasons'][0], s


OWN = '''
import os, time
from pepper_interface_tests.plan.settings import package_dir
from pepper_interface_tests.sources import messages, ros2wire
from pepper_interface_tests.sources.live2 import Ros2Graph, Ros2LiveSource

class Window:                  # a sources.Listener: what reaches it is not this node's own
    def __init__(self):
        self.topic, self.listens, self.queue_size, self.fed = '/diagnostics', True, 10, 0
    def feed_raw(self, *args):
        self.fed += 1
    def observe_connections(self, n, now):
        pass

DA = messages.message_class('diagnostic_msgs/DiagnosticArray')
DS = messages.message_class('diagnostic_msgs/DiagnosticStatus')
KV = messages.message_class('diagnostic_msgs/KeyValue')
graph = Ros2Graph('own_test')
pub = ros2wire.RawPublisher(graph.node, '/diagnostics', 'diagnostic_msgs/DiagnosticArray', 10, remember=True)
source, window = Ros2LiveSource(graph, os.path.join(package_dir(), 'msg')), Window()
seen = []
graph.node.create_subscription(ros2wire.msg_class('diagnostic_msgs/msg/DiagnosticArray'), '/diagnostics',
                               lambda raw: seen.append(bytes(raw)), 10, raw=True)
source.attach(window)
time.sleep(1.0)
sent = []
for n in range(8):             # four lengths modulo 4 (the last value's): the padding differs
    array = DA(status=[DS(name='sensorTest: laser', message='OK', values=[KV(key='rate', value='x' * n)])])
    sent.append(len(ros2wire.to_cdr(array, pub.store)))
    pub.publish(array)
    time.sleep(0.1)
end = time.monotonic() + 10
while time.monotonic() < end and len(seen) < 8:
    source.poll(window, time.monotonic())
    time.sleep(0.05)
print('sent', sorted(set(l % 4 for l in sent)), 'padded', sum(len(s) % 4 == 0 for s in seen), 'heard', len(seen),
      'fed', window.fed, flush=True)
graph.shutdown()
'''


def test_this_nodes_own_diagnostics_are_told_apart_however_the_middleware_pads_them():
    """Cyclone DDS hands a raw subscription the serialized message padded with zeros to a
    multiple of 4 bytes: before, 3 lengths in 4 of sensorTest's own status arrays reached the
    robotHealth window as another node's ("1 array from other nodes only")."""
    p = subprocess.run([sys.executable, '-c', OWN], env=domain_env(), capture_output=True, text=True, timeout=60)
    assert 'sent [0, 1, 2, 3] padded 8 heard 8 fed 0' in p.stdout, p.stdout + p.stderr
