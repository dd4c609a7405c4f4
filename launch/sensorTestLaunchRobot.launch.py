"""sensorTest on a physical Pepper on ROS 2: naoqi_driver2, the audio bridge when asked for, and
the test: sensorTestLaunchRobot.launch's names and arguments, on ROS 2.

  ros2 launch pepper_interface_tests sensorTestLaunchRobot.launch.py robot_ip:=<ip> \\
      network_interface:=<interface>; echo $?

naoqi_driver2's own launch (ros-naoqi/naoqi_driver2 launch/naoqi_driver.launch.py, package
naoqi_driver) is included with nao_ip, nao_port, username, password, network_interface and
qi_listen_url when naoqi_driver:=true; the launch stops at once, naming the package, when it is
not installed.
naoqi_driver:=false when the driver already runs (or runs elsewhere).
The microphones: naoqi_driver2 publishes /audio itself (AudioBuffer) when its audio works,
which needs the robot to reach back into this machine (NAT, Docker or a wrong interface stop it;
naoqi_driver2 2.1.2 turns audio off without an endpoint). driver_audio:=false starts this
package's bridge instead (its capture side connects out from the robot: naoqiAudio on this
machine through libqi, naoqiAudioPublisher publishing /audio as audio_msg says); turn the
driver's own audio off then (its boot_config.json), never two publishers on /audio. The bridge's
token: export PEPPER_AUDIO_TOKEN_FILE=<file holding it> before ros2 launch.
With run_test:=true the launch ends when sensorTest ends, with its verdict as exit status (0:
every row passed, 1: not; pepper_interface_tests/launch/ros2.py); run_test:=false starts the
drivers only (then: ros2 run pepper_interface_tests sensorTest).
All arguments with their meaning: ros2 launch pepper_interface_tests sensorTestLaunchRobot.launch.py --show-args
"""
from launch import LaunchDescription
from launch.actions import (
    DeclareLaunchArgument,
    ExecuteProcess,
    IncludeLaunchDescription,
    OpaqueFunction,
    RegisterEventHandler,
)
from launch.launch_description_sources import PythonLaunchDescriptionSource
from launch_ros.actions import Node
from launch_ros.substitutions import ExecutableInPackage

from pepper_interface_tests.launch.ros2 import ends_launch, flag, require_package

PKG = 'pepper_interface_tests'
ARGS = [
    ('move', 'false', 'true: also the motion check (--move): the head yaws and the base turns by small '
     'known amounts; nobody is asked first, so keep the space around the robot clear'),
    ('robot_ip', '172.29.111.230', 'the robot\'s IP address (naoqi_driver2\'s nao_ip)'),
    ('robot_port', '9559', 'the robot\'s NAOqi port (nao_port)'),
    ('username', 'nao', 'naoqi_driver2: the robot\'s user (NAOqi 2.9)'),
    ('password', 'no_password', 'naoqi_driver2: its password (NAOqi 2.9)'),
    ('network_interface', 'eth0', 'naoqi_driver2: the network interface of this machine that reaches the robot'),
    ('qi_listen_url', 'tcp://0.0.0.0:0', 'naoqi_driver2: where its session listens for NAOqi to call its audio '
     'back (an address of this machine the robot reaches; naoqi_driver2\'s own default)'),
    ('naoqi_driver', 'true', 'start naoqi_driver2; false when it already runs (or runs elsewhere)'),
    ('driver_audio', 'true', 'true: naoqi_driver2 publishes /audio; false: this package\'s bridge does'),
    ('audio', 'auto', 'start this package\'s audio bridge (naoqiAudio + naoqiAudioPublisher); auto = not driver_audio'),
    ('audio_msg', 'AudioBuffer', 'audio bridge: AudioBuffer (as naoqi_driver2) | AudioCustomMsg (as the ROS 1 bridge)'),
    ('ws_port', '9090', 'audio bridge: websocket port of naoqiAudioPublisher on 127.0.0.1'),
    ('cameras', 'auto', 'sensorTest --cameras: pepper | realsense | both; auto = the input file decides'),
    ('run_test', 'true', 'run sensorTest; the launch ends with its verdict (exit 0 / 1); false: the drivers only'),
    ('mode', 'auto', 'sensorTest mode: sequential | parallel; auto = the configuration file decides'),
    ('duration', 'auto', 'seconds each sensor is listened to; auto = 10 s'),
    ('output_dir', 'auto', 'results folder; auto = sensorTest\'s default'),
]
DRIVER_FIX = ('build ros-naoqi/naoqi_driver2 in your workspace (or apt install ros-humble-naoqi-driver); '
              'or pass naoqi_driver:=false when the driver already runs')


def _actions(context):
    a = {name: context.launch_configurations[name] for name, _, _ in ARGS}
    actions = []
    if flag(a['naoqi_driver'], 'naoqi_driver'):
        require_package('naoqi_driver', 'sensorTestLaunchRobot.launch.py', DRIVER_FIX)
        from ament_index_python.packages import get_package_share_directory
        driver = get_package_share_directory('naoqi_driver') + '/launch/naoqi_driver.launch.py'
        actions.append(IncludeLaunchDescription(PythonLaunchDescriptionSource(driver), launch_arguments={
            'nao_ip': a['robot_ip'], 'nao_port': a['robot_port'], 'username': a['username'],
            'password': a['password'], 'network_interface': a['network_interface'],
            'qi_listen_url': a['qi_listen_url']}.items()))
    bridge = (not flag(a['driver_audio'], 'driver_audio')) if a['audio'] == 'auto' else flag(a['audio'], 'audio')
    if bridge:
        actions += [
            Node(package=PKG, executable='naoqiAudioPublisher', output='screen',
                 arguments=['--host', '127.0.0.1', '--port', a['ws_port'], '--topic', '/audio',
                            '--message', a['audio_msg']]),
            # naoqiAudio is no ROS node (launch_ros' Node would add --ros-args)
            ExecuteProcess(cmd=[ExecutableInPackage('naoqiAudio', PKG), '--ip', a['robot_ip'], '--port',
                                a['robot_port'], '--ws', 'ws://127.0.0.1:%s' % a['ws_port']], output='screen')]
    if flag(a['run_test'], 'run_test'):
        test_args = ['--platform', 'robot']
        for name in ('cameras', 'mode', 'duration', 'output_dir'):
            if a[name] != 'auto':
                test_args += ['--' + name.replace('_', '-'), a[name]]
        if flag(a['move'], 'move'):
            test_args += ['--move', '--yes']
        sensor_test = Node(package=PKG, executable='sensorTest', arguments=test_args, output='screen')
        actions += [sensor_test, RegisterEventHandler(ends_launch(sensor_test, 'sensorTest'))]
    return actions


def generate_launch_description():
    return LaunchDescription([DeclareLaunchArgument(name, default_value=default, description=text)
                              for name, default, text in ARGS] + [OpaqueFunction(function=_actions)])
