"""Start-up of the demo and of the tests (issue 9): port picking, a taken port, a foreign
master on our port, and tools/demo.sh saying the real cause within seconds.

Real parts only: real roscores, real sockets holding real ports, the real demo script.
"""
import os
import socket
import subprocess
import time

import psutil
import pytest

from pepper_interface_tests import rosmaster
from rosmaster import ROOT, Master


def test_free_ports_are_distinct_and_outside_the_ephemeral_range():
    low, high = rosmaster.ephemeral_range()
    seen = set()
    for _ in range(30):
        ports = rosmaster.free_ports(3)
        assert len(set(ports)) == 3
        assert not any(low <= p <= high for p in ports), (ports, low, high)
        assert not seen & set(ports), 'a port was handed out twice'
        seen.update(ports)
    # No bind to port 0 (what every rospy node does) can land on a picked port.
    for _ in range(200):
        with socket.socket() as s:
            s.bind(('127.0.0.1', 0))
            assert s.getsockname()[1] not in seen


def test_master_whose_port_was_stolen_starts_on_another_port():
    m = Master()
    stolen = m.port
    with socket.socket() as thief:   # taken between the pick and roscore's bind
        thief.bind(('127.0.0.1', stolen))
        t0 = time.monotonic()
        with m:
            took = time.monotonic() - t0
            assert m.port != stolen and 'already in use' in m.attempts[0], m.attempts
            assert took < 15, 'noticed after %.1f s' % took


def test_two_roscores_racing_for_one_port_is_a_taken_port():
    """Two roscores that pick one port at the same moment: the loser says its run_id does not
    match the parameter server's (a CI run failed on it instead of trying another port). The
    line is roslaunch's own (read from the installed roslaunch/launch.py)."""
    import importlib.util  # roslaunch is read, not imported: rosmaster.py here shadows ROS's
    spec = importlib.util.find_spec('roslaunch')
    with open(os.path.join(os.path.dirname(spec.origin), 'launch.py')) as f:
        assert 'run_id on parameter server does not match declared run_id' in f.read()
    said = ('RLException: run_id on parameter server does not match declared run_id: '
            'bfe289f2-ebbb vs bfd70fd2-ebbb')
    assert rosmaster.port_taken([said])
    assert not rosmaster.port_taken(['RLException: Invalid roslaunch XML syntax'])


def test_master_never_joins_a_foreign_master_on_its_port():
    """Two picks that collide: the second roscore must not silently use the first one's."""
    with Master() as first:
        second = Master()
        second._use_port(first.port)
        with second:
            assert second.port != first.port and 'not our own' in second.attempts[0]
            pid = rosmaster._master_pid(second.uri)
            assert isinstance(pid, int) and rosmaster._descends(pid, second.proc.pid)
            assert not rosmaster._descends(rosmaster._master_pid(first.uri), second.proc.pid)


def demo(env_extra, *args, timeout=240):
    env = dict(os.environ, **env_extra)
    env.setdefault('DEMO_MOVE', '0')     # the motion check (--move) is tested in test/sensors/test_motion.py
    env.pop('ROS_MASTER_URI', None)
    t0 = time.monotonic()
    res = subprocess.run([os.path.join(ROOT, 'tools', 'demo.sh')] + list(args), env=env,
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                         timeout=timeout)
    return res.returncode, res.stdout, time.monotonic() - t0


def test_demo_says_the_real_cause_within_seconds(tmp_path):
    """Master port held by a program that accepts connections but is no ROS master: the demo
    used to wait 60 s and say "the emulator did not come up"."""
    ports = rosmaster.free_ports(3)
    with socket.socket() as squatter:
        squatter.bind(('127.0.0.1', ports[0]))
        squatter.listen(5)
        code, out, took = demo({'DEMO_PORTS': ' '.join(map(str, ports)), 'DEMO_ATTEMPTS': '1',
                                'ROS_HOME': str(tmp_path)}, '--quick')
    head = '\n'.join(out.splitlines()[:4])
    assert code == 2, out
    assert took < 30, 'took %.0f s:\n%s' % (took, out)
    assert 'port %d is held by another program' % ports[0] in head, out


@pytest.mark.parametrize('which', ['naoqi', 'websocket'])
def test_demo_survives_a_taken_port(tmp_path, which):
    """A server port taken before its server binds it: the dead process's own words are shown
    and the demo starts again on other ports and completes."""
    ports = rosmaster.free_ports(3)
    index = {'naoqi': 1, 'websocket': 2}[which]
    with socket.socket() as squatter:
        squatter.bind(('127.0.0.1', ports[index]))
        squatter.listen(5)
        code, out, took = demo({'DEMO_PORTS': ' '.join(map(str, ports)),
                                'ROS_HOME': str(tmp_path)},
                               '--duration', '3', '--sensors', 'microphone,laser')
    first = out.split('starting again')[0]
    assert 'already in use' in first and str(ports[index]) in first, out
    assert 'starting again on other ports' in out, out
    assert code == 0 and 'microphone             PASS' in out, out
    assert not left_running(str(tmp_path)), 'processes of the failed attempt left running'


def left_running(ros_home, timeout=10.0):
    """Pids of processes still running with `ros_home` in their command line (roslaunch puts
    each node's log path, under ROS_HOME, there) once they had `timeout` s to end."""
    deadline = time.monotonic() + timeout
    while True:
        found = []
        for proc in psutil.process_iter(['cmdline', 'status']):
            if (ros_home in ' '.join(proc.info['cmdline'] or ())
                    and proc.info['status'] != psutil.STATUS_ZOMBIE):
                found.append(proc.pid)
        if not found or time.monotonic() > deadline:
            return found
        time.sleep(0.1)
