"""The ROS 2 launch files, started as users start them (`ros2 launch`, ros2cli and launch of the
tools overlay of tools/platform/ros2.sh): pepperEmulator.launch.py with run_test:=true ends
with sensorTest's verdict as its exit status (0 every row PASS, 1 with a fault), Ctrl-C during
a --move base turn leaves a zero twist last, and sensorTestLaunchRobot.launch.py names
naoqi_driver2 when it is not installed. Run by the ROS 2 tier (tools/ros2/tests.sh)."""
import json
import os
import signal
import subprocess
import sys

from motion_runs import GOAL, assert_stopped_safely
from ros2_runs import domain_env, launch, results
from rosmaster import kill_group, spawn, wait_until

HELPERS = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'helpers')
QUICK = ['camera_resolution:=QQVGA', 'mode:=parallel', 'duration:=3']


def run_launch(tmp_path, *args, timeout=180):
    """(exit status, output) of `ros2 launch pepper_interface_tests pepperEmulator.launch.py ARGS`."""
    log_path = tmp_path / 'launch.log'
    with open(str(log_path), 'w') as log:
        proc = spawn(launch('pepperEmulator.launch.py', *args), domain_env(), stdout=log,
                     stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL)
        try:
            code = proc.wait(timeout)
        finally:
            kill_group(proc)
    return code, log_path.read_text()


def test_the_emulator_launch_with_run_test_exits_0_with_every_row_passing(tmp_path):
    out = tmp_path / 'out'
    code, text = run_launch(tmp_path, 'run_test:=true', 'output_dir:=%s' % out,
                            'sensors:=tf,frontSonar,laser,imu,odometry,jointState,frontCamera,microphone',
                            *QUICK)
    assert code == 0, text[-5000:]
    _, rows = results(out)
    assert len(rows) == 8 and all(r['verdict'] == 'PASS' for r in rows.values()), \
        {n: (r['verdict'], r['reasons']) for n, r in rows.items()}
    assert rows['microphone']['topic'] == '/audio' and rows['tf']['values']['publishers'] == ['/naoqi_driver']
    for name in ('laser', 'imu', 'odometry', 'frontCamera', 'frontSonar'):    # placed by ROS 2's tf2
        frame = rows[name]['frame']
        assert frame and frame['judged'] > 0 and frame['placed'] == frame['judged'], (name, frame)
    assert 'Traceback' not in text, text[-5000:]


def test_the_emulator_launch_with_a_fault_exits_1_naming_sensor_tests_code(tmp_path):
    out = tmp_path / 'out'
    code, text = run_launch(tmp_path, 'run_test:=true', 'output_dir:=%s' % out, 'faults:=laser:nan',
                            'sensors:=frontSonar,laser', *QUICK)
    assert code == 1, text[-5000:]
    assert 'sensorTest exited with code 1 (a row did not pass); the launch exits 1' in text, text[-3000:]
    _, rows = results(out)
    assert {n: r['verdict'] for n, r in rows.items()} == {'frontSonar': 'PASS', 'laser': 'FAIL'}
    assert 'Traceback' not in text, text[-5000:]


def test_the_emulator_launch_with_the_audio_bridge_on_ros2_passes_its_microphones(tmp_path):
    """audio:=bridge: the emulated naoqi_driver2 without microphones, naoqiEndpoint ->
    naoqiAudio -> websocket -> naoqiAudioPublisher on rclpy, which publishes naoqi_driver2's
    AudioBuffer on /audio; sensorTest on ROS 2 hears it."""
    out = tmp_path / 'out'
    code, text = run_launch(tmp_path, 'run_test:=true', 'audio:=bridge', 'output_dir:=%s' % out,
                            'sensors:=microphone,laser', *QUICK)
    assert code == 0, text[-5000:]
    assert 'publishing /audio (naoqi_bridge_msgs/AudioBuffer)' in text, text[-5000:]
    _, rows = results(out)
    mic = rows['microphone']
    assert mic['verdict'] == 'PASS' and mic['messages'] > 10 and mic['received_type'].endswith('AudioBuffer'), mic
    assert 'Traceback' not in text, text[-5000:]


def test_a_bad_emulator_argument_ends_the_launch_naming_the_emulator(tmp_path):
    code, text = run_launch(tmp_path, 'run_test:=true', 'faults:=laser:no_such_fault', *QUICK, timeout=90)
    assert code == 1, text[-3000:]
    assert 'pepperEmulator exited with code 2' in text, text[-3000:]
    assert 'Traceback' not in text, text[-5000:]


def test_ctrl_c_to_the_launch_during_a_base_turn_leaves_a_zero_twist_last(tmp_path):
    env = domain_env()
    received = tmp_path / 'received.jsonl'
    rec_log = tmp_path / 'recorder.log'
    with open(str(rec_log), 'w') as log:
        recorder = spawn([sys.executable, os.path.join(HELPERS, 'ros2_motion_recorder.py'), str(received)],
                         env, stdout=log, stderr=subprocess.STDOUT)
    log_path = tmp_path / 'launch.log'
    proc = None
    try:
        wait_until(lambda: 'recorder up' in rec_log.read_text(), 40, rec_log.read_text)
        with open(str(log_path), 'w') as log:
            proc = spawn(launch('pepperEmulator.launch.py', 'run_test:=true', 'move:=true', 'condition:=still',
                                'audio:=off', 'sensors:=jointState,odometry,imu,laser', 'wait:=8',
                                'output_dir:=%s' % (tmp_path / 'out'), *QUICK),
                         env, stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL)

        def rows():
            if not received.exists():
                return []
            return [json.loads(ln) for ln in received.read_text().splitlines() if ln.strip()]
        wait_until(lambda: any(r['topic'] == GOAL for r in rows()), 120, lambda: log_path.read_text()[-3000:])
        os.killpg(proc.pid, signal.SIGINT)         # Ctrl-C in the terminal of `ros2 launch`
        code = proc.wait(40)
        text = log_path.read_text()
        assert code == 1, text[-3000:]      # an interrupted run is no pass
        assert 'sensorTest exited with code 130 (interrupted)' in text, text[-3000:]
        wait_until(lambda: rows() and rows()[-1]['topic'] != GOAL, 5, lambda: rows()[-3:])
        assert_stopped_safely(rows(), 0.5)
    finally:
        if proc is not None:
            kill_group(proc)
        kill_group(recorder)
    data, result_rows = results(tmp_path / 'out')
    assert data['interrupted'] and result_rows['motion']['verdict'] == 'INTERRUPTED'


def test_the_robot_launch_without_naoqi_driver2_names_it_and_the_fix(tmp_path):
    p = subprocess.run(launch('sensorTestLaunchRobot.launch.py', 'robot_ip:=127.0.0.1'), env=domain_env(),
                       capture_output=True, text=True, timeout=60, stdin=subprocess.DEVNULL)
    text = p.stdout + p.stderr
    assert p.returncode == 1, text
    assert 'needs the ROS 2 package naoqi_driver, which is not installed; fix: build ros-naoqi/naoqi_driver2' \
        in text, text
    assert 'Traceback' not in text, text


def test_the_launch_files_declare_the_ros1_arguments(tmp_path):
    """`ros2 launch ... --show-args` lists each argument of the ROS 1 launch file of the same
    name that has a meaning on ROS 2 (roscore_ip and namespace have none: no master, and
    naoqi_driver2 publishes at the root)."""
    import re
    here = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'launch')
    for name, left_out in (('pepperEmulator', set()), ('sensorTestLaunchRobot', {'roscore_ip', 'namespace'})):
        with open(os.path.join(here, name + '.launch')) as f:
            ros1 = set(re.findall(r'<arg name="([a-z_]+)" default=', f.read()))
        p = subprocess.run(launch(name + '.launch.py', '--show-args'), env=domain_env(), capture_output=True,
                           text=True, timeout=60)
        assert p.returncode == 0, p.stdout + p.stderr
        ros2 = set(re.findall(r"^    '([a-z_]+)':", p.stdout, re.M))
        assert ros1 - left_out <= ros2, (name, sorted(ros1 - left_out - ros2))


# A stand-in for naoqi_driver2's package, in a prefix of its own: its launch file declares the
# arguments of ros-naoqi/naoqi_driver2 launch/naoqi_driver.launch.py (nao_ip, nao_port,
# username, password, network_interface, qi_listen_url, namespace) and logs the values it was given.
FAKE_DRIVER_LAUNCH = '''
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, LogInfo
from launch.substitutions import LaunchConfiguration

NAMES = ('nao_ip', 'nao_port', 'username', 'password', 'network_interface', 'qi_listen_url', 'namespace')


def generate_launch_description():
    return LaunchDescription([DeclareLaunchArgument(n, default_value='default') for n in NAMES] + [
        LogInfo(msg=['fake naoqi_driver2: '] + sum([[n, '=', LaunchConfiguration(n), ' '] for n in NAMES], []))])
'''


def test_the_robot_launch_includes_naoqi_driver2s_launch_with_the_robots_address(tmp_path):
    prefix = tmp_path / 'prefix'
    (prefix / 'share' / 'naoqi_driver' / 'launch').mkdir(parents=True)
    (prefix / 'share' / 'naoqi_driver' / 'launch' / 'naoqi_driver.launch.py').write_text(FAKE_DRIVER_LAUNCH)
    (prefix / 'share' / 'ament_index' / 'resource_index' / 'packages').mkdir(parents=True)
    (prefix / 'share' / 'ament_index' / 'resource_index' / 'packages' / 'naoqi_driver').write_text('')
    env = domain_env(AMENT_PREFIX_PATH=str(prefix) + os.pathsep + os.environ.get('AMENT_PREFIX_PATH', ''))
    p = subprocess.run(launch('sensorTestLaunchRobot.launch.py', 'robot_ip:=10.0.0.5', 'robot_port:=9503',
                              'network_interface:=wlan0', 'password:=s3cret', 'run_test:=false',
                              'qi_listen_url:=tcp://10.0.0.2:0'),
                       env=env, capture_output=True, text=True, timeout=60, stdin=subprocess.DEVNULL)
    text = p.stdout + p.stderr
    assert p.returncode == 0, text
    assert ('fake naoqi_driver2: nao_ip=10.0.0.5 nao_port=9503 username=nao password=s3cret '
            'network_interface=wlan0 qi_listen_url=tcp://10.0.0.2:0 namespace=default') in text, text
    assert 'naoqiAudio' not in text, text       # driver_audio defaults to true: no second /audio
