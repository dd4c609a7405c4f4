"""The robot's identity from naoqi_driver's info message (sources/identity.py): parsed as the
driver joins it (src/converters/info.cpp:83-88), the BodyId as the identity, and every way it can
be unknown said with its reason. read_live against a real master: tests/outputs/test_baseline_robot.py."""
from pepper_interface_tests.emulator import info
from pepper_interface_tests.sources import identity
from pepper_interface_tests.sources.naoqi_msgs import STRING_STAMPED_TYPE, known_class

# what the real naoqi_driver (ros-naoqi aed1b87) sent on /naoqi_driver/info against the fake NAOqi
REAL = ('RobotConfig/Head/FullHeadId: AP990495A0000000 ; Device/DeviceList/ChestBoard/BodyId: AP990370B0000000 ; '
        'RobotConfig/Body/Type: juliette ; RobotConfig/Body/BaseVersion: 1.8a ; '
        'RobotConfig/Body/Device/LeftArm/Version: 1.8a ; RobotConfig/Body/Device/RightArm/Version: 1.8a ; '
        'RobotConfig/Body/Device/Hand/Left/Version: 1.8a ; RobotConfig/Body/Version: 1.8a ; '
        'RobotConfig/Body/SoftwareRequirement: 2.5 ; RobotConfig/Body/Device/Legs/Version: 1.8a ; '
        'Device/DeviceList/BatteryFuelGauge/SerialNumber: FAKE0001 ; '
        'Device/DeviceList/BatteryFuelGauge/FirmwareVersion: 1.0 ; RobotConfig/Body/Device/Platform/Version: 1.8a ; '
        'RobotConfig/Body/Device/Brakes/Version: 1.8a ; RobotConfig/Body/Device/Wheel/Version: 1.8a')


def test_the_real_drivers_message_names_the_robot():
    got = identity.from_text(REAL, '/naoqi_driver/info')
    assert got.body_id == 'AP990370B0000000' and not got.why
    assert got.to_dict() == {'body_id': 'AP990370B0000000', 'topic': '/naoqi_driver/info',
                             'head_id': 'AP990495A0000000', 'body_type': 'juliette', 'base_version': '1.8a'}


def test_the_emulator_says_it_as_the_real_driver_does():
    assert info.info_text(info.identity_values('stereo')) == REAL
    other = identity.from_text(info.info_text(info.identity_values('xtion', 'AP990370B0000001')), '/x/info')
    assert other.body_id == 'AP990370B0000001' and other.values[identity.BASE_VERSION] == '1.7'


def test_a_message_without_a_body_id_leaves_the_robot_unknown():
    got = identity.from_text('RobotConfig/Body/Type: juliette ; garbage ; : nokey', '/naoqi_driver/info')
    assert got.body_id == ''
    assert got.to_dict() == {'unknown': '/naoqi_driver/info names no Device/DeviceList/ChestBoard/BodyId'}
    assert identity.parse_info('') == {}


def test_the_info_topic_is_found_in_any_namespace_by_its_type():
    published = [['/pepper/info', STRING_STAMPED_TYPE], ['/naoqi_driver/info_extra', STRING_STAMPED_TYPE],
                 ['/info', 'std_msgs/String'], ['/rosout', 'rosgraph_msgs/Log']]
    assert identity.info_topic(published) == '/pepper/info'
    assert identity.info_topic(published[1:]) is None


def test_the_message_class_has_the_real_packages_md5sum():
    # rosmsg md5 naoqi_bridge_msgs/StringStamped of ros-naoqi/naoqi_bridge_msgs (Header header, string data)
    assert known_class(STRING_STAMPED_TYPE)._md5sum == 'c99a9440709e4d4a9716d55b8270d5e7'


def test_a_serial_number_is_checked():
    assert info.check_body_id(' AP990370B0000001 ') == 'AP990370B0000001'
    assert info.check_body_id('none') == ''
    for bad in ('', 'a ; b', 'x' * 65):
        try:
            info.check_body_id(bad)
        except Exception as e:
            assert 'robot serial number' in str(e)
        else:
            raise AssertionError(bad)
