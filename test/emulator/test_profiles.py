"""Driver profiles in the expectations file (`drivers:`): a sensor block takes one with
`driver: name`; load(..., driver=name) takes one for every sensor it describes. Mistakes stop
the load with file:line and the fix, as every other key does."""
import os

import pytest

from pepper_interface_tests.plan import expectations, settings
from pepper_interface_tests.plan.textfile import ConfigError

SHIPPED = os.path.join(settings.package_dir(), 'config', 'sensorExpectations.yaml')

PROFILES = """drivers:
  mine:
    laser:
      layout: "my filter's 45 slots"
      ranges: 45
      boards: {right: [0, 14], front: [15, 29], left: [30, 44]}
      inf_is_no_return: false
robot:
  laser:
    driver: mine
    stuck_scans: 10
"""


def write(tmp_path, text):
    path = tmp_path / 'e.yaml'
    path.write_text(text)
    return str(path)


def test_a_sensor_takes_its_profile_and_overrides_it(tmp_path):
    laser = expectations.load(write(tmp_path, PROFILES), 'robot')['laser']
    assert (laser.driver, laser.ranges, laser.layout) == ('mine', 45, "my filter's 45 slots")
    assert laser.boards == (('right', 0, 14), ('front', 15, 29), ('left', 30, 44))
    assert laser.inf_is_no_return is False and laser.stuck_scans == 10
    # a sensor without a profile keeps the dataclass defaults
    assert expectations.load(write(tmp_path, PROFILES), 'simulator')['laser'].boards is None


def test_the_shipped_profiles():
    robot = expectations.load(SHIPPED, 'robot')['laser']
    assert robot.driver == 'naoqi_driver' and robot.blind_slots == ((15, 22), (38, 45))
    for name in ('cssr4africa_naoqi_driver', 'naoqi_driver2', 'yohatad_naoqi_driver2'):
        other = expectations.load(SHIPPED, 'robot', driver=name)['laser']
        assert other.driver == name and other.boards == robot.boards and other.ranges == 61
        assert other.rate == robot.rate           # the platform's own keys stay
    yohatad = expectations.load(SHIPPED, 'robot', driver='yohatad_naoqi_driver2')['laser']
    assert yohatad.inf_is_no_return and not yohatad.nan_is_no_return
    # a profile without a camera leaves the cameras as the platform says
    assert expectations.load(SHIPPED, 'robot', driver='naoqi_driver2')['frontCamera'].driver is None


@pytest.mark.parametrize('text, words, line', [
    (PROFILES.replace('driver: mine', 'driver: theirs'), 'robot.laser: unknown driver profile "theirs"', 10),
    (PROFILES.replace('{right: [0, 14], front: [15, 29], left: [30, 44]}',
                      '{right: [0, 14], front: [10, 29]}'), 'overlapping', 6),
    (PROFILES.replace('{right: [0, 14], front: [15, 29], left: [30, 44]}', '[[0, 14]]'),
     'not a mapping of names to [first, last] slot pairs', 6),
    (PROFILES.replace('      ranges: 45\n', '      ranges: 45\n      driver: mine\n'),
     'a driver profile cannot name another', 6),
    (PROFILES.replace('      ranges: 45\n', '      rangez: 45\n'), 'drivers.mine.laser: unknown key "rangez"', 5),
])
def test_mistakes_name_the_line_and_the_fix(tmp_path, text, words, line):
    with pytest.raises(ConfigError) as e:
        expectations.load(write(tmp_path, text), 'robot')
    assert words in str(e.value) and ':%d' % line in str(e.value), str(e.value)


def test_an_unknown_profile_asked_for_names_the_known_ones():
    with pytest.raises(ConfigError, match='naoqi_driver, cssr4africa_naoqi_driver'):
        expectations.load(SHIPPED, 'robot', driver='naoqi_driver3')

