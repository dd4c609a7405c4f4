"""The Pepper emulator on ROS 2 (a Pepper as naoqi_driver2 publishes it), optionally with
sensorTest against it: pepperEmulator.launch's names and arguments, on ROS 2.

  ros2 launch pepper_interface_tests pepperEmulator.launch.py
  ros2 launch pepper_interface_tests pepperEmulator.launch.py run_test:=true; echo $?
  ros2 launch pepper_interface_tests pepperEmulator.launch.py faults:="frontCamera:frozen;laser:nan" run_test:=true
  ros2 launch pepper_interface_tests pepperEmulator.launch.py audio:=bridge run_test:=true

With run_test:=true sensorTest starts once the emulator's publishers are up, and the launch
ends when sensorTest ends, with its verdict as exit status: 0 when every row passed, 1
otherwise (its exit code named in the launch's last line;
pepper_interface_tests/launch/ros2.py). The emulator ending with an error ends the launch
(exit 1), as required="true" on ROS 1. audio: direct (default: the emulated naoqi_driver2
publishes AudioBuffer on /audio), off, or bridge: naoqi_driver2 without microphones (as
naoqi_driver2 2.1.2 with no audio endpoint) and this package's audio bridge in their place
(naoqiEndpoint plays the robot's microphones, naoqiAudio captures them and sends them over a
websocket to naoqiAudioPublisher, which publishes /audio as audio_msg says). The bridge's token:
export PEPPER_AUDIO_TOKEN_FILE=<file holding it> before ros2 launch (never an argument).
All arguments with their meaning: ros2 launch pepper_interface_tests pepperEmulator.launch.py --show-args
"""
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, ExecuteProcess, OpaqueFunction, RegisterEventHandler
from launch_ros.actions import Node
from launch_ros.substitutions import ExecutableInPackage

from pepper_interface_tests.launch.ros2 import ends_launch, flag, required, start_when_up

PKG = 'pepper_interface_tests'
ARGS = [   # name, default, description: pepperEmulator.launch's, where ROS 2 has them
    ('profile', 'robot-stock', 'robot-stock (naoqi_driver2: ros-naoqi/naoqi_driver ported, AudioBuffer) | '
     'robot (the CSSR4Africa fork\'s streams) | simulator (awesomebytes Gazebo, sim time)'),
    ('head', 'stereo', 'robot profiles: stereo (Pepper 1.8 head) | xtion (Pepper 1.7 head)'),
    ('real_time_factor', '0.6', 'simulator: simulated seconds per wall second (/clock)'),
    ('condition', 'normal', 'normal | loaded | still | dark | resting'),
    ('network', 'none', 'none | wifi (a busy WiFi between robot and PC: holds of 0.30-0.45 s every 1.5-3.5 s)'),
    ('realsense', 'false', 'true: also publish the RealSense D435i topics (and sensorTest tests them)'),
    ('faults', 'none', 'none, or the faults to inject, e.g. frontCamera:frozen;laser:nan '
     '(ros2 run pepper_interface_tests pepperEmulator --list-faults)'),
    ('audio', 'direct', 'direct (the driver publishes /audio) | off | bridge (this package\'s audio bridge '
     'publishes /audio)'),
    ('audio_msg', 'AudioBuffer', 'audio bridge: AudioBuffer (naoqi_bridge_msgs, as naoqi_driver2) | '
     'AudioCustomMsg (as the ROS 1 bridge)'),
    ('naoqi_port', '9559', 'audio bridge: TCP port of the emulated NAOqi endpoint on 127.0.0.1'),
    ('ws_port', '9090', 'audio bridge: websocket port of naoqiAudioPublisher on 127.0.0.1'),
    ('silent_channel', 'none', 'audio bridge: a dead microphone channel of the NAOqi endpoint, or none'),
    ('camera_resolution', 'auto', 'QQVGA | QVGA | VGA | auto = the driver\'s boot_config.json'),
    ('rate_factor', '1.0', 'multiplies every publishing rate'),
    ('touch', 'auto', 'robot profiles: publish the touch events; auto = the driver\'s boot_config.json'),
    ('robot_id', 'AP990370B0000000', 'robot profiles: the serial number on /info; none: no info'),
    ('operator', 'false', 'true: an emulated operator touches each zone the guided check asks for'),
    ('run_test', 'false', 'true: also run sensorTest; the launch ends with its verdict (exit 0 / 1)'),
    ('mode', 'parallel', 'run_test: sensorTest mode, parallel | sequential'),
    ('duration', '10', 'run_test: seconds each sensor is listened to'),
    ('wait', '20', 'run_test: seconds allowed for each sensor\'s first message (the emulator starts '
     'alongside sensorTest)'),
    ('move', 'false', 'run_test: true: also the motion check (--move): the head yaws and the base turns; '
     'nobody is asked first, so keep the space around the robot clear'),
    ('output_dir', 'auto', 'run_test: results folder; auto = sensorTest\'s default'),
    ('sensors', 'auto', 'run_test: comma-separated sensors to test; auto = the input file decides'),
]


def _given(value, none=('none', 'auto', '')):
    return value not in none


def _actions(context):
    a = {name: context.launch_configurations[name] for name, _, _ in ARGS}
    bridge = a['audio'] == 'bridge'
    emulator_args = ['--profile', a['profile'], '--head', a['head'], '--condition', a['condition'],
                     '--network', a['network'],
                     '--realsense', a['realsense'], '--audio', 'off' if bridge else a['audio'],
                     '--rate-factor', a['rate_factor'], '--real-time-factor', a['real_time_factor'],
                     '--robot-id', a['robot_id'], '--operator', a['operator']]
    for name, option in (('faults', '--faults'), ('camera_resolution', '--camera-resolution'),
                         ('touch', '--touch')):
        if _given(a[name]):
            emulator_args += [option, a[name]]
    emulator = Node(package=PKG, executable='pepperEmulator', arguments=emulator_args, output='screen')
    actions = [emulator, RegisterEventHandler(required(emulator, 'pepperEmulator'))]
    if bridge:
        endpoint = ['--host', '127.0.0.1', '--port', a['naoqi_port'], '--network', a['network']]
        if _given(a['silent_channel']):
            endpoint += ['--silent-channel', a['silent_channel']]
        publisher = Node(package=PKG, executable='naoqiAudioPublisher', output='screen',
                         arguments=['--host', '127.0.0.1', '--port', a['ws_port'], '--topic', '/audio',
                                    '--message', a['audio_msg']])
        # naoqiEndpoint and naoqiAudio are no ROS nodes (launch_ros' Node would add --ros-args)
        actions += [ExecuteProcess(cmd=[ExecutableInPackage('naoqiEndpoint', PKG)] + endpoint, output='screen'),
                    publisher, RegisterEventHandler(required(publisher, 'naoqiAudioPublisher')),
                    ExecuteProcess(cmd=[ExecutableInPackage('naoqiAudio', PKG), '--ip', '127.0.0.1', '--port',
                                        a['naoqi_port'], '--ws', 'ws://127.0.0.1:%s' % a['ws_port']],
                                   output='screen')]
    if flag(a['run_test'], 'run_test'):
        test_args = ['--platform', 'simulator' if a['profile'] == 'simulator' else 'robot',
                     '--mode', a['mode'], '--duration', a['duration'], '--wait', a['wait'],
                     '--cameras', 'both' if flag(a['realsense'], 'realsense') else 'pepper']
        if flag(a['move'], 'move'):
            test_args += ['--move', '--yes']
        if _given(a['output_dir']):
            test_args += ['--output-dir', a['output_dir']]
        if _given(a['sensors']):
            test_args += ['--sensors', a['sensors']]
        sensor_test = Node(package=PKG, executable='sensorTest', arguments=test_args, output='screen')
        actions += [RegisterEventHandler(start_when_up(emulator, sensor_test)),
                    RegisterEventHandler(ends_launch(sensor_test, 'sensorTest'))]
    return actions


def generate_launch_description():
    return LaunchDescription([DeclareLaunchArgument(name, default_value=default, description=text)
                              for name, default, text in ARGS] + [OpaqueFunction(function=_actions)])
