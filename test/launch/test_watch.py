"""The launch watch of the demo (launch/watch.py, issue 24): a node of the launch that dies while
the run goes on is named at once, with its own last words, said again at the end, and the run
exits 2 (the launch broke), not with the verdict of a dead stream.

Real parts: a real roscore, real roslaunch runs of a launch with a node that dies by itself
(test/nodes/dying_node.py), the real tools/demo.sh with the real emulator and a real SIGKILL to
its audio capture node in the middle of the run."""
import os
import signal
import subprocess
import sys
import time

import psutil
import pytest

from pepper_interface_tests.launch.watch import ended_nodes
from rosmaster import ROOT, kill_group, spawn, unregistered, wait_until

NODE = os.path.join(ROOT, 'test', 'nodes', 'dying_node.py')
DIES_AFTER = 3.0
RUN = 9.0      # the command's length: the death comes in the middle of it

STEADY = '  <node pkg="pepper_interface_tests" type="dying_node.py" name="steady" args="steady" output="screen"/>\n'
DYING = '  <node pkg="pepper_interface_tests" type="dying_node.py" name="%s" args="%s %g" output="screen"/>\n'


# roslaunch's words as pmon.py:563-572 and nodeprocess.py:392-406 write them, with its colours
ROSLAUNCH_SAYS = (
    '\x1b[1mprocess[naoqiAudio-5]: started with pid [5767]\x1b[0m\n'
    '\x1b[1m[naoqiAudioPublisher-4] process has finished cleanly\n'
    'log file: /r/log/abc/naoqiAudioPublisher-4*.log\x1b[0m\n'
    '\x1b[31m[naoqiAudio-5] process has died [pid 5767, exit code -9, cmd /x/naoqiAudio --ip 1].\n'
    'log file: /r/log/abc/naoqiAudio-5*.log\x1b[0m\n'
    '\x1b[31m================================================================================'
    'REQUIRED process [pepperEmulator-3] has died!\n'
    'process has died [pid 5764, exit code 1, cmd /x/pepperEmulator __name:=pepperEmulator].\n'
    'log file: /r/log/abc/pepperEmulator-3*.log\nInitiating shutdown!\n'
    '================================================================================\x1b[0m\n'
    '[naoqiEndpoint-2] process has died without exit code [pid 5761, cmd /x/naoqiEndpoint].\n')


def test_roslaunch_reports_of_ended_processes_are_read():
    ends = ended_nodes(ROSLAUNCH_SAYS)
    assert [(e.node, e.code, e.log_glob) for e in ends] == [
        ('naoqiAudioPublisher', 0, '/r/log/abc/naoqiAudioPublisher-4*.log'),
        ('naoqiAudio', -9, '/r/log/abc/naoqiAudio-5*.log'),
        ('pepperEmulator', 1, '/r/log/abc/pepperEmulator-3*.log'),
        ('naoqiEndpoint', None, '')]
    assert [e.how() for e in ends] == ['ended (exit code 0) in the middle of the run',
                                       'died (killed by SIGKILL)', 'died (exit code 1)', 'died']


def start_launch(master, tmp_path, mode):
    """roslaunch of a steady node and (mode 'rospy' or 'screen') one that dies DIES_AFTER s in."""
    nodes = STEADY
    if mode:
        nodes += DYING % ({'rospy': 'dyingNode', 'screen': 'flaky'}[mode], mode, DIES_AFTER)
    path = tmp_path / 'dies.launch'
    path.write_text('<launch>\n%s</launch>\n' % nodes)
    out = tmp_path / 'roslaunch.log'
    with open(str(out), 'wb') as f:
        proc = spawn(['roslaunch', str(path)], master.env(ROS_HOME=str(tmp_path / 'ros_home')),
                     stdout=f, stderr=subprocess.STDOUT)
    return proc, str(out)


def watched(proc, log, command):
    res = subprocess.run([sys.executable, '-m', 'pepper_interface_tests.launch.watch', str(proc.pid), log,
                          '--'] + command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                         timeout=120)
    return res.returncode, res.stdout


COMMAND = [sys.executable, '-c', 'import time; time.sleep(%g); print("command done", flush=True); '
           'raise SystemExit(1)' % RUN]


@pytest.mark.parametrize('mode, said', [
    ('rospy', ['dyingNode died (exit code 1)', 'lost the device /dev/fake0: Input/output error']),
    ('screen', ['flaky died (exit code 1)', 'flaky: ERROR: the capture device went away',
                'RuntimeError: capture device /dev/fake0 gone'])])
def test_a_node_that_dies_mid_run_is_named_with_its_last_words(master, tmp_path, mode, said):
    proc, log = start_launch(master, tmp_path, mode)
    try:
        wait_until(lambda: unregistered(master, [('/rosout', '/steady')]) == [], 60,
                   'the launch did not come up')
        rc, out = watched(proc, log, COMMAND)
    finally:
        kill_group(proc)
    assert rc == 2, out
    during, after = out.split('command done')
    # said while the command still ran, in the node's own words (from its log or its output)
    assert 'demo: the emulator broke during the run: ' + said[0] in during, out
    for words in said[1:]:
        assert words in during, out
    assert 'steady' not in during, out          # the node that stayed up is not blamed
    # and again at the end, last, with what it means for the verdicts
    assert said[0] in after and after.rstrip().endswith(
        'the verdicts of the sensors it fed say nothing about a robot (exit 2)'), out


def test_a_whole_launch_leaves_the_command_its_exit_code(master, tmp_path):
    proc, log = start_launch(master, tmp_path, None)
    try:
        wait_until(lambda: unregistered(master, [('/rosout', '/steady')]) == [], 60,
                   'the launch did not come up')
        rc, out = watched(proc, log, [sys.executable, '-c', 'raise SystemExit(1)'])
    finally:
        kill_group(proc)
    assert rc == 1 and 'broke' not in out, out


@pytest.mark.integration     # the demo: a roscore, the emulator, the audio bridge and sensorTest
def test_the_demo_says_the_emulator_broke_when_a_node_dies_mid_run(tmp_path):
    """The audio capture node (naoqiAudio) killed while sensorTest listens. Before: the demo
    went on, the microphone FAILed as a stopped stream (exit 1), and nothing said why."""
    env = dict(os.environ, ROS_HOME=str(tmp_path), COLUMNS='80')
    env.pop('ROS_MASTER_URI', None)
    demo = subprocess.Popen([os.path.join(ROOT, 'tools', 'demo.sh'), '--duration', '8', '--sensors',
                             'microphone,laser', '--output-dir', str(tmp_path / 'out'), '--no-report'],
                            env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, start_new_session=True)
    lines = []
    try:
        for line in demo.stdout:
            lines.append(line)
            if line.lstrip().startswith('start') and 'microphone' in line:
                break
        capture = [p for p in psutil.process_iter(['cmdline'])
                   if str(tmp_path) in ' '.join(p.info['cmdline'] or ())
                   and '__name:=naoqiAudio' in p.info['cmdline']]
        assert len(capture) == 1, ''.join(lines)
        time.sleep(2)                       # the microphone has received for a while
        capture[0].send_signal(signal.SIGKILL)
        lines += demo.stdout.readlines()
        rc = demo.wait(60)
    finally:
        kill_group(demo)
    out = ''.join(lines)
    assert rc == 2, out
    assert out.count('demo: the emulator broke during the run: naoqiAudio died (killed by SIGKILL)') == 2, out
    assert 'its last words: naoqiAudio: ' in out, out     # its own lines in the launch's output
    assert out.rstrip().endswith('say nothing about a robot (exit 2)'), out
