"""sensorTest's options, declared once: OPTIONS is the single list every other form comes from.

Each `Opt` row is one command-line flag. From the table come the argparse arguments (flag, help,
metavar, group: `add_arguments`), the private ROS params `~name` (`PARAMS`) and which of them are
true/false (`BOOL_PARAMS`), and the reading of both into `Options` (`from_args`, `from_params`).
The `Options` dataclass below names the same fields once more, typed for mypy; test/plan/test_options.py
fails when the table, the dataclass and the option reference docs/options.md disagree.

To add an option: one row in OPTIONS, one field in Options, then `make docs` (docs/options.md is
generated from this table: tools/gen_options.py) and its param in docs/node-api.md.
"""
import argparse
from dataclasses import dataclass, fields, replace
from typing import Any, Callable, Dict, Optional, Tuple, Union

from .textfile import ConfigError, parse_bool, positive_seconds

# what a flag's value is (its kind)
TEXT = 'text'         # a word or a path, taken as given
SECONDS = 'seconds'   # a positive number of seconds
NAMES = 'names'       # sensor names separated by commas or spaces (a ROS param may be a list)
ON = 'on'             # a switch without a value that sets True
OFF = 'off'           # a switch without a value that sets False
SWITCHES = (ON, OFF)


@dataclass(frozen=True)
class Opt:
    """One command-line flag; `name` is what it sets: the Options field and the ROS param ~name."""
    name: str
    flag: str
    kind: str
    group: str           # the --help section: files, run, media or results
    help: str
    metavar: Optional[str] = None
    param: bool = True   # also read as the private ROS param ~name
    field: bool = True   # an Options field; False: how the node itself runs (cli reads it)


OPTIONS: Tuple[Opt, ...] = (
    Opt('config', '--config', TEXT, 'files', 'configuration file (default config/sensorTestConfiguration.ini)',
        'FILE'),
    Opt('input', '--input', TEXT, 'files', 'input file: which sensors run (default config/sensorTestInput.ini)',
        'FILE'),
    Opt('topics', '--topics', TEXT, 'files', 'topics file (default: the one the configuration names, in data/)',
        'FILE'),
    Opt('topics_dir', '--topics-dir', TEXT, 'files',
        'folder where the configuration\'s topics file is looked up (default data/)', 'DIR'),
    Opt('expectations', '--expectations', TEXT, 'files',
        'expectations file (default config/sensorExpectations.yaml)', 'FILE'),
    Opt('driver', '--driver', TEXT, 'files',
        'driver profile of the expectations file (a name under "drivers:", e.g. '
        'yohatad_naoqi_driver2); default: each sensor\'s own, and for a ROS 2 recording the '
        'naoqi_driver2 profile the recording shows', 'NAME'),
    Opt('output_dir', '--output-dir', TEXT, 'files',
        'where results go (default data/ of the package when writable, else '
        '$ROS_HOME/pepper_interface_tests, $ROS_HOME being ~/.ros unless set)', 'DIR'),
    Opt('platform', '--platform', TEXT, 'run', 'robot or simulator (overrides the configuration file)'),
    Opt('mode', '--mode', TEXT, 'run', 'sequential or parallel (overrides the configuration file)'),
    Opt('duration', '--duration', SECONDS, 'run', 'seconds each sensor is listened to (default 10)', 'S'),
    Opt('wait', '--wait', SECONDS, 'run', 'seconds allowed for the first message (default 5)', 'S'),
    Opt('sensors', '--sensors', NAMES, 'run',
        'run exactly these sensors, in this order (ignores the input file)', 'A,B,...'),
    Opt('rerun_failed', '--rerun-failed', ON, 'run',
        'run only the sensors that did not pass in the latest run of the output folder (its '
        'sensorTestResults.json)'),
    Opt('cameras', '--cameras', TEXT, 'run',
        'test exactly these cameras: pepper, realsense or both, whatever the input file says '
        '(default: the input file decides)', 'WHICH'),
    Opt('quick', '--quick', ON, 'run',
        'end each sensor\'s window as soon as its verdict is settled (quick_messages, default 10, '
        'spanning at least 0.8 s, and the sensor\'s own checks)'),
    Opt('guided', '--guided', ON, 'run',
        'guided check: ask a person to touch each touch zone and bumper in turn (default: when '
        'stdin and stdout are a terminal)'),
    Opt('guided', '--no-guided', OFF, 'run',
        'unattended: judge the touch events that arrive, nobody is asked (default without a terminal)'),
    Opt('touch_wait', '--touch-wait', SECONDS, 'run',
        'guided check: seconds to wait for each zone\'s press (default 15)', 'S'),
    Opt('move', '--move', ON, 'run',
        'motion check: turn the head and the base by small known amounts and judge every motion '
        'sensor against the motion (adds the motion row; live robot only, never on by default)'),
    Opt('yes', '--yes', ON, 'run',
        'with --move: move without asking for Enter first (a run without a terminal never asks)'),
    Opt('bag', '--bag', TEXT, 'run', 'check a recorded bag instead of live topics (no master needed)',
        'FILE', param=False),
    Opt('debug', '--debug', ON, 'run', 'print one line per received message (stderr)'),
    Opt('end_launch', '--end-launch', ON, 'run',
        'for launch files: at the end, write the exit code to $PEPPER_SENSORTEST_EXIT_FILE and end the '
        'roslaunch that started this node (no "REQUIRED process has died" banner; see sensorTestLaunch)',
        param=False, field=False),
    Opt('node_name', '--node-name', TEXT, 'run',
        'fixed ROS node name (default: sensorTest_<pid>_<ms>, unique per run, which also reads params '
        'set under /sensorTest/)', 'NAME', param=False, field=False),
    Opt('record', '--no-record', OFF, 'media', 'do not write videos and WAV files'),
    Opt('show', '--show', ON, 'media', 'live view of the cameras (default: when a display exists)'),
    Opt('show', '--no-show', OFF, 'media', 'no live view'),
    Opt('play_audio', '--play-audio', ON, 'media', 'play the recorded microphones afterwards (spec behaviour)'),
    Opt('delete_file', '--delete-file', ON, 'media', 'delete the WAV after playing it'),
    Opt('mic_mode', '--mic-mode', TEXT, 'media',
        'together (4-channel WAV, default) or sequential (each microphone in turn, as the spec)', 'MODE'),
    Opt('require_heard', '--require-heard', ON, 'media',
        'speech fails unless the microphones hear it (needs the microphone in the run)'),
    Opt('baseline', '--baseline', TEXT, 'results',
        'compare this run with that run (an id, a run folder or its sensorTestResults.json) '
        'instead of the pinned baseline (sensorTestHistory baseline set RUN); "none": with none',
        'RUN'),
    Opt('baseline', '--no-baseline', OFF, 'results',
        'compare with no baseline, not even the pinned one', param=False),
    Opt('history', '--no-history', OFF, 'results', 'do not keep this run in the run history'),
    Opt('diagnostics', '--no-diagnostics', OFF, 'results', 'do not publish /diagnostics'),
    Opt('report', '--no-report', OFF, 'results', 'do not write the HTML report'),
)


@dataclass(frozen=True)
class Options:
    """Everything a user can set from the command line or as a private ROS param (OPTIONS).

    None means "not given": the file value or the default applies.
    """
    config: Optional[str] = None
    input: Optional[str] = None
    topics: Optional[str] = None
    topics_dir: Optional[str] = None
    expectations: Optional[str] = None
    driver: Optional[str] = None
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
    rerun_failed: Optional[bool] = None
    guided: Optional[bool] = None
    touch_wait: Optional[float] = None
    baseline: Optional[Union[str, bool]] = None     # a run; False: --no-baseline
    move: Optional[bool] = None
    yes: Optional[bool] = None

    def merged(self, other: 'Options') -> 'Options':
        """Values of `other` where given, else ours."""
        given = {k: v for k, v in other.__dict__.items() if v is not None}
        return replace(self, **given)


def _kinds() -> Dict[str, str]:
    """{name: kind} of the Options fields; a name set by ON and OFF flags is a switch (ON)."""
    kinds: Dict[str, str] = {}
    for o in OPTIONS:
        if o.field:
            kinds.setdefault(o.name, ON if o.kind in SWITCHES else o.kind)
    return kinds


KINDS = _kinds()
FLAGS = {o.name: o.flag for o in reversed(OPTIONS)}   # name -> its (first) flag
# the private ROS params, in the Options fields' order (the order their origins are listed in)
PARAMS: Tuple[str, ...] = tuple(f.name for f in fields(Options)
                                 if any(o.param and o.name == f.name for o in OPTIONS))
BOOL_PARAMS: Tuple[str, ...] = tuple(name for name in PARAMS if KINDS[name] == ON)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Every OPTIONS row as an argument of `parser`, in --help sections named by `group`."""
    groups: Dict[str, Any] = {}     # name -> argparse's (private) _ArgumentGroup
    for o in OPTIONS:
        if o.group not in groups:
            groups[o.group] = parser.add_argument_group(o.group)
        if o.kind in SWITCHES:
            groups[o.group].add_argument(o.flag, dest=o.name, action='store_const', const=o.kind == ON,
                                         help=o.help)
        else:
            groups[o.group].add_argument(o.flag, dest=o.name, metavar=o.metavar, help=o.help)


def sensor_names(value: Any) -> Tuple[str, ...]:
    """`laser,imu`, `laser imu` or a list (a ROS param) -> ('laser', 'imu')."""
    items = value if isinstance(value, (list, tuple)) else str(value).replace(' ', ',').split(',')
    return tuple(x for x in items if x)


def from_args(ns: argparse.Namespace) -> Options:
    """Parsed command line -> Options (flags not given stay None)."""
    values: Dict[str, Any] = {}
    for name, kind in KINDS.items():
        v = getattr(ns, name, None)
        if v is None:
            continue
        if kind == NAMES:
            v = sensor_names(v)
            if not v:
                raise ConfigError('%s "%s" names no sensor' % (FLAGS[name], getattr(ns, name)),
                                  fix='give sensor names, e.g. --sensors laser,imu, or leave --sensors '
                                      'out to run the sensors the input file enables')
        elif kind == SECONDS:
            v = positive_seconds(v, FLAGS[name])
        values[name] = v
    return Options(**values)


def from_params(get_param: Callable[..., Any], what: Callable[[str], str] = lambda name: '~' + name) -> Options:
    """Private ROS params (~mode, ~duration, ...) -> Options; `get_param(key, default)` as
    rospy.get_param. An empty value counts as not given. `what(name)`: how an error names the
    param (ROS 1's ~name; a ROS 2 parameter on ROS 2)."""
    values: Dict[str, Any] = {}
    for name in PARAMS:
        v = get_param('~' + name, None)
        if v is None or v == '':
            continue
        kind = KINDS[name]
        if kind == ON:
            v = parse_bool(v, key=what(name))
        elif kind == SECONDS:
            v = positive_seconds(v, what(name))
        elif kind == NAMES:
            v = sensor_names(v)
        else:
            v = str(v)
        values[name] = v
    return Options(**values)
