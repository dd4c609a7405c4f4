"""Configuration, input, topics and expectations files -> one immutable TestPlan.

Data flow: Options (options.py: command line, then private ROS params) name the files and override values;
the configuration file gives platform, mode and the topics file; the input file says which
sensors run, in which order; the topics file maps sensors to topics; the expectations file gives
what each sensor should deliver. Every problem raises ConfigError naming the file, the line,
what was found and the fix. Every file must be UTF-8 (a leading BOM is accepted); a key given
twice is an error naming both lines. The expectations are typed per family (expectations.py).
"""
import os
from dataclasses import replace  # noqa: F401  (settings.replace: used by cli.py)
from types import MappingProxyType
from typing import Dict, List, Optional, Tuple

from . import catalog, expectations, selection
from .model import SensorPlan, TestPlan  # noqa: F401  (imported from here)
from .options import Options
from .textfile import ConfigError, choice, parse_bool, positive_seconds, read_text  # noqa: F401  (imported from here)

PLATFORMS = ('robot', 'simulator')
MODES = ('sequential', 'parallel')
CAMERA_CHOICES = ('pepper', 'realsense', 'both')
MIC_MODES = ('together', 'sequential')
CONFIG_KEYS = ('platform', 'robottopics', 'simulatortopics', 'mode')


def package_dir() -> str:
    """The package's own directory (source checkout or installed share directory)."""
    here = os.path.dirname(os.path.realpath(__file__))      # <package>/src/pepper_interface_tests/plan
    candidate = os.path.normpath(os.path.join(here, '..', '..', '..'))
    if os.path.isdir(os.path.join(candidate, 'config')):
        return candidate
    if os.environ.get('ROS_VERSION', '').strip() == '2':     # installed by colcon: share/<package>
        from ament_index_python.packages import get_package_share_directory
        return get_package_share_directory('pepper_interface_tests')
    import rospkg
    return rospkg.RosPack().get_path('pepper_interface_tests')


def default_output_dir() -> str:
    """data/ of the package when writable (a source checkout), else $ROS_HOME/pepper_interface_tests."""
    data = os.path.join(package_dir(), 'data')
    if os.access(data, os.W_OK):
        return data
    ros_home = os.environ.get('ROS_HOME', os.path.join(os.path.expanduser('~'), '.ros'))
    return os.path.join(ros_home, 'pepper_interface_tests')


# ---------------------------------------------------------------- low-level file reading

def read_pairs(path: str, what: str) -> List[Tuple[int, str, str]]:
    """`key value` lines of a file -> [(line number, key, value)]; '#' comments, blanks skipped."""
    lines = read_text(path, what).splitlines()
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


def _valid_names():
    return ', '.join(catalog.SENSORS)


# ---------------------------------------------------------------- the three files

def read_configuration(path: str) -> Dict[str, str]:
    """sensorTestConfiguration.ini -> dict with platform, mode, robottopics, simulatortopics."""
    values: Dict[str, str] = {}
    where: Dict[str, int] = {}
    for line, key, value in read_pairs(path, 'configuration file'):
        k = key.lower()
        if k not in CONFIG_KEYS:
            raise ConfigError('unknown key "%s"' % key, path, line,
                              fix='valid keys: platform, robotTopics, simulatorTopics, mode')
        if k in values:
            raise ConfigError('"%s" is given twice (first on line %d)' % (key, where[k]), path, line,
                              fix='keep one "%s" line' % key)
        values[k], where[k] = value, line
    if 'platform' in values:
        values['platform'] = choice(values['platform'], PLATFORMS, 'platform', path, where['platform'])
    if 'mode' in values:
        values['mode'] = choice(values['mode'], MODES, 'mode', path, where['mode'])
    return values


def read_input(path: str) -> List[Tuple[str, bool]]:
    """sensorTestInput.ini -> ordered [(canonical name, enabled)] in file order."""
    seen: Dict[str, int] = {}
    order: List[Tuple[str, bool]] = []
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


def read_topics(path: str) -> Dict[str, str]:
    """Topics file -> {canonical name: topic}; actuator keys are ignored."""
    topics: Dict[str, str] = {}
    where: Dict[str, int] = {}
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
        if name in topics:
            raise ConfigError('sensor "%s" is listed twice (first on line %d)' % (key, where[name]),
                              path, line, fix='keep one line per sensor')
        topics[name], where[name] = topic, line
    return topics


def read_expectations(path: str, platform: str,
                      driver: Optional[str] = None) -> Dict[str, expectations.Expect]:
    """Expectations file -> {sensor name: frozen, typed expectations} for one platform (and
    driver profile, when given)."""
    return expectations.load(path, platform, driver)


# ---------------------------------------------------------------- the plan

def _resolve(path, base):
    path = os.path.expanduser(path)
    return path if os.path.isabs(path) else os.path.join(base, path)


def _motion(order: List[Tuple[str, bool]], options: Options) -> List[Tuple[str, bool]]:
    """The rows only an option adds (catalog `opt_in`): `motion` with --move, first (it runs
    before the other windows: sensors/families.py Traits.leads); refused from a bag."""
    named = [n for n, _ in order if catalog.SENSORS[n].opt_in] if options.sensors else []
    for name in named:      # an input file's line for it is ignored: only the option adds it
        if name == 'motion' and not options.move:
            raise ConfigError('"motion" in --sensors: the motion check runs only with --move',
                              fix='add --move (it adds the motion row by itself), or leave motion '
                                  'out of --sensors')
    order = [(n, on) for n, on in order if not catalog.SENSORS[n].opt_in]
    if not options.move:
        return order
    if options.bag:
        raise ConfigError('--move cannot run from a bag: a recording has nothing to command',
                          fix='leave out --move (a bag is judged as recorded; the sonar/laser and '
                              'clock cross-checks run without it), or run --move against a live '
                              'robot or the emulator')
    return [('motion', True)] + order


def load_plan(options: Optional[Options] = None) -> TestPlan:
    """Read every file named by `options` (or the package defaults) into a TestPlan."""
    options = Options() if options is None else options
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
    cameras = choice(options.cameras, CAMERA_CHOICES, 'cameras') if options.cameras else None
    duration = positive_seconds(options.duration if options.duration is not None else 10.0, 'duration')
    wait = positive_seconds(options.wait if options.wait is not None else 5.0, 'wait')
    if options.mic_mode is not None:    # the check and the run header read the canonical word
        options = replace(options, mic_mode=choice(options.mic_mode, MIC_MODES, 'mic_mode'))

    if options.topics:
        topics_path = os.path.abspath(os.path.expanduser(options.topics))
    else:
        key = 'robottopics' if platform == 'robot' else 'simulatortopics'
        default_name = 'pepperTopics.dat' if platform == 'robot' else 'simulatorTopics.dat'
        topics_dir = options.topics_dir or os.path.join(pkg, 'data')
        topics_path = os.path.abspath(_resolve(config.get(key, default_name), topics_dir))
    topics = read_topics(topics_path)
    expectations = read_expectations(expect_path, platform, options.driver)

    output_dir = os.path.abspath(os.path.expanduser(options.output_dir)) if options.output_dir \
        else default_output_dir()
    rerun_notes: List[str] = []
    if options.rerun_failed:
        sensors, rerun_notes = selection.rerun_failed(output_dir, platform, options)
        options = replace(options, sensors=sensors)
    if options.sensors is not None and not options.sensors:
        raise ConfigError('--sensors names no sensor', fix='give sensor names, e.g. --sensors laser,imu '
                          '(valid: %s), or leave --sensors out to run the input file' % _valid_names())
    if options.sensors:
        order: List[Tuple[str, bool]] = []
        for spelling in options.sensors:
            name = catalog.canonical(spelling)
            if name is None:
                raise ConfigError('unknown sensor "%s" in --sensors' % spelling,
                                  fix='valid sensors: ' + _valid_names())
            if name not in [n for n, _ in order]:
                order.append((name, True))
        notes = rerun_notes + selection.sensors_option_notes([n for n, _ in order], cameras)
    else:
        names, notes = selection.select(read_input(input_path), cameras, os.path.basename(input_path),
                                        platform)
        order = [(n, True) for n in names]
        if not order:
            raise ConfigError('no sensor is selected: every sensor is false or missing', input_path,
                              fix='set at least one sensor to true (e.g. "laser true"), or name '
                                  'sensors with --sensors')

    order = _motion(order, options)
    plans = []
    for name, _ in order:
        sensor = catalog.SENSORS[name]
        skip = None
        if platform == 'simulator' and not sensor.simulator:
            skip = catalog.simulator_skip_reason(name)
        else:
            skip = selection.excluded_by_cameras(sensor, cameras)
        topic = topics.get(name)
        if topic is None and skip is None and platform == 'robot' and sensor.driver_topic:
            # a topics file older than the sensor: the driver's own topic
            topic = sensor.driver_topic
            if not sensor.opt_in:    # motion's topics are naoqi_driver's own, fixed ones
                notes.append('%s: no key in %s, listening on naoqi_driver\'s %s'
                             % (name, os.path.basename(topics_path), topic))
        if topic is None and skip is None:
            raise ConfigError('no topic for sensor "%s"' % name, topics_path,
                              fix='add a line "%s /topic/name" or disable the sensor in %s'
                                  % (name, os.path.basename(input_path)))
        plans.append(SensorPlan(sensor, topic, expectations[name], skip))
    notes += selection.require_heard_notes(plans, options, input_path)

    files = MappingProxyType({'configuration': config_path, 'input': input_path,
                              'topics': topics_path, 'expectations': expect_path})
    return TestPlan(platform=platform, mode=mode, duration=duration, wait=wait,
                    quick=bool(options.quick), cameras=cameras, output_dir=output_dir,
                    sensors=tuple(plans), files=files, options=options, selection_notes=tuple(notes),
                    topics=MappingProxyType(dict(topics)))
