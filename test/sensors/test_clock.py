"""Sim time: under /use_sim_time, rates and windows are measured on the simulation clock (the
simulator runs slower than real time: Gazebo's real-time factor is often well below 1), and the
output says so. A real /clock publisher at real-time factor 0.3 and 1.0 drives real rospy
publishers that keep their rate on the simulation clock (rospy.Rate), as Gazebo's plugins do."""
import json
import os
import subprocess
import sys
import time

import pytest

from pepper_interface_tests.stats import StreamStats
from rosmaster import NODES, kill_group, script, spawn, wait_for_publishers

HERE = NODES   # the node scripts' folder (test/nodes/)


def test_stats_measure_rates_on_the_sim_clock():
    """5 Hz on the sim clock at real-time factor 0.5: 2.5 Hz of wall time, 5 Hz reported."""
    s = StreamStats(start=0.0, clock='sim', clock_start=100.0)
    for i in range(11):
        s.add(0.4 * i, 100.0 + 0.2 * i, 100.0 + 0.2 * i + 0.01, 100.0 + 0.2 * i + 0.01)
    assert s.rate == pytest.approx(5.0) and s.stamp_rate == pytest.approx(5.0)
    assert s.summary().clock == 'sim'
    assert s.gaps(0.3) == []                      # 0.4 s of wall time between messages is no gap
    assert round(s.rate_series(end=102.1)[0][1], 1) == 5.0    # bins on the sim clock
    wall = StreamStats(start=0.0)
    for i in range(11):
        wall.add(0.4 * i)
    assert wall.rate == pytest.approx(2.5) and wall.summary().clock == 'wall'


def _spawn(master, procs, *args):
    cmd = [sys.executable, os.path.join(HERE, 'driver_publisher.py')] + [str(a) for a in args]
    procs.append(spawn(cmd, master.env(), stdout=subprocess.DEVNULL))


@pytest.mark.parametrize('rtf', [0.3, 1.0])
def test_simulator_rates_on_the_sim_clock(master, tmp_path, rtf):
    procs = []
    topics = tmp_path / 'simTopics.dat'
    topics.write_text('FrontSonar /pepper/sonar_front\nLaser /pepper/laser_2\n')
    out = tmp_path / 'out'
    try:
        _spawn(master, procs, 'clock', '/clock', '--rtf', rtf, '--node', 'gazebo')
        wait_for_publishers(master, ['/clock'])    # it sets /use_sim_time before it registers
        _spawn(master, procs, 'sim_sonar', '/pepper/sonar_front', '--rate', 20, '--node', 'sonar_front')
        _spawn(master, procs, 'sim_laser', '/pepper/laser_2', '--rate', 6.25, '--node', 'laser_publisher')
        wait_for_publishers(master, ['/pepper/sonar_front', '/pepper/laser_2'])
        started = time.monotonic()
        done = subprocess.run(script('sensorTest') + [
            '--topics', str(topics), '--sensors', 'frontSonar,laser', '--platform', 'simulator',
            '--mode', 'parallel', '--duration', '3', '--wait', '6', '--output-dir', str(out),
            '--no-show', '--no-history', '--no-report', '--no-diagnostics'],
            env=master.env(), capture_output=True, text=True, timeout=120)
        wall = time.monotonic() - started
    finally:
        for p in procs:
            kill_group(p)
    path = out / 'sensorTestResults.json'
    assert path.exists(), done.stdout + done.stderr
    res = {s['name']: s for s in json.loads(path.read_text())['sensors']}
    for name, hz in (('frontSonar', 20.0), ('laser', 6.25)):
        r = res[name]
        assert r['verdict'] == 'PASS', (name, r['reasons'], r['warnings'])
        assert r['stats']['clock'] == 'sim'
        assert abs(r['rate_hz'] - hz) < 0.15 * hz, (name, r['rate_hz'])        # not hz * rtf
        assert abs(r['stamp_rate_hz'] - hz) < 0.15 * hz
        assert abs(r['stats']['real_time_factor'] - rtf) < 0.1 * rtf + 0.05, r['stats']
        assert any(n.startswith('rates measured on the simulation clock (/use_sim_time); real-time factor')
                   for n in r['notes']), r['notes']
        # the window is 3 s of simulation time: about 3 s x rate messages whatever the factor
        assert r['messages'] >= 0.8 * 3 * hz, (name, r['messages'])
    assert wall >= 3.0 / rtf * 0.9
    assert done.returncode == 0, done.stdout[-2000:]


def test_use_sim_time_without_clock_is_named(master, tmp_path):
    """/use_sim_time left true with nothing on /clock: ROS time is 0, so the reason names the
    missing /clock and the fix, not "header stamps 1.8e9 s in the future" blaming the robot."""
    import rosgraph
    procs = []
    topics = tmp_path / 'topics.dat'
    topics.write_text('FrontSonar /d/sonar/front\n')
    out = tmp_path / 'out'
    try:
        _spawn(master, procs, 'sonar', '/d/sonar/front', '--rate', 10, '--node', 'sonar_front')
        wait_for_publishers(master, ['/d/sonar/front'])   # started on wall time: stamps ~1.8e9 s
        rosgraph.Master('/test', master_uri=master.uri).setParam('/use_sim_time', True)
        done = subprocess.run(script('sensorTest') + [
            '--topics', str(topics), '--sensors', 'frontSonar', '--duration', '2', '--wait', '4',
            '--output-dir', str(out), '--no-show', '--no-history', '--no-report', '--no-diagnostics'],
            env=master.env(), capture_output=True, text=True, timeout=120)
    finally:
        for p in procs:
            kill_group(p)
    path = out / 'sensorTestResults.json'
    assert path.exists(), done.stdout + done.stderr
    sonar = json.loads(path.read_text())['sensors'][0]
    assert done.returncode == 1 and sonar['verdict'] == 'FAIL', sonar
    assert sonar['messages'] > 5, sonar
    assert any('/use_sim_time is true but nothing publishes /clock' in r and
               'rosparam set /use_sim_time false' in r for r in sonar['reasons']), sonar['reasons']
    assert not any('future' in r or 'clock offset' in r for r in sonar['reasons']), sonar['reasons']
