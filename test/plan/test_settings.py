"""Configuration parsing: the configuration, input, topics and expectations files -> TestPlan.

Real files in a temporary folder; no ROS needed. Every error must name the file and line, what
was found and the valid choices (the `fix`).
"""
import dataclasses
import os

import pytest
import yaml

from pepper_interface_tests import cli
from pepper_interface_tests.plan import catalog, declaration, options, settings
from pepper_interface_tests.plan.settings import ConfigError, Options, load_plan
from plan_files import Files, error_of, topics_text, write

PKG = settings.package_dir()
SHIPPED_INPUT = os.path.join(PKG, 'config', 'sensorTestInput.ini')
SHIPPED_EXPECT = os.path.join(PKG, 'config', 'sensorExpectations.yaml')
PEPPER_TOPICS = os.path.join(PKG, 'data', 'pepperTopics.dat')
SIM_TOPICS = os.path.join(PKG, 'data', 'simulatorTopics.dat')

ALL = [n for n, s in catalog.SENSORS.items() if not s.opt_in]   # opt-in rows (motion: --move) aside


@pytest.fixture
def files(tmp_path):
    return Files(tmp_path)

# Every spelling the original package's files use (reference: original-sensorTest.md) -> the
# canonical (input file) name.
ORIGINAL_SPELLINGS = {
    # input file
    'backSonar': 'backSonar', 'frontSonar': 'frontSonar', 'bottomCamera': 'bottomCamera',
    'frontCamera': 'frontCamera', 'realsenseRGBCamera': 'realsenseRGBCamera',
    'realsenseDepthCamera': 'realsenseDepthCamera', 'depthCamera': 'depthCamera',
    'stereoCamera': 'stereoCamera', 'laser': 'laser', 'microphone': 'microphone',
    'jointState': 'jointState', 'odometry': 'odometry', 'imu': 'imu', 'speech': 'speech',
    # robot topics file
    'BackSonar': 'backSonar', 'FrontSonar': 'frontSonar', 'FrontCamera': 'frontCamera',
    'BottomCamera': 'bottomCamera', 'DepthCamera': 'depthCamera', 'StereoCamera': 'stereoCamera',
    'RealSenseCameraRGB': 'realsenseRGBCamera', 'RealSenseCameraDepth': 'realsenseDepthCamera',
    'Laser': 'laser', 'Microphone': 'microphone', 'JointState': 'jointState',
    'Odometry': 'odometry', 'IMU': 'imu', 'Speech': 'speech',
    # simulator topics file
    'laserSensor': 'laser',
}
CASE_VARIANTS = (str, str.lower, str.upper, str.swapcase)


# ------------------------------------------------------------------ helpers

def plan_names(plan):
    return [s.name for s in plan.sensors]


def enabled_in_file(path):
    """The enabled sensors of an input file, read here independently of settings.py."""
    out = []
    for raw in open(path, encoding='utf-8'):
        parts = raw.split('#')[0].split()
        if len(parts) == 2 and parts[1].lower() == 'true':
            out.append(parts[0])
    return out


# ------------------------------------------------------------------ the shipped files

def test_shipped_files_give_the_input_file_order():
    plan = load_plan(Options())
    assert plan.platform == 'robot' and plan.mode == 'sequential'
    assert plan_names(plan) == [catalog.canonical(n) for n in enabled_in_file(SHIPPED_INPUT)]
    assert plan.files['topics'] == os.path.abspath(PEPPER_TOPICS)
    assert all(s.topic and s.topic.startswith('/') for s in plan.sensors)


def test_shipped_robot_topics_file_maps_every_sensor():
    topics = settings.read_topics(PEPPER_TOPICS)
    assert set(topics) == set(ALL)
    assert topics['laser'] == '/naoqi_driver/laser'
    assert topics['realsenseRGBCamera'] == '/camera/color/image_raw'
    assert topics['backSonar'] == '/naoqi_driver/sonar/back'


def test_shipped_simulator_topics_file_matches_despite_its_spellings():
    """The original skipped every simulator test: laserSensor never matched laser."""
    topics = settings.read_topics(SIM_TOPICS)
    assert topics['laser'] == '/pepper/laser_2'
    assert topics['backSonar'] == '/pepper/sonar_back'
    plan = load_plan(Options(platform='simulator', sensors=tuple(ALL)))
    active = {s.name: s.topic for s in plan.sensors if s.skip_reason is None}
    assert active['laser'] == '/pepper/laser_2'
    assert active['odometry'] == '/pepper/odom'


def test_shipped_expectations_are_consistent():
    data = yaml.safe_load(open(SHIPPED_EXPECT))
    for platform in ('robot', 'simulator'):
        for name, values in data[platform].items():
            assert catalog.canonical(name) == name, name
            if 'rate' in values:
                lo, hi = values['rate']
                assert 0 < lo < hi, (platform, name)
                if 'nominal' in values:
                    assert lo <= values['nominal'] <= hi, (platform, name)
    for name in data['simulator']:
        assert catalog.SENSORS[name].simulator, 'simulator expectations for %s, which it lacks' % name


# ------------------------------------------------------------------ every spelling, all three files

@pytest.mark.parametrize('spelling', sorted(ORIGINAL_SPELLINGS))
def test_every_original_spelling_is_known(spelling):
    for variant in CASE_VARIANTS:
        assert catalog.canonical(variant(spelling)) == ORIGINAL_SPELLINGS[spelling]
    assert catalog.canonical('  %s ' % spelling) == ORIGINAL_SPELLINGS[spelling]


@pytest.mark.parametrize('spelling', sorted(ORIGINAL_SPELLINGS))
def test_every_spelling_works_in_all_three_files(files, spelling):
    name = ORIGINAL_SPELLINGS[spelling]
    for i, variant in enumerate(CASE_VARIANTS):
        key = variant(spelling)
        write(files.input, '%s true\n' % key)
        write(files.topics, '%s /spelled/%d\n' % (key, i))
        write(files.expectations, 'defaults:\n  min_messages: 3\nrobot:\n  %s:\n    nominal: %d\n'
              % (key, 40 + i))
        plan = load_plan(files.options())      # the input file decides: the cameras too
        assert plan_names(plan) == [name], key
        assert plan.sensors[0].topic == '/spelled/%d' % i, key
        assert plan.sensors[0].expect.nominal == 40 + i, key
        assert plan.sensors[0].expect.min_messages == 3


def test_unknown_spelling_is_not_guessed():
    for wrong in ('sonar', 'laser2', 'camera', '', 'Head'):
        assert catalog.canonical(wrong) is None


# ------------------------------------------------------------------ malformed lines

def test_comments_blank_lines_and_case_in_input(files):
    write(files.input, '# a comment line\n\n   \nLASER   TRUE   # trailing comment\n'
                       '  # indented comment\nbackSonar false\nImu True\n')
    assert plan_names(load_plan(files.options())) == ['laser', 'imu']


@pytest.mark.parametrize('which, text, line', [
    ('config', 'platform robot\nmode\n', 2),
    ('input', 'laser true\n\nbackSonar\n', 3),
    ('topics', 'Laser /scan\nBackSonar   \n', 2),
])
def test_key_without_value(files, which, text, line):
    path = write(getattr(files, which), text)
    e = error_of(files.options())
    assert (e.path, e.line) == (path, line)
    assert str(e).startswith('%s:%d: ' % (path, line))
    assert 'no value' in e.message and e.fix


def test_unknown_configuration_key(files):
    write(files.config, 'platform robot\nspeed fast\n')
    e = error_of(files.options())
    assert (e.path, e.line) == (files.config, 2)
    assert '"speed"' in e.message
    for key in ('platform', 'robotTopics', 'simulatorTopics', 'mode'):
        assert key in e.fix


def test_unknown_sensor_in_input(files):
    write(files.input, 'laser true\nsonarLeft true\n')
    e = error_of(files.options())
    assert (e.path, e.line) == (files.input, 2)
    assert '"sonarLeft"' in e.message
    for name in ALL:
        assert name in e.fix


def test_unknown_key_in_topics_file_but_actuators_ignored(files):
    write(files.topics, topics_text() + 'Head /head\nWheels /cmd_vel\nLArm /larm\n')
    load_plan(files.options())       # actuator keys are ignored
    write(files.topics, topics_text() + 'Tail /tail\n')
    e = error_of(files.options())
    assert (e.path, e.line) == (files.topics, len(ALL) + 1)
    assert '"Tail"' in e.message and 'Wheels' in e.fix and 'backSonar' in e.fix


@pytest.mark.parametrize('value', ['naoqi_driver/laser', '/a /b'])
def test_topic_value_must_be_one_absolute_name(files, value):
    write(files.topics, 'Laser %s\n' % value)
    write(files.input, 'laser true\n')
    e = error_of(files.options())
    assert (e.path, e.line) == (files.topics, 1)
    assert value in e.message and 'Laser /' in e.fix


@pytest.mark.parametrize('value', ['maybe', 'ture', '2', 'enabled'])
def test_bad_true_false(files, value):
    write(files.input, 'laser true\nimu %s\n' % value)
    e = error_of(files.options())
    assert (e.path, e.line) == (files.input, 2)
    assert value in e.message and 'true or false' in e.fix


@pytest.mark.parametrize('word, value', [('true', True), ('FALSE', False), ('Yes', True),
                                         ('off', False), ('1', True), ('0', False)])
def test_true_false_words(word, value):
    assert settings.parse_bool(word) is value


@pytest.mark.parametrize('key, value, valid', [
    ('mode', 'diagonal', ('sequential', 'parallel')),
    ('platform', 'gazebo', ('robot', 'simulator')),
])
def test_bad_mode_or_platform_in_configuration(files, key, value, valid):
    write(files.config, '# header\nrobotTopics topics.dat\nsimulatorTopics sim.dat\n%s %s\n' % (key, value))
    e = error_of(files.options())
    assert (e.path, e.line) == (files.config, 4)
    assert value in e.message
    for v in valid:
        assert v in e.fix


def test_configuration_values_are_case_insensitive(files):
    write(files.config, 'PLATFORM Robot\nMODE Parallel\nROBOTTOPICS topics.dat\n')
    plan = load_plan(files.options())
    assert (plan.platform, plan.mode) == ('robot', 'parallel')


@pytest.mark.parametrize('option, value', [('mode', 'diagonal'), ('platform', 'gazebo'),
                                           ('cameras', 'kinect'), ('mic_mode', 'stereo')])
def test_bad_option_values_name_the_choices(files, option, value):
    e = error_of(files.options(**{option: value}))
    assert value in e.message and e.fix.startswith('use one of: ')


def test_missing_platform(files):
    write(files.config, 'mode parallel\n')
    e = error_of(files.options())
    assert e.path == files.config and 'platform' in e.message and '--platform' in e.fix
    plan = load_plan(files.options(platform='Simulator', topics=files.sim))
    assert plan.platform == 'simulator' and plan.mode == 'parallel'


def test_duplicate_sensor_including_other_spelling(files):
    write(files.input, 'laser true\nimu true\nLaser false\n')
    e = error_of(files.options())
    assert (e.path, e.line) == (files.input, 3)
    assert 'twice' in e.message and 'line 1' in e.message


@pytest.mark.parametrize('which', ['config', 'input', 'topics', 'expectations'])
def test_missing_file(files, tmp_path, which):
    missing = str(tmp_path / 'nowhere' / 'missing.file')
    e = error_of(files.options(**{which: missing}))
    assert e.path == missing and 'not found' in e.message and e.fix


def test_topics_file_named_by_configuration_missing(files):
    write(files.config, 'platform robot\nrobotTopics other.dat\n')
    e = error_of(files.options())
    assert e.path == os.path.join(files.dir, 'other.dat') and 'not found' in e.message


@pytest.mark.parametrize('which', ['config', 'input', 'topics'])
def test_unreadable_file_a_directory(files, tmp_path, which):
    folder = tmp_path / 'a_folder.ini'
    folder.mkdir()
    e = error_of(files.options(**{which: str(folder)}))
    assert e.path == str(folder) and 'cannot read' in e.message and 'permissions' in e.fix


def test_unreadable_file_permissions(files):
    if os.geteuid() == 0:
        pytest.skip('running as root: chmod 000 does not stop root from reading '
                    '(covered by the directory-in-place-of-a-file case)')
    os.chmod(files.input, 0)
    try:
        e = error_of(files.options())
    finally:
        os.chmod(files.input, 0o644)
    assert e.path == files.input and 'cannot read' in e.message


def test_file_that_is_not_text(files):
    with open(files.input, 'wb') as f:
        f.write(b'laser \xff\xfe\x00true\n')
    e = error_of(files.options())
    assert e.path == files.input and 'cannot read' in e.message


@pytest.mark.parametrize('value', ['abc', '0', '-3', 'nan', 'inf', '', None])
def test_bad_duration_and_wait(value):
    for what in ('duration', 'wait'):
        with pytest.raises(ConfigError) as info:
            settings.positive_seconds(value, what)
        assert what in info.value.message and 'greater than 0' in info.value.fix


def test_bad_duration_in_options_and_on_the_command_line(files):
    e = error_of(files.options(duration=0))
    assert 'duration' in e.message
    with pytest.raises(ConfigError) as info:
        options.from_args(cli.build_parser().parse_args(['--duration', 'ten']))
    assert '--duration' in info.value.message and '"ten"' in info.value.message
    assert load_plan(files.options(duration=2.5, wait=1)).duration == 2.5


def test_bad_expectations_yaml_gives_the_line(files):
    write(files.expectations, 'defaults:\n  min_messages: 3\nrobot:\n  laser: [unclosed\n')
    e = error_of(files.options())
    assert e.path == files.expectations and e.line in (4, 5) and 'YAML' in e.fix


def test_unknown_sensor_in_expectations(files):
    write(files.expectations, 'robot:\n  lidar:\n    rate: [1, 2]\n')
    e = error_of(files.options())
    assert (e.path, e.line) == (files.expectations, 2)
    assert '"lidar"' in e.message and 'laser' in e.fix


def test_expectations_not_a_mapping(files):
    write(files.expectations, '- a\n- b\n')
    e = error_of(files.options())
    assert e.path == files.expectations and 'mapping' in e.message


# ------------------------------------------------------------------ --sensors, cameras, platform

def test_sensors_option_chooses_subset_and_order(files):
    write(files.input, 'laser true\nimu false\nbackSonar true\n')
    plan = load_plan(files.options(sensors=('IMU', 'Laser', 'odom', 'laser')))
    assert plan_names(plan) == ['imu', 'laser', 'odometry']   # its order; duplicates once; disabled ok


def test_sensors_option_unknown_name(files):
    e = error_of(files.options(sensors=('laser', 'periscope')))
    assert '"periscope"' in e.message and '--sensors' in e.message and 'frontSonar' in e.fix


def test_input_file_order_is_execution_order(files):
    order = ['odometry', 'laser', 'backSonar', 'imu', 'jointState']
    write(files.input, ''.join('%s true\n' % n for n in order) + 'speech false\n')
    assert plan_names(load_plan(files.options())) == order


PEPPER_CAMS = list(declaration.sensors_of(camera='pepper'))
REALSENSE = list(declaration.sensors_of(camera='realsense'))


def shipped_like_input(files):
    """The shipped input file's choice: every sensor on but the two RealSense cameras."""
    write(files.input, ''.join('%s %s\n' % (n, 'false' if n in REALSENSE else 'true') for n in ALL))


@pytest.mark.parametrize('cameras, tested, skipped', [
    (None, PEPPER_CAMS, []),                            # the input file decides
    ('pepper', PEPPER_CAMS, []),
    ('realsense', REALSENSE, PEPPER_CAMS),              # before: 4 SKIPPED, no camera tested
    ('both', PEPPER_CAMS + REALSENSE, []),              # before: never the RealSense
    ('BOTH', PEPPER_CAMS + REALSENSE, []),
])
def test_cameras_option_selects_the_cameras_it_names(files, cameras, tested, skipped):
    shipped_like_input(files)
    plan = load_plan(files.options(cameras=cameras))
    active = [s.name for s in plan.active if s.sensor.camera]
    assert sorted(active) == sorted(tested)
    got = {s.name: s.skip_reason for s in plan.sensors if s.skip_reason}
    assert sorted(got) == sorted(skipped)
    assert all(r == 'left out by --cameras realsense' for r in got.values())
    # the other sensors are the input file's, in its order; the cameras keep the file's order
    assert plan_names(plan) == [n for n in ALL if n not in REALSENSE or n in tested]
    notes = '\n'.join(plan.notes)
    if cameras is None:        # the header says what is left out and how to test it
        assert 'not tested: realsenseRGBCamera, realsenseDepthCamera (false in input.ini)' in notes
        assert '--cameras realsense' in notes and '--cameras both' in notes
    else:
        assert 'cameras: %s (--cameras %s' % (', '.join(n for n in ALL if n in tested), cameras.lower()) in notes
    if skipped:
        assert 'skipped: %s (left out by --cameras realsense)' % ', '.join(
            n for n in ALL if n in skipped) in notes


def test_cameras_option_adds_cameras_missing_from_the_input_file(files):
    write(files.input, 'laser true\nfrontCamera false\n')
    plan = load_plan(files.options(cameras='realsense'))
    assert plan_names(plan) == ['laser'] + REALSENSE
    assert [s.name for s in plan.active] == ['laser'] + REALSENSE
    assert any('not tested: frontCamera (false in input.ini)' in n for n in plan.notes), plan.notes


def test_cameras_option_with_sensors_only_leaves_out(files):
    """--sensors is exact: --cameras adds nothing to it and SKIPS the other group's cameras."""
    plan = load_plan(files.options(sensors=('laser', 'frontCamera', 'realsenseRGBCamera'), cameras='pepper'))
    assert plan_names(plan) == ['laser', 'frontCamera', 'realsenseRGBCamera']
    assert {s.name: s.skip_reason for s in plan.sensors if s.skip_reason} == \
        {'realsenseRGBCamera': 'left out by --cameras pepper'}
    assert any('adds no camera to --sensors' in n and 'bottomCamera' in n for n in plan.notes), plan.notes


def test_cameras_default_is_the_input_file(files):
    assert load_plan(files.options()).cameras is None
    shipped_like_input(files)
    assert [s.name for s in load_plan(files.options()).active if s.sensor.camera] == PEPPER_CAMS


def test_realsense_in_the_simulator_is_skipped_with_its_reason(files):
    plan = load_plan(files.options(platform='simulator', cameras='realsense'))
    got = {s.name: s.skip_reason for s in plan.sensors if s.sensor.camera}
    assert got['realsenseRGBCamera'] == got['realsenseDepthCamera'] == 'not available in the simulator'
    shipped_like_input(files)     # no hint to use --cameras realsense where there is none
    assert not any('--cameras realsense' in n for n in load_plan(files.options(platform='simulator')).notes)


# ------------------------------------------------------------------ --require-heard, windows in the header

def test_require_heard_without_the_microphone_is_refused(files):
    """Before: speech passed with no note (nothing could hear it)."""
    e = error_of(files.options(sensors=('speech', 'laser'), require_heard=True))
    assert '--require-heard' in e.message and 'microphone is not in this run' in e.message
    assert '--sensors speech,microphone' in e.fix and 'input.ini' in e.fix
    write(files.input, 'speech true\nmicrophone false\n')
    assert 'microphone is not in this run' in error_of(files.options(require_heard=True)).message
    plan = load_plan(files.options(sensors=('speech', 'microphone'), require_heard=True))
    assert any('passes only when the microphones hear' in n for n in plan.notes)


@pytest.mark.parametrize('extra, words', [
    (dict(sensors=('laser',)), 'speech is not in this run'),
    (dict(platform='simulator'), 'speech is not available in the simulator'),
    (dict(bag='/tmp/x.bag'), 'speech is not checked from a bag'),
])
def test_require_heard_without_speech_has_no_effect_and_says_so(files, extra, words):
    plan = load_plan(files.options(require_heard=True, **extra))
    assert any('--require-heard has no effect' in n and words in n for n in plan.notes), plan.notes


def test_header_notes_tell_each_window(files):
    """Before: the header said "2 s each" while the microphone listened 8 s."""
    plan = load_plan(files.options(mic_mode='sequential', duration=2.0))
    assert 'microphone listens 8 s: --mic-mode sequential, each of the 4 microphones for 2 s' in plan.notes
    assert any(n.startswith('speech: one sentence') and 'listen 4 s' in n for n in plan.notes)
    # computed from the plan as it is run (cli.run_bag changes the duration after loading)
    assert 'microphone listens 20 s' in '\n'.join(settings.replace(plan, duration=5.0).notes)
    together = load_plan(files.options(duration=2.0, sensors=('microphone', 'laser')))
    assert not any('listens' in n for n in together.notes)


def test_mic_mode_is_read_as_its_canonical_word(files):
    """--mic-mode Sequential: the check and the run header both see 'sequential' (the header
    used to say 8 s while the check, comparing the raw word, listened together for 2 s)."""
    plan = load_plan(files.options(mic_mode='Sequential', duration=2.0))
    assert plan.options.mic_mode == 'sequential'
    assert any(n.startswith('microphone listens 8 s') for n in plan.notes)


def test_simulator_skips_what_the_simulator_lacks(files):
    sim_names = [n for n in ALL if catalog.SENSORS[n].simulator]
    write(files.sim, topics_text(sim_names, prefix='/sim'))   # no topics for the others
    plan = load_plan(files.options(platform='simulator'))
    skipped = {s.name: s.skip_reason for s in plan.sensors if s.skip_reason}
    assert set(skipped) == set(ALL) - set(sim_names)
    # the declaration's simulator has no microphone, IMU, speech, stereo camera, RealSense, touch
    # or diagnostics (pepper_virtual: docs/drivers.md)
    assert {'microphone', 'imu', 'speech', 'stereoCamera', 'robotHealth'} <= set(skipped)
    assert all('simulator' in r for r in skipped.values())
    for name in ('headTouch', 'handTouch', 'bumper', 'robotHealth'):   # why, in words
        assert 'pepper_virtual' in skipped[name] and 'publishes no' in skipped[name]
    assert {s.name: s.topic for s in plan.active} == {n: '/sim/' + n for n in sim_names}
    assert plan.files['topics'] == files.sim


def test_topic_missing_for_an_enabled_sensor(files):
    write(files.topics, topics_text([n for n in ALL if n != 'odometry']))
    e = error_of(files.options())
    assert e.path == files.topics and '"odometry"' in e.message
    assert 'odometry /topic/name' in e.fix and 'input.ini' in e.fix
    # disabled, or excluded by --sensors: no topic needed
    write(files.input, 'laser true\nodometry false\n')
    assert plan_names(load_plan(files.options())) == ['laser']
    assert plan_names(load_plan(files.options(sensors=('imu',)))) == ['imu']


def test_topics_file_option_and_topics_dir(files, tmp_path):
    other = tmp_path / 'elsewhere'
    other.mkdir()
    write(other / 'topics.dat', topics_text(prefix='/other'))
    plan = load_plan(files.options(topics_dir=str(other), sensors=('laser',)))
    assert plan.sensors[0].topic == '/other/laser'
    direct = write(tmp_path / 'direct.dat', 'laserSensor /direct\n')
    plan = load_plan(files.options(topics=direct, sensors=('laser',)))
    assert plan.sensors[0].topic == '/direct' and plan.files['topics'] == direct
    write(files.config, 'platform robot\nrobotTopics %s\n' % direct)     # absolute path in config
    assert load_plan(files.options(sensors=('laser',))).sensors[0].topic == '/direct'


def test_options_override_the_configuration_file(files):
    write(files.config, 'platform robot\nmode sequential\nrobotTopics topics.dat\n'
                        'simulatorTopics sim.dat\n')
    plan = load_plan(files.options(mode='parallel', platform='simulator', quick=True))
    assert (plan.mode, plan.platform, plan.quick) == ('parallel', 'simulator', True)
    assert plan.files['topics'] == files.sim
    plan = load_plan(files.options())
    assert (plan.mode, plan.platform, plan.quick) == ('sequential', 'robot', False)
    assert (plan.duration, plan.wait) == (10.0, 5.0)
    assert plan.output_dir == files.out


def test_mode_and_topics_file_defaults(files):
    """Without mode and topics keys: sequential, and the original file names in the topics dir."""
    write(files.config, 'platform robot\n')
    write(os.path.join(files.dir, 'pepperTopics.dat'), topics_text(prefix='/pepper_default'))
    write(os.path.join(files.dir, 'simulatorTopics.dat'), 'laserSensor /sim_default\n')
    plan = load_plan(files.options(sensors=('laser',)))
    assert plan.mode == 'sequential' and plan.sensors[0].topic == '/pepper_default/laser'
    plan = load_plan(files.options(sensors=('laser',), platform='simulator'))
    assert plan.sensors[0].topic == '/sim_default'


# ------------------------------------------------------------------ expectations

def test_expectations_merge_defaults_and_platform(files):
    write(files.expectations, yaml.safe_dump({
        'defaults': {'min_messages': 3, 'max_delay': 5.0},
        'robot': {'Laser': {'max_delay': 1.0, 'ranges': 61}, 'backSonar': None},
        'simulator': {'laserSensor': {'ranges': 90}},
    }))
    plan = load_plan(files.options(sensors=('laser', 'backSonar', 'imu')))
    e = {s.name: s.expect for s in plan.sensors}
    assert (e['laser'].min_messages, e['laser'].max_delay, e['laser'].ranges) == (3, 1.0, 61)
    assert (e['backSonar'].min_messages, e['backSonar'].max_delay) == (3, 5.0)
    assert (e['imu'].min_messages, e['imu'].max_delay) == (3, 5.0)
    # keys the file leaves out take the dataclass defaults (the only defaults)
    assert (e['imu'].max_future, e['imu'].quick_messages, e['imu'].rate) == (1.0, 10, None)
    sim = load_plan(files.options(platform='simulator', sensors=('laser',)))
    assert (sim.sensors[0].expect.max_delay, sim.sensors[0].expect.ranges) == (5.0, 90)
    with pytest.raises(dataclasses.FrozenInstanceError):
        plan.sensors[0].expect.ranges = 1        # read-only


def test_shipped_expectations_reach_the_plan():
    plan = load_plan(Options(sensors=('laser', 'jointState')))
    laser, joints = plan.sensors
    data = yaml.safe_load(open(SHIPPED_EXPECT))
    # the laser's layout comes from its driver profile (drivers: in the file)
    profile = data['drivers'][data['robot']['laser']['driver']]['laser']
    assert laser.expect.driver == 'naoqi_driver' and laser.expect.ranges == profile['ranges']
    assert laser.expect.min_messages == data['defaults']['min_messages']
    assert list(joints.expect.joints) == data['robot']['jointState']['joints']


# ------------------------------------------------------------------ options from args and ROS params

def test_options_merged():
    a = Options(mode='parallel', duration=3.0)
    b = Options(duration=5.0, quick=False)
    m = a.merged(b)
    assert (m.mode, m.duration, m.quick) == ('parallel', 5.0, False)


def test_options_from_command_line():
    ns = cli.build_parser().parse_args(['--mode', 'parallel', '--sensors', 'laser,BackSonar imu',
                                        '--duration', '2', '--wait', '1.5', '--quick',
                                        '--output-dir', '/tmp/x', '--no-history', '--cameras', 'pepper'])
    o = options.from_args(ns)
    assert o.sensors == ('laser', 'BackSonar', 'imu')
    assert (o.mode, o.duration, o.wait, o.quick, o.history) == ('parallel', 2.0, 1.5, True, False)
    assert (o.output_dir, o.cameras, o.platform) == ('/tmp/x', 'pepper', None)


def test_options_from_private_params():
    params = {'~mode': 'parallel', '~duration': 2, '~wait': '1.5', '~quick': 'true',
              '~record': False, '~sensors': ['laser', 'imu'], '~output_dir': '/tmp/y',
              '~platform': ''}
    o = options.from_params(lambda name, default=None: params.get(name, default))
    assert (o.mode, o.duration, o.wait, o.quick, o.record) == ('parallel', 2.0, 1.5, True, False)
    assert o.sensors == ('laser', 'imu') and o.output_dir == '/tmp/y' and o.platform is None
    params['~sensors'] = 'laser, imu'
    o = options.from_params(lambda name, default=None: params.get(name, default))
    assert o.sensors == ('laser', 'imu')


@pytest.mark.parametrize('name, value, words', [('~quick', 'sometimes', 'true or false'),
                                                ('~duration', 'long', 'greater than 0')])
def test_bad_private_params(name, value, words):
    with pytest.raises(ConfigError) as info:
        options.from_params(lambda n, default=None: value if n == name else default)
    assert name in info.value.message and words in info.value.fix


@pytest.mark.parametrize('text, line, words', [
    ('defaults: 3\n', 1, 'defaults is 3'),
    ('defaults:\n  min_messages: 3\nrobot: [laser]\n', 3, 'robot is'),
    ('robot:\n  backSonar:\n    nominal: 10\n  laser: 5\n', 4, 'robot.laser is 5'),
    ('robot:\n  laser:\n    rate: 5\n', 3, 'rate is 5'),
    ('robot:\n  imu:\n    rate: [16, 4]\n', 3, 'rate is [16, 4]'),
    ('robot:\n  backSonar:\n    field_of_view: [0.1]\n', 3, 'field_of_view'),
    ('defaults:\n  min_messages: many\n', 2, 'min_messages is \'many\''),
    ('robot:\n\n  laser:\n    max_delay: [1]\n', 4, 'max_delay'),
])
def test_malformed_expectations_name_the_line(files, text, line, words):
    """Before: a TypeError/AttributeError traceback at start, or a crash when the verdict was made.
    The line is the offending key's own line (it was the sensor's line before the typed loader)."""
    write(files.expectations, text)
    e = error_of(files.options())
    assert (e.path, e.line) == (files.expectations, line)
    assert words in e.message and e.fix


def test_expectations_of_the_other_platform_are_not_checked(files):
    write(files.expectations, 'simulator:\n  laser:\n    rate: 5\n')
    assert load_plan(files.options(sensors=('laser',))).platform == 'robot'


# ------------------------------------------------------------------ --rerun-failed

def test_rerun_failed_reads_the_latest_run_of_the_output_folder(files):
    import json
    os.makedirs(files.out)
    path = os.path.join(files.out, 'sensorTestResults.json')
    e = error_of(files.options(rerun_failed=True))
    assert 'no previous run in %s' % files.out in e.message and 'without --rerun-failed' in e.fix
    run = {'run_id': '20260101-000000', 'platform': 'robot', 'sensors': [
        {'name': 'laser', 'verdict': 'FAIL'}, {'name': 'imu', 'verdict': 'PASS'},
        {'name': 'odometry', 'verdict': 'INTERRUPTED'}, {'name': 'speech', 'verdict': 'SKIPPED'}]}
    write(path, json.dumps(run))
    plan = load_plan(files.options(rerun_failed=True))
    assert plan_names(plan) == ['laser', 'odometry']
    assert 're-running what did not pass in run 20260101-000000: laser, odometry' in plan.notes
    e = error_of(files.options(rerun_failed=True, platform='simulator', topics=files.sim))
    assert 'on the robot platform' in e.message and e.fix == 'add --platform robot'
    assert '--sensors' in error_of(files.options(rerun_failed=True, sensors=('imu',))).message
    for s in run['sensors']:
        s['verdict'] = 'PASS'
    write(path, json.dumps(run))
    assert 'nothing to re-run' in error_of(files.options(rerun_failed=True)).message
    write(path, '{"sensors": "laser"}')
    assert 'is not a sensorTest result' in error_of(files.options(rerun_failed=True)).message


def test_package_dir_is_found_next_to_the_module_without_rospkg(monkeypatch):
    """From a source checkout the package's folder is found from the module's own path, not by
    asking rospkg to crawl the ROS package path (slow, and wrong when another copy is on it)."""
    from pepper_interface_tests.plan.settings import package_dir
    repo = os.path.dirname(os.path.dirname(os.path.dirname(os.path.realpath(__file__))))
    monkeypatch.setenv('ROS_PACKAGE_PATH', '/nonexistent')   # rospkg could find nothing
    assert os.path.realpath(package_dir()) == repo


# ------------------------------------------------------------------ --move (the motion row)

def test_move_adds_the_motion_row_first_without_naming_it(files):
    write(files.input, 'laser true\nimu true\n')
    plan = load_plan(files.options(move=True))
    assert plan_names(plan) == ['motion', 'laser', 'imu']
    assert plan.sensors[0].topic == '/move_base_simple/goal' and plan.sensors[0].expect.base_turn == 0.5
    assert not any('motion' in n for n in plan.notes)            # no "not tested: motion" either way
    assert not any('motion' in n for n in load_plan(files.options()).notes)
    assert plan.topics['laser']                                  # the witnesses' topics


def test_motion_in_sensors_needs_move_and_move_is_refused_from_a_bag(files):
    e = error_of(files.options(sensors=('laser', 'motion')))
    assert 'only with --move' in e.message and 'add --move' in e.fix
    plan = load_plan(files.options(sensors=('laser', 'motion'), move=True))
    assert plan_names(plan) == ['motion', 'laser']
    e = error_of(files.options(move=True, bag='/tmp/x.bag'))
    assert 'a recording has nothing to command' in e.message and 'leave out --move' in e.fix


def test_the_motion_row_is_skipped_with_its_reason_on_the_simulator(files):
    plan = load_plan(files.options(move=True, platform='simulator', sensors=('laser',)))
    assert plan.sensors[0].name == 'motion' and '/pepper/cmd_vel' in plan.sensors[0].skip_reason
