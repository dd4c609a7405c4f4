"""The launch files: each parses (roslaunch --nodes / --dump-params / --args and roslaunch's own
check_roslaunch), the switches do what they say, missing packages stop the launch with a message
naming them, and real `roslaunch` runs of pepperEmulator.launch on a real roscore.

Launch files are given by path (not `roslaunch pepper_interface_tests X.launch`): the package
directory may hold other catkin build trees (e.g. a nested build/) in which roslaunch would find
the same launch file several times and refuse to choose.

naoqi_driver and the Gazebo simulator are not installable here; to check that the includes are
wired to them correctly, two tests put small packages with those names (package.xml + the
upstream launch file's argument interface) on ROS_PACKAGE_PATH and parse the launch with them.
"""
import json
import os
import re
import subprocess
import sys
import time

import pytest

from rosmaster import ROOT, free_port, kill_group, script, spawn, wait_until

LAUNCH = os.path.join(ROOT, 'launch')
EMULATOR = os.path.join(LAUNCH, 'pepperEmulator.launch')
ROBOT = os.path.join(LAUNCH, 'sensorTestLaunchRobot.launch')
SIMULATOR = os.path.join(LAUNCH, 'sensorTestLaunchSimulator.launch')
LISTEN = [sys.executable, os.path.join(ROOT, 'test', 'nodes', 'emu_listen.py')]
NS = '/naoqi_driver'


def roslaunch(*args, env=None):
    out = subprocess.run(['roslaunch'] + list(args), capture_output=True, text=True, timeout=120, env=env)
    return out.returncode, out.stdout, out.stderr


def nodes(path, *args, env=None):
    code, out, err = roslaunch('--nodes', path, *args, env=env)
    assert code == 0, err
    return sorted(line.strip() for line in out.splitlines() if line.strip())


def params(path, *args, env=None):
    import yaml
    code, out, err = roslaunch('--dump-params', path, *args, env=env)
    assert code == 0, err
    return yaml.safe_load(out) or {}


def node_args(path, node, *args, env=None):
    code, out, err = roslaunch('--args', node, path, *args, env=env)
    assert code == 0, err
    return out.strip()


def check_roslaunch(path):
    """roslaunch.rlutil.check_roslaunch (what roslaunch-check runs) in a clean process: this
    test directory's rosmaster.py helper would shadow ROS's rosmaster package here."""
    code = ('import json, sys; from roslaunch.rlutil import check_roslaunch; '
            'print(json.dumps(check_roslaunch(sys.argv[1])))')
    out = subprocess.run([sys.executable, '-c', code, path], stdout=subprocess.PIPE, text=True,
                         cwd='/', timeout=120)
    assert out.returncode == 0
    return json.loads(out.stdout.strip().splitlines()[-1])


def launch_nodes(path, *args, env=None):
    """The nodes roslaunch's own parser builds from a launch file with args (no master, no
    executables needed): {name: {package, type, args, required, prefix}}."""
    code = ('import json, sys\n'
            'import roslaunch.config\n'
            'path = sys.argv[1]\n'
            'sys.argv = ["roslaunch"] + sys.argv[2:]\n'
            'cfg = roslaunch.config.load_config_default([path], None)\n'
            'print(json.dumps({n.namespace + n.name: dict(package=n.package, type=n.type, '
            'args=n.args, required=n.required, prefix=n.launch_prefix) for n in cfg.nodes}))\n')
    out = subprocess.run([sys.executable, '-c', code, path] + list(args), capture_output=True,
                         text=True, cwd='/', timeout=120, env=env)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout.strip().splitlines()[-1])


# ---------------------------------------------------------------- parsing

def test_all_launch_files_pass_roslaunch_check():
    """roslaunch's own checker (as roslaunch-check): packages and node executables exist.
    With their defaults, the robot and simulator launch files must report their missing
    packages by name (naoqi_driver and pepper_gazebo_plugin are not installed here)."""
    import rospkg
    assert check_roslaunch(EMULATOR) is None
    installed = set(rospkg.RosPack().list())
    for path, package in ((ROBOT, 'naoqi_driver'), (SIMULATOR, 'pepper_gazebo_plugin')):
        error = check_roslaunch(path)
        if package in installed:
            assert error is None, error
        else:
            assert error and package in error, error


def test_emulator_launch_defaults():
    assert nodes(EMULATOR) == ['/naoqiAudio', '/naoqiAudioPublisher', '/naoqiEndpoint',
                               '/pepperEmulator']
    p = params(EMULATOR)
    assert p['/pepperEmulator/profile'] == 'robot' and p['/pepperEmulator/audio'] == 'bridge'
    assert p['/pepperEmulator/naoqi_url'] == 'tcp://127.0.0.1:9559'
    assert p['/pepperEmulator/realsense'] is False and p['/pepperEmulator/faults'] == ''
    assert p['/naoqiAudioPublisher/port'] == 9090
    assert '--port 9559' in node_args(EMULATOR, 'naoqiEndpoint')
    assert '--ws ws://127.0.0.1:9090' in node_args(EMULATOR, 'naoqiAudio')


def test_emulator_launch_switches():
    # simulator profile with the test: no bridge, sensorTest on the simulator platform
    args = ('profile:=simulator', 'run_test:=true', 'duration:=3', 'output_dir:=/tmp/x')
    assert nodes(EMULATOR, *args) == ['/pepperEmulator', '/sensorTest']
    p = params(EMULATOR, *args)
    assert (p['/sensorTest/platform'], p['/sensorTest/mode'], p['/sensorTest/duration'],
            p['/sensorTest/output_dir']) == ('simulator', 'parallel', 3, '/tmp/x')
    found = launch_nodes(EMULATOR, *args)
    # sensorTest ends the launch itself (no REQUIRED banner); the emulator is required: one that
    # cannot start ends the launch at once instead of leaving it waiting
    assert found['/sensorTest']['required'] is False and '--end-launch' in found['/sensorTest']['args']
    assert found['/pepperEmulator']['required'] is True
    # audio direct: the emulator publishes the microphones, no bridge
    assert nodes(EMULATOR, 'audio:=direct') == ['/pepperEmulator']
    # faults, ports, RealSense and a dead microphone reach the right nodes
    args = ('faults:=frontCamera:frozen;laser:nan', 'naoqi_port:=9600', 'ws_port:=9700',
            'realsense:=true', 'silent_channel:=rearRight', 'run_test:=true')
    p = params(EMULATOR, *args)
    assert p['/pepperEmulator/faults'] == 'frontCamera:frozen;laser:nan'
    assert p['/pepperEmulator/naoqi_url'] == 'tcp://127.0.0.1:9600'
    assert p['/pepperEmulator/realsense'] is True and p['/sensorTest/cameras'] == 'both'
    assert p['/naoqiAudioPublisher/port'] == 9700
    assert '/naoqiAudioPublisher/token' not in p  # the token travels in the environment only
    endpoint = node_args(EMULATOR, 'naoqiEndpoint', *args)
    assert '--port 9600' in endpoint and '--silent-channel rearRight' in endpoint
    capture = node_args(EMULATOR, 'naoqiAudio', *args)
    assert '--port 9600' in capture and 'ws://127.0.0.1:9700' in capture and '--token' not in capture


def test_robot_launch_without_naoqi_driver_names_it():
    import rospkg
    if 'naoqi_driver' in rospkg.RosPack().list():
        pytest.skip('naoqi_driver is installed on this machine')
    code, out, err = roslaunch('--nodes', ROBOT)
    assert code != 0
    assert 'missing ROS package: naoqi_driver' in err and 'naoqi_driver:=false' in err


def test_robot_launch_switches():
    assert nodes(ROBOT, 'naoqi_driver:=false') == ['/naoqiAudio', '/naoqiAudioPublisher',
                                                   '/sensorTest']
    assert nodes(ROBOT, 'naoqi_driver:=false', 'audio:=false') == ['/sensorTest']
    assert nodes(ROBOT, 'naoqi_driver:=false', 'audio:=false', 'run_test:=false') == []
    args = ('naoqi_driver:=false', 'cameras:=realsense', 'robot_ip:=10.1.2.3', 'robot_port:=9503',
            'mode:=parallel')
    p = params(ROBOT, *args)
    assert (p['/sensorTest/platform'], p['/sensorTest/cameras'], p['/sensorTest/mode']) == \
        ('robot', 'realsense', 'parallel')
    assert p['/naoqiAudioPublisher/topic'] == '/naoqi_driver/audio'
    assert '--ip 10.1.2.3 --port 9503' in node_args(ROBOT, 'naoqiAudio', *args)


def _package(root, name, launch=None, launch_text=None):
    d = root / name
    (d / 'launch').mkdir(parents=True)
    (d / 'package.xml').write_text(
        '<?xml version="1.0"?>\n<package format="2"><name>%s</name><version>0.0.0</version>'
        '<description>test</description><maintainer email="a@b.c">t</maintainer>'
        '<license>BSD</license><buildtool_depend>catkin</buildtool_depend></package>\n' % name)
    if launch:
        (d / 'launch' / launch).write_text(launch_text)


# naoqi_driver's launch file: older releases declare nao_ip, roscore_ip, network_interface only;
# newer ones add nao_port and namespace (and username/password).
NAOQI_DRIVER_OLD = '''<launch>
  <arg name="nao_ip" default="$(optenv NAO_IP)"/>
  <arg name="roscore_ip" default="127.0.0.1"/>
  <arg name="network_interface" default="eth0"/>
  <node pkg="naoqi_driver" type="naoqi_driver_node" name="naoqi_driver" required="true"
        args="--qi-url=tcp://$(arg nao_ip):9559 --roscore_ip=$(arg roscore_ip) --network_interface=$(arg network_interface)"/>
</launch>
'''
NAOQI_DRIVER_NEW = '''<launch>
  <arg name="nao_ip" default="$(optenv NAO_IP 127.0.0.1)"/>
  <arg name="nao_port" default="$(optenv NAO_PORT 9559)"/>
  <arg name="roscore_ip" default="127.0.0.1"/>
  <arg name="network_interface" default="eth0"/>
  <arg name="namespace" default="naoqi_driver"/>
  <arg name="username" default="nao"/>
  <arg name="password" default="no_password"/>
  <node pkg="naoqi_driver" type="naoqi_driver_node" name="$(arg namespace)" required="true"
        args="--qi-url=tcp://$(arg nao_ip):$(arg nao_port) --roscore_ip=$(arg roscore_ip) --network_interface=$(arg network_interface) --namespace=$(arg namespace)"/>
</launch>
'''


@pytest.mark.parametrize('launch_text,expect', [
    (NAOQI_DRIVER_OLD, '--qi-url=tcp://10.1.2.3:9559 --roscore_ip=10.1.2.9 --network_interface=wlan0'),
    (NAOQI_DRIVER_NEW, '--qi-url=tcp://10.1.2.3:9503 --roscore_ip=10.1.2.9 '
                       '--network_interface=wlan0 --namespace=naoqi_driver'),
], ids=['old-interface', 'new-interface'])
def test_robot_launch_includes_naoqi_driver(tmp_path, launch_text, expect):
    _package(tmp_path, 'naoqi_driver', 'naoqi_driver.launch', launch_text)
    env = dict(os.environ, ROS_PACKAGE_PATH='%s:%s' % (tmp_path, os.environ['ROS_PACKAGE_PATH']))
    args = ('robot_ip:=10.1.2.3', 'robot_port:=9503', 'roscore_ip:=10.1.2.9',
            'network_interface:=wlan0')
    assert nodes(ROBOT, *args, env=env) == ['/naoqiAudio', '/naoqiAudioPublisher', '/naoqi_driver',
                                            '/sensorTest']
    found = launch_nodes(ROBOT, *args, env=env)
    driver = found['/naoqi_driver']
    assert (driver['package'], driver['type'], driver['args']) == ('naoqi_driver',
                                                                   'naoqi_driver_node', expect)
    assert found['/sensorTest']['required'] is False and '--end-launch' in found['/sensorTest']['args']


# the CSSR4Africa fork's launch file (cssr4africa/naoqi_driver launch/naoqi_driver.launch):
# launch_audio (default true) starts its own audio bridge next to the driver
NAOQI_DRIVER_CSSR = '''<launch>
  <arg name="nao_ip" default="$(optenv NAO_IP)" />
  <arg name="nao_port" default="$(optenv NAO_PORT 9559)" />
  <arg name="roscore_ip" default="127.0.0.1" />
  <arg name="network_interface" default="eth0" />
  <arg name="namespace" default="naoqi_driver" />
  <arg name="launch_audio" default="true" />
  <node pkg="naoqi_driver" type="naoqi_driver_node" name="$(arg namespace)" required="true"
        args="--qi-url=tcp://$(arg nao_ip):$(arg nao_port) --roscore_ip=$(arg roscore_ip) --network_interface=$(arg network_interface) --namespace=$(arg namespace)"/>
  <group if="$(arg launch_audio)">
    <node pkg="naoqi_driver" type="naoqiAudioPublisher.py" name="naoqiAudioPublisher" output="screen"/>
  </group>
  <group if="$(arg launch_audio)">
    <node pkg="naoqi_driver" type="run_naoqiAudio.sh" name="naoqiAudio" args="--ip=$(arg nao_ip) --port=$(arg nao_port)"/>
  </group>
</launch>
'''


def test_robot_launch_never_starts_two_audio_bridges(tmp_path):
    """With the CSSR fork's driver launch, only one bridge runs: this package's (the fork gets
    launch_audio:=false) or, with driver_audio:=true, the fork's own."""
    _package(tmp_path, 'naoqi_driver', 'naoqi_driver.launch', NAOQI_DRIVER_CSSR)
    env = dict(os.environ, ROS_PACKAGE_PATH='%s:%s' % (tmp_path, os.environ['ROS_PACKAGE_PATH']))
    found = launch_nodes(ROBOT, env=env)
    audio = sorted((n, v['package']) for n, v in found.items() if 'Audio' in n)
    assert audio == [('/naoqiAudio', 'pepper_interface_tests'),
                     ('/naoqiAudioPublisher', 'pepper_interface_tests')], audio
    found = launch_nodes(ROBOT, 'driver_audio:=true', env=env)
    audio = sorted((n, v['package']) for n, v in found.items() if 'Audio' in n)
    assert audio == [('/naoqiAudio', 'naoqi_driver'), ('/naoqiAudioPublisher', 'naoqi_driver')], audio
    # stock naoqi_driver (no launch_audio arg): driver_audio:=true leaves the driver's AudioBuffer alone
    assert nodes(ROBOT, 'naoqi_driver:=false', 'driver_audio:=true') == ['/sensorTest']


def test_emulator_launch_profiles():
    # robot-stock: the driver's own AudioBuffer (emulator, audio direct), no bridge
    assert nodes(EMULATOR, 'profile:=robot-stock') == ['/pepperEmulator']
    p = params(EMULATOR, 'profile:=robot-stock', 'head:=xtion', 'run_test:=true')
    assert (p['/pepperEmulator/profile'], p['/pepperEmulator/audio'], p['/pepperEmulator/head'],
            p['/sensorTest/platform']) == ('robot-stock', 'direct', 'xtion', 'robot')
    assert '/use_sim_time' not in p
    # simulator: sim time for every node of the launch, the real-time factor reaches the emulator
    p = params(EMULATOR, 'profile:=simulator', 'real_time_factor:=0.3')
    assert p['/use_sim_time'] is True and p['/pepperEmulator/real_time_factor'] == 0.3
    assert params(EMULATOR)['/pepperEmulator/real_time_factor'] == 0.6


def test_simulator_launch_without_gazebo_names_missing_packages():
    import rospkg
    if 'pepper_gazebo_plugin' in rospkg.RosPack().list():
        pytest.skip('pepper_gazebo_plugin is installed on this machine')
    code, out, err = roslaunch('--nodes', SIMULATOR)
    assert code != 0
    assert 'missing ROS packages: pepper_gazebo_plugin' in err and 'gazebo:=false' in err


def test_simulator_launch_switches(tmp_path):
    assert nodes(SIMULATOR, 'gazebo:=false') == ['/sensorTest']
    p = params(SIMULATOR, 'gazebo:=false')
    assert (p['/sensorTest/platform'], p['/sensorTest/mode']) == ('simulator', 'sequential')
    assert nodes(SIMULATOR, 'gazebo:=false', 'run_test:=false') == []
    # with the simulator's packages present, its world launch is included and unpaused
    for name in ('pepper_description', 'pepper_control', 'gazebo_ros'):
        _package(tmp_path, name)
    _package(tmp_path, 'pepper_gazebo_plugin', 'pepper_gazebo_plugin_Y20_CPU.launch',
             '<launch><node pkg="gazebo_ros" type="spawn_model" name="spawn_urdf"/></launch>\n')
    env = dict(os.environ, ROS_PACKAGE_PATH='%s:%s' % (tmp_path, os.environ['ROS_PACKAGE_PATH']))
    assert nodes(SIMULATOR, env=env) == ['/sensorTest', '/spawn_urdf', '/unpause_gazebo']
    found = launch_nodes(SIMULATOR, 'test_delay:=7', env=env)
    assert found['/sensorTest']['required'] is False and '--end-launch' in found['/sensorTest']['args']
    # exec: sensorTest's parent is roslaunch, which it ends (launch_end.py)
    assert found['/sensorTest']['prefix'].startswith("bash -c 'sleep 7; exec ")
    assert found['/unpause_gazebo']['args'] == 'call --wait /gazebo/unpause_physics'


# ---------------------------------------------------------------- real runs

LAUNCH_TOPICS = {NS + '/camera/front/image_raw': 'sensor_msgs/Image',
                 NS + '/camera/depth/image_raw': 'sensor_msgs/Image',
                 NS + '/laser': 'sensor_msgs/LaserScan', NS + '/sonar/back': 'sensor_msgs/Range',
                 NS + '/odom': 'nav_msgs/Odometry', NS + '/imu/base': 'sensor_msgs/Imu',
                 '/joint_states': 'sensor_msgs/JointState',
                 NS + '/audio': 'pepper_interface_tests/AudioCustomMsg'}


@pytest.fixture(scope='module')
def emulator_launch_run(module_master, tmp_path_factory):
    """One real `roslaunch pepperEmulator.launch` (robot, audio bridge) on free ports, listened
    to for 8 s with a /speech sentence at 3 s: (what was received, the roslaunch log, exit code)."""
    log_path = tmp_path_factory.mktemp('launch') / 'roslaunch.log'
    with open(log_path, 'w') as log:
        launch = spawn(['roslaunch', EMULATOR, 'naoqi_port:=%d' % free_port(),
                        'ws_port:=%d' % free_port()], module_master.env(), stdout=log,
                       stderr=subprocess.STDOUT)
        try:
            out = subprocess.run(LISTEN + ['--duration', '8', '--wait', '40', '--speech',
                                           'This is the CSSR4Africa speaker test.',
                                           '--speech-at', '3'] + list(LAUNCH_TOPICS),
                                 env=module_master.env(), stdout=subprocess.PIPE, timeout=120)
            got = json.loads(out.stdout)
        finally:
            code = kill_group(launch, timeout=30)
    return got, log_path.read_text(), code


def test_emulator_launch_runs(emulator_launch_run):
    """The emulator's topics appear with their types and publish; Ctrl-C ends the launch cleanly."""
    got, text, code = emulator_launch_run
    for topic, type_name in LAUNCH_TOPICS.items():
        assert topic in got, 'no %s\n%s' % (topic, text)
        assert got[topic]['type'] == type_name
        if topic != NS + '/audio':
            assert got[topic]['count'] > 10, (topic, got[topic]['count'])
    assert 'pepperEmulator: all 12 publishers up' in text, re.findall('pepperEmulator: all .*', text)     # 10 sensors' + the driver's /diagnostics + /tf
    assert code == 0


def test_emulator_launch_audio_bridge(emulator_launch_run):
    """In the same run: naoqiEndpoint -> naoqiAudio -> websocket -> naoqiAudioPublisher publishes
    the microphones, and /speech (emulator -> ALTextToSpeech on the endpoint) is heard in them."""
    got, text, code = emulator_launch_run
    audio = got[NS + '/audio']
    assert audio['count'] > 20, 'the audio bridge published %d buffers\n%s' % (audio['count'], text)
    spoke_at = got['_meta']['spoke_at']
    before = [max(r[1:]) for r in audio['rms'] if r[0] < spoke_at]
    after = [max(r[1:]) for r in audio['rms'] if r[0] > spoke_at]
    assert before and after and max(after) > 1.5 * max(before), 'speech not heard\n' + text


def test_emulator_launch_run_test_ends_the_launch(master, tmp_path):
    """run_test:=true with plain roslaunch: sensorTest runs against the emulator (simulator
    profile) and ends the whole launch when it finishes, without roslaunch's red "REQUIRED
    process has died!" banner."""
    out_dir = tmp_path / 'results'
    log_path = tmp_path / 'roslaunch.log'
    with open(log_path, 'w') as log:
        launch = spawn(['roslaunch', EMULATOR, 'profile:=simulator', 'run_test:=true',
                        'duration:=3', 'output_dir:=%s' % out_dir], master.env(), stdout=log,
                       stderr=subprocess.STDOUT)
        try:
            wait_until(lambda: launch.poll() is not None, 120,
                       lambda: 'the launch did not end with sensorTest\n' + log_path.read_text(), every=0.2)
        finally:
            kill_group(launch)
    text = log_path.read_text()
    assert 'sensorTest' in text and os.path.isdir(out_dir) and os.listdir(out_dir), text
    assert 'sensorTest: finished with exit code 0: ending the launch' in text, text
    assert 'REQUIRED process' not in text and 'has died' not in text, text
    assert 'Traceback' not in text, text


def wrapper(master, tmp_path, *args, timeout=150):
    """sensorTestLaunch as a CI job runs it: (exit code, output, seconds)."""
    t0 = time.monotonic()
    proc = spawn(script('sensorTestLaunch') + list(args), master.env(), stdout=subprocess.PIPE,
                 stderr=subprocess.STDOUT, text=True)
    try:
        out, _ = proc.communicate(timeout=timeout)
    finally:
        if proc.poll() is None:
            kill_group(proc)
    return proc.returncode, out, time.monotonic() - t0


def test_wrapper_exits_with_sensor_tests_code(master, tmp_path):
    """sensorTestLaunch gives scripts and CI sensorTest's exit code: 0 when every sensor passes,
    1 when one fails (a fault injected in the emulator)."""
    common = ['profile:=simulator', 'duration:=2', 'mode:=parallel']
    code, out, _ = wrapper(master, tmp_path, EMULATOR, *common,
                           'output_dir:=%s' % (tmp_path / 'ok'), 'sensors:=backSonar,laser')
    assert code == 0, out
    assert 'REQUIRED process' not in out, out
    code, out, _ = wrapper(master, tmp_path, 'pepperEmulator.launch', *common,
                           'output_dir:=%s' % (tmp_path / 'bad'), 'sensors:=backSonar,laser',
                           'faults:=laser:nan')
    assert code == 1, out
    with open(tmp_path / 'bad' / 'sensorTestResults.json') as f:
        sensors = json.load(f)['sensors']
    verdicts = {s['name']: s['verdict'] for s in sensors}
    assert verdicts == {'backSonar': 'PASS', 'laser': 'FAIL'}, [(s['name'], s['reasons']) for s in sensors]


def test_fault_example_fails_fast_with_the_reason(master, tmp_path):
    """A microphone fault with the default audio bridge: the emulator refuses it, and the launch
    ends at once with the emulator's reason (before: the launch sat there); the wrapper exits 2.
    With audio:=direct, as docs/emulator.md writes the example, the same faults run."""
    faults = 'laser:nan;microphone:silent_channel=rearRight'
    code, out, took = wrapper(master, tmp_path, EMULATOR, 'faults:=' + faults, 'duration:=2',
                              'sensors:=laser,microphone', 'output_dir:=%s' % (tmp_path / 'o'),
                              'naoqi_port:=%d' % free_port(), 'ws_port:=%d' % free_port())
    assert code == 2, out
    assert 'microphone faults need ~audio direct' in out, out
    assert 'sensorTestLaunch: error: the launch ended' in out and took < 60, (took, out)
    code, out, _ = wrapper(master, tmp_path, EMULATOR, 'audio:=direct', 'faults:=' + faults,
                           'duration:=2', 'sensors:=laser,microphone',
                           'output_dir:=%s' % (tmp_path / 'direct'))
    assert code == 1, out
    with open(tmp_path / 'direct' / 'sensorTestResults.json') as f:
        verdicts = {s['name']: s['verdict'] for s in json.load(f)['sensors']}
    assert verdicts == {'laser': 'FAIL', 'microphone': 'FAIL'}, verdicts


@pytest.mark.parametrize('path', [EMULATOR, ROBOT, SIMULATOR], ids=os.path.basename)
def test_every_launch_arg_is_documented_and_optional(path):
    """roslaunch --ros-args explains every argument; none is listed as Required (roslaunch lists
    an empty default as Required, hence the defaults auto / none)."""
    code, out, err = roslaunch('--ros-args', path)
    assert code == 0, err
    assert 'Optional Arguments:' in out and 'Required Arguments' not in out, out
    assert 'undocumented' not in out, out
