"""Configuration, input, topics and expectations files -> one immutable TestPlan.

Data flow: Options (command line, then private ROS params) name the files and override values;
the configuration file gives platform, mode and the topics file; the input file says which
sensors run, in which order; the topics file maps sensors to topics; the expectations file gives
what each sensor should deliver. Every problem raises ConfigError naming the file, the line,
what was found and the fix.
"""
import os
from dataclasses import dataclass, field, replace
from types import MappingProxyType
from typing import Optional, Tuple

import yaml

from . import catalog

PLATFORMS = ('robot', 'simulator')
MODES = ('sequential', 'parallel')
CAMERA_CHOICES = ('pepper', 'realsense', 'both')
MIC_MODES = ('together', 'sequential')
CONFIG_KEYS = ('platform', 'robottopics', 'simulatortopics', 'mode')
TRUE_WORDS = ('true', 'yes', 'on', '1')
FALSE_WORDS = ('false', 'no', 'off', '0')


class ConfigError(Exception):
    """A problem with the run's files or options, reported as `file:line: problem. fix`."""

    def __init__(self, message, path=None, line=None, fix=None):
        self.path, self.line, self.message, self.fix = path, line, message, fix
        where = ''
        if path:
            where = '%s:%s: ' % (path, line) if line else '%s: ' % path
        text = where + message
        if fix:
            text += '\n  fix: ' + fix
        super().__init__(text)


def package_dir():
    """The package's own directory (source checkout or installed share directory)."""
    here = os.path.dirname(os.path.realpath(__file__))
    candidate = os.path.normpath(os.path.join(here, '..', '..'))
    if os.path.isdir(os.path.join(candidate, 'config')):
        return candidate
    import rospkg
    return rospkg.RosPack().get_path('pepper_interface_tests')


def default_output_dir():
    """data/ of the package when writable (a source checkout), else $ROS_HOME/pepper_interface_tests."""
    data = os.path.join(package_dir(), 'data')
    if os.access(data, os.W_OK):
        return data
    ros_home = os.environ.get('ROS_HOME', os.path.join(os.path.expanduser('~'), '.ros'))
    return os.path.join(ros_home, 'pepper_interface_tests')


@dataclass(frozen=True)
class Options:
    """Everything a user can set from the command line or as a private ROS param.

    None means "not given": the file value or the default applies.
    """
    config: Optional[str] = None
    input: Optional[str] = None
    topics: Optional[str] = None
    topics_dir: Optional[str] = None
    expectations: Optional[str] = None
    platform: Optional[str] = None
    mode: Optional[str] = None
    duration: Optional[float] = None
    wait: Optional[float] = None
    output_dir: Optional[str] = None
    sensors: Optional[Tuple[str, ...]] = None
    cameras: Optional[str] = None
    quick: Optional[bool] = None
    bag: Optional[str] = None
    record: Optional[bool] = None
    show: Optional[bool] = None
    play_audio: Optional[bool] = None
    delete_file: Optional[bool] = None
    mic_mode: Optional[str] = None
    require_heard: Optional[bool] = None
    history: Optional[bool] = None
    diagnostics: Optional[bool] = None
    report: Optional[bool] = None
    debug: Optional[bool] = None

    def merged(self, other):
        """Values of `other` where given, else ours."""
        given = {k: v for k, v in other.__dict__.items() if v is not None}
        return replace(self, **given)


@dataclass(frozen=True)
class SensorPlan:
    """One sensor of the run: what to listen to and what to expect."""
    sensor: catalog.Sensor
    topic: Optional[str]
    expect: MappingProxyType
    skip_reason: Optional[str] = None

    @property
    def name(self):
        return self.sensor.name


@dataclass(frozen=True)
class TestPlan:
    platform: str
    mode: str
    duration: float
    wait: float
    quick: bool
    cameras: str
    output_dir: str
    sensors: Tuple[SensorPlan, ...]
    files: MappingProxyType = field(default_factory=lambda: MappingProxyType({}))
    options: Options = Options()

    @property
    def active(self):
        return tuple(s for s in self.sensors if s.skip_reason is None)


# ---------------------------------------------------------------- low-level file reading

def read_pairs(path, what):
    """`key value` lines of a file -> [(line number, key, value)]; '#' comments, blanks skipped."""
    if not os.path.exists(path):
        raise ConfigError('%s not found' % what, path,
                          fix='give an existing file (see README, "Files") or create it')
    try:
        with open(path, encoding='utf-8') as f:
            lines = f.read().splitlines()
    except (OSError, UnicodeDecodeError) as e:
        raise ConfigError('cannot read %s: %s' % (what, e), path,
                          fix='check the file permissions and that it is a text file')
    pairs = []
    for number, raw in enumerate(lines, 1):
        text = raw.split('#', 1)[0].strip() if not raw.lstrip().startswith('#') else ''
        if not text:
            continue
        parts = text.split(None, 1)
        if len(parts) < 2:
            raise ConfigError('"%s" has a key but no value' % text, path, number,
                              fix='write "key value" on one line, separated by spaces')
        pairs.append((number, parts[0], parts[1].strip()))
    return pairs


def parse_bool(value, path=None, line=None, key=None):
    word = str(value).strip().lower()
    if word in TRUE_WORDS:
        return True
    if word in FALSE_WORDS:
        return False
    raise ConfigError('%s"%s" is not true or false' % ('%s: ' % key if key else '', value),
                      path, line, fix='write true or false')


def choice(value, choices, what, path=None, line=None):
    word = str(value).strip().lower()
    if word not in choices:
        raise ConfigError('%s "%s" is not valid' % (what, value), path, line,
                          fix='use one of: ' + ', '.join(choices))
    return word


def positive_seconds(value, what, path=None, line=None):
    try:
        number = float(value)
    except (TypeError, ValueError):
        number = -1.0
    if not number > 0 or number != number or number == float('inf'):
        raise ConfigError('%s "%s" is not a positive number of seconds' % (what, value), path, line,
                          fix='give a number of seconds greater than 0, e.g. 10')
    return number


def _valid_names():
    return ', '.join(catalog.SENSORS)


# ---------------------------------------------------------------- the three files

def read_configuration(path):
    """sensorTestConfiguration.ini -> dict with platform, mode, robottopics, simulatortopics."""
    values, where = {}, {}
    for line, key, value in read_pairs(path, 'configuration file'):
        k = key.lower()
        if k not in CONFIG_KEYS:
            raise ConfigError('unknown key "%s"' % key, path, line,
                              fix='valid keys: platform, robotTopics, simulatorTopics, mode')
        values[k], where[k] = value, line
    if 'platform' in values:
        values['platform'] = choice(values['platform'], PLATFORMS, 'platform', path, where['platform'])
    if 'mode' in values:
        values['mode'] = choice(values['mode'], MODES, 'mode', path, where['mode'])
    return values


def read_input(path):
    """sensorTestInput.ini -> ordered [(canonical name, enabled)] in file order."""
    seen, order = {}, []
    for line, key, value in read_pairs(path, 'input file'):
        name = catalog.canonical(key)
        if name is None:
            raise ConfigError('unknown sensor "%s"' % key, path, line,
                              fix='valid sensors: ' + _valid_names())
        if name in seen:
            raise ConfigError('sensor "%s" is listed twice (first on line %d)' % (key, seen[name]),
                              path, line, fix='keep one line per sensor')
        seen[name] = line
        order.append((name, parse_bool(value, path, line, key)))
    return order


def read_topics(path):
    """Topics file -> {canonical name: topic}; actuator keys are ignored."""
    topics = {}
    for line, key, value in read_pairs(path, 'topics file'):
        if catalog.is_actuator_key(key):
            continue
        name = catalog.canonical(key)
        if name is None:
            raise ConfigError('unknown topic key "%s"' % key, path, line,
                              fix='valid keys: %s (or the actuator keys Head, RArm, LArm, RHand, '
                                  'LHand, Leg, Wheels)' % _valid_names())
        topic = value.split()[0]
        if not topic.startswith('/') or len(value.split()) > 1:
            raise ConfigError('"%s" is not a topic name' % value, path, line,
                              fix='write "%s /absolute/topic/name"' % key)
        topics[name] = topic
    return topics


def read_expectations(path, platform):
    """Expectations file -> {sensor name: read-only dict} for one platform, defaults merged."""
    if not os.path.exists(path):
        raise ConfigError('expectations file not found', path,
                          fix='give --expectations an existing file (default config/sensorExpectations.yaml)')
    try:
        with open(path, encoding='utf-8') as f:
            data = yaml.safe_load(f) or {}
    except (OSError, yaml.YAMLError) as e:
        line = getattr(getattr(e, 'problem_mark', None), 'line', None)
        raise ConfigError('cannot read expectations: %s' % str(e).splitlines()[0], path,
                          line + 1 if line is not None else None, fix='fix the YAML syntax')
    if not isinstance(data, dict):
        raise ConfigError('expected a mapping with "defaults", "robot" and "simulator"', path)
    defaults = data.get('defaults') or {}
    section = data.get(platform) or {}
    lines = _yaml_key_lines(path)
    _check_mapping('defaults', defaults, path, lines.get(('defaults',)))
    _check_mapping(platform, section, path, lines.get((platform,)))
    for where, value in [(('defaults',), defaults)] + [((platform, k), v) for k, v in section.items()]:
        _check_block('.'.join(map(str, where)), value or {}, path, lines.get(where))
    out = {}
    for name in section:
        if catalog.canonical(str(name)) is None:
            raise ConfigError('unknown sensor "%s" in section %s' % (name, platform), path,
                              lines.get((platform, name)), fix='valid sensors: ' + _valid_names())
    for name in catalog.SENSORS:
        merged = dict(defaults)
        for key, value in section.items():
            if catalog.canonical(str(key)) == name:
                merged.update(value or {})
        out[name] = MappingProxyType(merged)
    return out


BANDS = ('rate', 'field_of_view')
NUMBERS = ('min_messages', 'max_delay', 'max_future', 'quick_messages', 'max_gap_factor')


def _check_mapping(where, value, path, line):
    if not isinstance(value, dict):
        raise ConfigError('%s is %r, not a mapping of "key: value" lines' % (where, value), path, line,
                          fix='indent "key: value" lines under it (see the comments at the top of '
                              'config/sensorExpectations.yaml)')


def _check_block(where, value, path, line):
    """A sensor's (or the defaults') expectations: the keys every run uses must be well formed."""
    _check_mapping(where, value, path, line)
    for key in BANDS:
        band = value.get(key)
        if band is not None and not (isinstance(band, list) and len(band) == 2 and all(
                isinstance(b, (int, float)) and not isinstance(b, bool) for b in band) and band[0] <= band[1]):
            raise ConfigError('%s: %s is %r, not a [min, max] pair' % (where, key, band), path, line,
                              fix='write e.g. "%s: [4.0, 16.0]"' % key)
    for key in NUMBERS:
        number = value.get(key)
        if number is not None and (isinstance(number, bool) or not isinstance(number, (int, float))):
            raise ConfigError('%s: %s is %r, not a number' % (where, key, number), path, line,
                              fix='write a number, e.g. "%s: 3"' % key)


def _yaml_key_lines(path):
    """{(section,): line, (section, sensor): line} of a YAML file, for error messages."""
    try:
        with open(path, encoding='utf-8') as f:
            root = yaml.compose(f)
    except (OSError, yaml.YAMLError):
        return {}
    lines = {}
    if isinstance(root, yaml.MappingNode):
        for key, value in root.value:
            lines[(key.value,)] = key.start_mark.line + 1
            if isinstance(value, yaml.MappingNode):
                for sub, _ in value.value:
                    lines[(key.value, sub.value)] = sub.start_mark.line + 1
    return lines


# ---------------------------------------------------------------- the plan

def _resolve(path, base):
    path = os.path.expanduser(path)
    return path if os.path.isabs(path) else os.path.join(base, path)


def load_plan(options=Options()):
    """Read every file named by `options` (or the package defaults) into a TestPlan."""
    pkg = package_dir()
    config_path = os.path.abspath(options.config or os.path.join(pkg, 'config', 'sensorTestConfiguration.ini'))
    input_path = os.path.abspath(options.input or os.path.join(pkg, 'config', 'sensorTestInput.ini'))
    expect_path = os.path.abspath(options.expectations or os.path.join(pkg, 'config', 'sensorExpectations.yaml'))
    config = read_configuration(config_path)

    platform = choice(options.platform, PLATFORMS, 'platform') if options.platform else config.get('platform')
    if platform is None:
        raise ConfigError('no platform given', config_path,
                          fix='add a line "platform robot" (or simulator), or pass --platform')
    mode = choice(options.mode, MODES, 'mode') if options.mode else config.get('mode', 'sequential')
    cameras = choice(options.cameras or 'both', CAMERA_CHOICES, 'cameras')
    duration = positive_seconds(options.duration if options.duration is not None else 10.0, 'duration')
    wait = positive_seconds(options.wait if options.wait is not None else 5.0, 'wait')
    if options.mic_mode is not None:
        choice(options.mic_mode, MIC_MODES, 'mic_mode')

    if options.topics:
        topics_path = os.path.abspath(os.path.expanduser(options.topics))
    else:
        key = 'robottopics' if platform == 'robot' else 'simulatortopics'
        default_name = 'pepperTopics.dat' if platform == 'robot' else 'simulatorTopics.dat'
        topics_dir = options.topics_dir or os.path.join(pkg, 'data')
        topics_path = os.path.abspath(_resolve(config.get(key, default_name), topics_dir))
    topics = read_topics(topics_path)
    expectations = read_expectations(expect_path, platform)

    if options.sensors:
        order = []
        for spelling in options.sensors:
            name = catalog.canonical(spelling)
            if name is None:
                raise ConfigError('unknown sensor "%s" in --sensors' % spelling,
                                  fix='valid sensors: ' + _valid_names())
            if name not in [n for n, _ in order]:
                order.append((name, True))
    else:
        order = [(n, on) for n, on in read_input(input_path) if on]

    plans = []
    for name, _ in order:
        sensor = catalog.SENSORS[name]
        skip = None
        if platform == 'simulator' and not sensor.simulator:
            skip = 'not available in the simulator'
        elif sensor.camera and cameras != 'both' and sensor.camera != cameras:
            skip = 'camera excluded by cameras=%s' % cameras
        topic = topics.get(name)
        if topic is None and skip is None:
            raise ConfigError('no topic for sensor "%s"' % name, topics_path,
                              fix='add a line "%s /topic/name" or disable the sensor in %s'
                                  % (name, os.path.basename(input_path)))
        plans.append(SensorPlan(sensor, topic, expectations[name], skip))

    output_dir = os.path.abspath(os.path.expanduser(options.output_dir)) if options.output_dir \
        else default_output_dir()
    files = MappingProxyType({'configuration': config_path, 'input': input_path,
                              'topics': topics_path, 'expectations': expect_path})
    return TestPlan(platform=platform, mode=mode, duration=duration, wait=wait,
                    quick=bool(options.quick), cameras=cameras, output_dir=output_dir,
                    sensors=tuple(plans), files=files, options=options)
