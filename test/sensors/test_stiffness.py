"""The stiffness witness (sensors/stiffness.py): whether the robot rests, from naoqi_driver's
per-joint Stiffness on /diagnostics (ros-naoqi/naoqi_driver src/converters/diagnostics.cpp:162,
:170), fed as the statuses come off the wire, and offered to the laser check by the runner, live
and from a bag (issue 24, point 7).

The bag test runs the real sensorTest on a real ROS 1 bag (no master): a frozen naoqi_driver scan
and the driver's /diagnostics with every joint at stiffness 0, with robotHealth NOT selected, so
only the witness reads /diagnostics.
"""
import json
import os
import subprocess

import genpy
import pytest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue

import fake_pepper as fake
from pepper_interface_tests.emulator.events import JOINTS, driver_array
from pepper_interface_tests.plan import settings
from pepper_interface_tests.plan.settings import Options
from pepper_interface_tests.sensors.base import RunContext
from pepper_interface_tests.sensors.stiffness import StiffnessWitness, witness_topic, witnesses
from rosmaster import script

PKG = settings.package_dir()
T0 = 1700000000.0
NO_MASTER = dict(os.environ, ROS_MASTER_URI='http://127.0.0.1:1')
TYPE = 'diagnostic_msgs/DiagnosticArray'


def fed(*arrays):
    w = StiffnessWitness('/diagnostics')
    for a in arrays:
        w.feed_raw(TYPE, fake.serialized(a), 0.0, 0.0)
    return w


def test_every_driver_joint_at_0_is_a_resting_robot():
    w = fed(driver_array({j: 35.0 for j in JOINTS}, 85, False, stiffness=0.0))
    assert w.stiffness() == (len(JOINTS), 0.0) and w.arrays == 1


def test_the_latest_array_counts_and_one_stiff_joint_is_an_awake_robot():
    resting = driver_array({'HipPitch': 35.0, 'HeadYaw': 34.0}, 85, False, stiffness=0.0)
    woken = driver_array({'HipPitch': 35.0}, 85, False, stiffness=0.8)
    assert fed(resting, woken).stiffness() == (2, 0.8)     # HeadYaw still 0, HipPitch now 0.8
    assert fed(woken, resting).stiffness() == (2, 0.0)


def test_other_statuses_types_and_broken_bytes_say_nothing():
    """The joints' aggregate (naoqi_driver_joints:Status, "Highest Stiffness"), another node's
    statuses, another type and undecodable bytes leave the witness without a report."""
    other = DiagnosticArray(status=[
        DiagnosticStatus(name='naoqi_driver_joints:Status', values=[KeyValue('Highest Stiffness', '1')]),
        DiagnosticStatus(name='sensorTest: laser', values=[KeyValue('Stiffness', '1')]),
        DiagnosticStatus(name='naoqi_driver_joints:HeadYaw', values=[KeyValue('Stiffness', 'n/a')])])
    w = fed(other)
    w.feed_raw('sensor_msgs/LaserScan', fake.serialized(fake.laser(0)), 0.0, 0.0)
    w.feed_raw(TYPE, b'\x05\x00', 0.0, 0.0)
    assert w.stiffness() is None and w.arrays == 0


def plan_of(topics_file, sensors):
    return settings.load_plan(Options(topics=os.path.join(PKG, 'data', topics_file), sensors=sensors,
                                      platform='robot' if topics_file == 'pepperTopics.dat' else 'simulator',
                                      output_dir='/tmp'))


def test_the_witness_listens_to_robot_health_topic_only_for_a_check_that_asks():
    robot = plan_of('pepperTopics.dat', ['laser'])       # robotHealth not selected: the file says
    assert witness_topic(robot) == '/diagnostics'
    ctx = RunContext('/tmp', 'robot', Options())
    found = witnesses(robot, ctx)
    assert [w.topic for w in found] == ['/diagnostics'] and ctx.services.stiffness is found[0]
    ctx = RunContext('/tmp', 'robot', Options())
    assert witnesses(plan_of('pepperTopics.dat', ['backSonar']), ctx) == []     # nobody asks
    assert ctx.services.stiffness is None
    sim = plan_of('simulatorTopics.dat', ['laser'])      # Gazebo has no driver diagnostics
    assert witness_topic(sim) is None and witnesses(sim, RunContext('/tmp', 'simulator', Options())) == []


@pytest.mark.integration     # a real sensorTest process (rosbag imported here: not in the unit tier)
def test_from_a_bag_a_frozen_laser_of_a_resting_robot_says_so(tmp_path):
    import rosbag
    bag_path = str(tmp_path / 'resting.bag')
    frozen = fake.laser(0)
    with rosbag.Bag(bag_path, 'w') as bag:
        for i in range(40):                      # 4 s at 10 Hz, fresh stamps, the same ranges
            t = T0 + 0.1 * i
            frozen.header.stamp = genpy.Time.from_sec(t)
            bag.write('/naoqi_driver/laser', frozen, genpy.Time.from_sec(t))
            if i % 10 == 0:                      # the driver's diagnostics at 1 Hz
                bag.write('/diagnostics', driver_array({j: 35.0 for j in JOINTS}, 85, False, stiffness=0.0),
                          genpy.Time.from_sec(t))
    out = tmp_path / 'out'
    p = subprocess.run(script('sensorTest') + [
        '--bag', bag_path, '--sensors', 'laser', '--output-dir', str(out), '--no-history',
        '--no-report', '--no-record', '--no-show', '--no-diagnostics'],
        env=NO_MASTER, capture_output=True, text=True, timeout=60)
    assert 'Traceback' not in p.stderr, p.stderr
    with open(os.path.join(str(out), 'sensorTestResults.json')) as f:
        laser = {s['name']: s for s in json.load(f)['sensors']}['laser']
    assert laser['verdict'] == 'FAIL'
    assert len(laser['reasons']) == 1, laser['reasons']
    assert 'the robot is resting (stiffness 0 on all %d joints' % len(JOINTS) in laser['reasons'][0]
    assert laser['values']['robot_resting'] is True
