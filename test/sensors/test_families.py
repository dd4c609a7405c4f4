"""Unit: the family registry (sensors/families.py) is the only table of families; every other
place that names families is derived from it or agrees with it, and no module outside it tells
families apart by a string test."""
import ast
import os

import pytest

from check_runs import ROBOT, judged
from codebase_files import PACKAGE, parse, source_files
from fake_pepper import JOINTS, imu, joints, laser, odometry, sonar
from pepper_interface_tests.plan import catalog, expectations
from pepper_interface_tests.results import PASS
from pepper_interface_tests.sensors import families
from pepper_interface_tests.sensors.base import Check


def test_every_catalog_sensor_names_a_registered_family():
    for sensor in catalog.SENSORS.values():
        assert sensor.family in families.FAMILIES, sensor


def test_expectations_know_exactly_the_registered_families():
    assert set(expectations.FAMILIES) == set(families.FAMILIES)


@pytest.mark.parametrize('name', sorted(families.FAMILIES))
def test_each_family_names_its_check_and_its_view(name):
    fam = families.FAMILIES[name]
    module = fam.check.split(':')[0]
    # the check module exists and defines the class (read, not imported: OpenCV is slow to load)
    tree = parse(os.path.join(PACKAGE, 'sensors', module + '.py'))
    classes = {n.name for n in tree.body if isinstance(n, ast.ClassDef)}
    assert fam.check.split(':')[1] in classes
    assert os.path.isfile(os.path.join(PACKAGE, 'outputs', 'report', 'views', fam.view + '.py'))


def test_a_check_class_resolves_lazily():
    cls = families.family('range').check_class()
    assert issubclass(cls, Check) and cls.__name__ == 'RangeCheck'


def test_an_unknown_family_is_named_with_the_known_ones():
    with pytest.raises(families.UnknownFamily) as e:
        families.family('bumpers')
    assert 'bumpers' in str(e.value) and 'range' in str(e.value)


def test_traits_say_what_the_string_tests_guessed():
    assert families.family('speech').traits.drives_itself and families.family('speech').traits.live_only
    assert families.family('camera').traits.images and families.family('depth').traits.images
    assert families.family('audio').traits.audio and families.family('audio').traits.records_media
    assert not families.family('laser').traits.records_media
    events = {'touch', 'health'}    # one message per change / a topic every node shares
    assert all(f.traits.periodic for f in families.FAMILIES.values()
               if not f.traits.drives_itself and f.name not in events)
    assert not any(families.family(n).traits.periodic for n in events)
    assert families.family('touch').traits.guided and families.family('health').traits.headline
    assert families.family('health').traits.shared_topic


def test_the_emulator_publishes_under_family_names():
    from pepper_interface_tests.emulator import faults, profiles, publishers
    assert set(faults.SENSOR_KINDS.values()) <= set(families.FAMILIES)
    for _takes, kinds in faults.FAULTS.values():
        # the robot's own conditions (robot:resting) are no family's: the pseudo-sensor `robot`
        assert kinds is None or set(kinds) <= set(families.FAMILIES) | {faults.ROBOT}, kinds
    assert set(publishers.FAMILY_PUBLISHERS) <= set(families.FAMILIES)
    spec = profiles.robot_profile(profiles.topics_file('robot'))
    for s in spec.sensors:
        assert s.family == catalog.SENSORS[s.name].family, s


FAMILY_WORDS = set(families.FAMILIES)


def family_string_tests(tree):
    """`x.family == 'speech'`, `family in ('camera', 'depth')` and the like: comparisons of a
    `family` name or attribute with family-name strings."""
    found = []
    for node in ast.walk(tree):
        if not isinstance(node, ast.Compare):
            continue
        sides = [node.left] + list(node.comparators)
        names = [s for s in sides if (isinstance(s, ast.Attribute) and s.attr == 'family')
                 or (isinstance(s, ast.Name) and s.id in ('family', 'fam'))
                 or (isinstance(s, ast.Call) and getattr(s.func, 'id', '') == 'family')]
        strings = [c.value for s in sides for c in ast.walk(s)
                   if isinstance(c, ast.Constant) and isinstance(c.value, str)]
        if names and FAMILY_WORDS & set(strings):
            found.append(node.lineno)
    return found


def test_the_string_test_finder_sees_one():
    tree = ast.parse("if run.sensor.family == 'speech': pass\nif family(r) in ('camera', 'x'): pass\n"
                     "if kind == 'speech': pass\n")
    assert family_string_tests(tree) == [1, 2]


def test_no_family_is_told_apart_by_a_string_test_outside_the_registry():
    offenders = []
    for rel, path in source_files():
        if rel in ('sensors/families.py',) or rel.startswith('emulator/'):
            continue        # the emulator builds its streams per family: its own table
        offenders += ['%s:%d' % (rel, line) for line in family_string_tests(parse(path))]
    assert not offenders, 'ask the family registry\'s traits instead: ' + ', '.join(offenders)


def test_the_checks_page_names_each_familys_check_module():
    """docs/checks.md points to each family's check, where its rules are stated."""
    import re

    from pepper_interface_tests.plan import settings
    with open(os.path.join(settings.package_dir(), 'docs', 'checks.md'), encoding='utf-8') as f:
        text = f.read()
    rows = dict(re.findall(r'^\| (\w+) \| [^|]+ \| `(sensors/\w+\.py)`', text, re.M))
    assert rows == {name: 'sensors/%s.py' % fam.check.split(':')[0] for name, fam in families.FAMILIES.items()}


@pytest.mark.parametrize('name, build, fields', [
    ('backSonar', sonar, ['Frame id', 'Field of view', 'Minimum range value', 'Maximum range value',
                          'Range value']),
    ('laser', laser, ['Frame id', 'Start angle of the scan', 'End angle of the scan',
                     'Angular distance between measurements', 'Time between measurements',
                     'Time between scans', 'Minimum range value', 'Maximum range value',
                     'Range data size']),
    ('jointState', joints, ['Header frame id', 'Number of joints'] + ['Joint'] * len(JOINTS)),
    ('odometry', odometry, ['Header', 'Child frame id', 'Pose', 'Twist']),
    ('imu', imu, ['Header', 'Orientation', 'Angular velocity', 'Linear acceleration']),
])
def test_good_messages_pass(tmp_path, name, build, fields):
    nominal = float(ROBOT[name].nominal)
    n = int(2.5 * nominal)
    r = judged(name, tmp_path, [build(i) for i in range(n)])
    assert r.verdict == PASS, r.reasons
    assert r.reasons == [] and r.messages == n
    assert r.rate_hz == pytest.approx(nominal) and r.stamp_rate_hz == pytest.approx(nominal)
    assert [k for k, _ in r.fields] == fields          # the spec's fields of the first message
    assert r.stats.delay_s.max == pytest.approx(0.01, abs=1e-3)
    assert r.received_type == catalog.SENSORS[name].msg_type
    assert r.notes, 'a summary of the values is expected'
