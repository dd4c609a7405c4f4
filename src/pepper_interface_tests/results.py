"""The verdict model: what a run found, as every output reads it.

Verdict, SensorResult (one sensor) and RunResult (the run) are produced by the runner and the
checks and rendered by the writers in outputs/ (outputs/files.py: the spec's .dat, the JSON and
the JUnit XML; the terminal, the report, /diagnostics, the history). Strings that came from the
robot (frame ids, type names, reasons quoting them) are made safe per output with `printable`:
control characters are escaped (no raw ANSI escape reaches a terminal or a text file) and the
length is bounded.
"""
import datetime
import re
from dataclasses import dataclass, field, fields
from enum import Enum
from typing import Any, Callable, Dict, List, Optional, Tuple, Type

from . import codec
from .stats import StreamSummary


class Verdict(str, Enum):
    """A sensor's verdict. A str subclass, so JSON, text files and comparisons with the strings
    read back from an earlier run's JSON see 'PASS', 'FAIL', ..."""
    PASS = 'PASS'
    FAIL = 'FAIL'
    SKIPPED = 'SKIPPED'
    INTERRUPTED = 'INTERRUPTED'   # the window was cut short by an interrupt: not judged, not a failure
    # the PC running sensorTest was too busy to judge the sensor (its load and sensorTest's own
    # lag explain what was seen): not judged, not a failure of the sensor (issue 41)
    NOT_JUDGED = 'NOT JUDGED'

    def __str__(self):
        return self.value

    def __format__(self, spec):
        return format(self.value, spec)


PASS, FAIL, SKIPPED, INTERRUPTED = Verdict.PASS, Verdict.FAIL, Verdict.SKIPPED, Verdict.INTERRUPTED
NOT_JUDGED = Verdict.NOT_JUDGED
OUTPUT_FILE = 'sensorTestOutput.dat'
JSON_FILE = 'sensorTestResults.json'
JUNIT_FILE = 'sensorTestResults.xml'
REPORT_FILE = 'sensorTestReport.html'
SCHEMA_VERSION = 1

EXIT_PASS, EXIT_FAIL, EXIT_CANNOT_START, EXIT_INTERRUPTED = 0, 1, 2, 130
EXIT_NOT_WRITTEN = 3    # a results file could not be written (full disk, removed folder, ...)
EXIT_NOT_JUDGED = 4     # no sensor failed, but the PC was too busy to judge at least one

# C0 controls but tab and newline, DEL, C1 controls, and what XML 1.0 cannot hold
_CONTROL = re.compile('[\x00-\x08\x0b-\x1f\x7f-\x9f\u2028\u2029\ud800-\udfff\ufffe\uffff]')
_NEWLINE = re.compile('[\t\n]')


def printable(text: object, limit: Optional[int] = None, one_line: bool = True) -> str:
    """`text` with control characters written as \\xNN (so an ANSI escape is shown, not obeyed,
    and XML stays well-formed), newlines as \\n when `one_line`, cut to `limit` characters."""
    text = str(text)
    if limit is not None and len(text) > limit:
        text = text[:limit] + '... (%d more characters)' % (len(text) - limit)
    text = _CONTROL.sub(lambda m: '\\x%02x' % ord(m.group()) if ord(m.group()) < 256
                        else '\\u%04x' % ord(m.group()), text)
    if one_line:
        text = _NEWLINE.sub(lambda m: '\\t' if m.group() == '\t' else '\\n', text)
    return text


FILE_LIMIT = 2000       # characters of one robot string in the .dat and JUnit files


def timestamp(t: Optional[float] = None) -> str:
    """The spec's time format: YYYY-MM-DD.HH:MM:SS (local time)."""
    dt = datetime.datetime.fromtimestamp(t) if t is not None else datetime.datetime.now()
    return dt.strftime('%Y-%m-%d.%H:%M:%S')


@dataclass(frozen=True)
class Drift:
    """One measured value that moved beyond its margin since the baseline run (outputs/drift.py):
    a warning on the sensor, never a failure."""
    measure: str            # the drift table's key, e.g. 'level_rearLeft', 'rate'
    label: str              # 'rearLeft level'
    unit: str               # 'dBFS', 'Hz', ...
    then: Optional[float] = None     # the baseline run's value
    now: Optional[float] = None      # this run's value
    change: str = ''        # '12 dB quieter'
    margin: str = ''        # the margin it went beyond, in words: '6 dB'
    text: str = ''          # the whole warning, as SensorResult.warnings holds it


@dataclass(frozen=True)
class FramePlacement:
    """Where a sensor's data sits on the robot (sensors/frames.py): its messages' frame looked
    up in /tf into `target` at their own stamps."""
    frame_id: str = ''
    target: str = ''
    judged: int = 0             # stamps looked up
    placed: int = 0             # of which tf2 could transform
    # the frames tf2 walked from frame_id to target (placed), or the walk up to the first
    # missing link (never placed)
    chain: List[str] = field(default_factory=list)
    missing_above: str = ''     # never placed: the highest frame reached, nothing above it
    worst_gap_s: Optional[float] = None     # the largest extrapolation tf2 refused (s; + future)


@dataclass
class SensorResult:
    name: str
    title: str
    topic: Optional[str]
    msg_type: str
    verdict: Verdict
    reasons: List[str] = field(default_factory=list)      # why it failed / was skipped
    warnings: List[str] = field(default_factory=list)     # reported, do not fail
    notes: List[str] = field(default_factory=list)        # information
    messages: int = 0
    rate_hz: Optional[float] = None
    stamp_rate_hz: Optional[float] = None
    expected_rate_hz: Optional[List[float]] = None
    nominal_rate_hz: Optional[float] = None
    received_type: Optional[str] = None
    window_s: float = 0.0
    stopped_because: str = ''
    started_at: Optional[float] = None   # seconds since the run's start
    ended_at: Optional[float] = None
    fields: List[List[str]] = field(default_factory=list)  # first message, the spec's fields
    # the stream's numbers (stats.StreamStats.summary); None: not listened (written as {})
    stats: Optional[StreamSummary] = None
    # what the family's check measured: its frozen values dataclass (sensors/values/<family>.py,
    # the row's `values` in sensors/families.py), None when nothing was measured
    values: Optional[Any] = None
    artifacts: Dict = field(default_factory=dict)
    family: str = ''                     # the check family (sensors/families.py), '' when unknown
    rate_series: Optional[List[Tuple[float, float]]] = None   # messages per second over the window
    drift: List[Drift] = field(default_factory=list)   # values beyond their margin since the baseline
    # its frame in the robot's transform tree (sensors/frames.py); None: not judged
    frame: Optional[FramePlacement] = None

    @property
    def ok(self) -> bool:
        return self.verdict != FAIL


@dataclass
class RunResult:
    platform: str
    mode: str
    start: float
    end: Optional[float] = None
    interrupted: bool = False
    interrupt_reason: str = ''
    output_dir: str = ''
    run_id: str = ''
    source: str = 'live'                 # 'live' or the bag's path
    files: Dict = field(default_factory=dict)
    options: Dict = field(default_factory=dict)
    sensors: List[SensorResult] = field(default_factory=list)
    write_errors: List[str] = field(default_factory=list)   # results files that could not be written
    param_sources: Dict = field(default_factory=dict)        # option -> where its ROS param came from
    # the run compared with (outputs/baseline.py): run_id, start, path; {} when none
    baseline: Dict = field(default_factory=dict)
    # the robot's serial number (naoqi_driver's info topic, sources/identity.py), '' when
    # unknown; robot_info: its other values, or {'unknown': why}
    robot: str = ''
    robot_info: Dict = field(default_factory=dict)

    @property
    def exit_code(self) -> int:
        if self.write_errors:
            return EXIT_NOT_WRITTEN
        if self.interrupted:
            return EXIT_INTERRUPTED
        if any(s.verdict == FAIL for s in self.sensors):
            return EXIT_FAIL
        if any(s.verdict == NOT_JUDGED for s in self.sensors):
            return EXIT_NOT_JUDGED
        return EXIT_PASS if all(s.ok for s in self.sensors) else EXIT_FAIL

    def counts(self) -> Dict[Verdict, int]:
        """Sensors per verdict; NOT JUDGED only when a sensor has it (the JSON's summary as before)."""
        out = {PASS: 0, FAIL: 0, SKIPPED: 0, INTERRUPTED: 0}
        for s in self.sensors:
            out[s.verdict] = out.get(s.verdict, 0) + 1
        return out

    def to_dict(self, with_series: bool = False) -> Dict[str, Any]:
        sensors = [sensor_dict(s, with_series) for s in self.sensors]
        return {
            'schema_version': SCHEMA_VERSION,
            'tool': 'pepper_interface_tests/sensorTest',
            'run_id': self.run_id,
            'platform': self.platform,
            'mode': self.mode,
            'source': self.source,
            'start': timestamp(self.start),
            'end': timestamp(self.end) if self.end else None,
            'start_unix': round(self.start, 3),
            'end_unix': round(self.end, 3) if self.end else None,
            'interrupted': self.interrupted,
            'interrupt_reason': self.interrupt_reason,
            'exit_code': self.exit_code,
            'write_errors': list(self.write_errors),
            'summary': self.counts(),
            'output_dir': self.output_dir,
            'files': self.files,
            'options': self.options,
            'param_sources': self.param_sources,
            'baseline': self.baseline or None,
            'robot': self.robot or None,
            'robot_info': self.robot_info or None,
            'sensors': sensors,
        }


_APART = ('stats', 'values', 'family', 'rate_series')    # written by sensor_dict itself


def sensor_dict(s: SensorResult, with_series: bool = False) -> Dict[str, Any]:
    """One sensor of the JSON: its fields in order, the family after msg_type, its values
    dataclass as "values" (and, `with_series`, its plot data and rate_hz as "series")."""
    d: Dict[str, Any] = {}
    for f in fields(s):
        if f.name not in _APART:
            d[f.name] = codec.to_json(getattr(s, f.name))
        if f.name == 'msg_type':
            d['family'] = s.family
        elif f.name == 'stats':
            d['stats'] = codec.to_json(s.stats) if s.stats is not None else {}
            values, plots = codec.split(s.values) if s.values is not None else ({}, {})
            d['values'] = values
            if with_series:
                if s.rate_series is not None:
                    plots['rate_hz'] = codec.to_json(s.rate_series)
                d['series'] = plots
    return d


def param_lines(run: RunResult) -> List[str]:
    """Where options given as ROS params came from (for the run header)."""
    return ['%s = %s from the %s' % (k, printable(run.options.get(k), 200), printable(v, 200))
            for k, v in sorted(run.param_sources.items())]


def robot_line(run: RunResult) -> str:
    """The run header's robot line: its identity, or why it is unknown ('' for the simulator)."""
    if run.robot:
        info = run.robot_info or {}
        parts = [str(info.get('body_type') or ''), 'base %s' % info['base_version'] if info.get('base_version') else '',
                 'head %s' % info['head_id'] if info.get('head_id') else '']
        more = ', '.join(x for x in parts if x)
        return 'robot %s%s' % (printable(run.robot, 200), ' (%s)' % printable(more, 200) if more else '')
    why = (run.robot_info or {}).get('unknown')
    return ('robot identity unknown: %s; a baseline is not checked for being this robot\'s' % printable(why, 300)
            if why else '')


def frame_line(r: SensorResult) -> str:
    """Where the sensor's data sits on the robot ('' when its frame was not judged): the chain
    tf2 walked to the target, or the missing link (sensors/frames.py)."""
    f = r.frame
    if f is None or not f.judged:
        return ''
    if f.placed == 0:
        return 'frame %s: no path to %s (/tf has nothing above %s)' % (
            printable(f.frame_id, 200), f.target, printable(f.missing_above or f.frame_id, 200))
    chain = ' -> '.join(printable(x, 200) for x in f.chain) or printable(f.frame_id, 200)
    return 'frame %s: placed at %d of %d stamps' % (chain, f.placed, f.judged)


def count_line(c: Dict[Verdict, int]) -> str:
    text = '%d passed, %d failed, %d skipped' % (c[PASS], c[FAIL], c[SKIPPED])
    text += ', %d not judged (the PC was too busy)' % c[NOT_JUDGED] if c.get(NOT_JUDGED) else ''
    return text + (', %d interrupted' % c[INTERRUPTED] if c.get(INTERRUPTED) else '')


def summary_line(r: SensorResult) -> str:
    parts = ['%d messages in %.1f s' % (r.messages, r.window_s)]
    if r.rate_hz is not None:
        rate = 'rate %.2f Hz' % r.rate_hz
        if r.stamp_rate_hz is not None:
            rate += ' (header stamps %.2f Hz)' % r.stamp_rate_hz
        if r.expected_rate_hz:
            rate += ', expected %g-%g Hz' % tuple(r.expected_rate_hz)
        parts.append(rate)
    delay = r.stats.delay_s if r.stats is not None else None
    if delay is not None and delay.mean is not None and delay.max is not None:
        parts.append('delay %.3f s mean, %.3f s max' % (delay.mean, delay.max))
    if r.stopped_because:
        parts.append('stopped: ' + r.stopped_because)
    return ', '.join(parts)


# ------------------------------------------------------------------ a run's JSON read back

PASSING = (PASS, SKIPPED)   # any other verdict (FAIL, INTERRUPTED, ...) did not pass


def not_passed(run: RunResult) -> List[str]:
    """Names of a run's sensors that did not pass, in run order (`sensorTestHistory failed`,
    `sensorTest --rerun-failed`)."""
    return [s.name for s in run.sensors if s.verdict not in PASSING]


ValuesOf = Callable[[str], Optional[Type[Any]]]     # family -> its values dataclass


def read_run(data: Dict[str, Any], values_of: Optional[ValuesOf] = None,
             family_of: Optional[Callable[[str], str]] = None) -> RunResult:
    """A run's JSON (as `RunResult.to_dict` wrote it, now or in an earlier version; checked by
    `malformed` first) read back into a RunResult. A sensor's values are read into its family's
    dataclass (`values_of`; without it, or when they do not fit, they are left out); a JSON
    written before the family was recorded names it by `family_of(sensor name)`."""
    run = RunResult(platform=_text(data.get('platform')), mode=_text(data.get('mode')),
                    start=_num(data.get('start_unix'), 0.0), end=_num(data.get('end_unix'), None),
                    interrupted=data.get('interrupted') is True,
                    interrupt_reason=_text(data.get('interrupt_reason')),
                    output_dir=_text(data.get('output_dir')), run_id=_text(data.get('run_id')),
                    source=_text(data.get('source')) or 'live', files=_dict(data.get('files')),
                    options=_dict(data.get('options')), write_errors=_texts(data.get('write_errors')),
                    param_sources=_dict(data.get('param_sources')),
                    baseline=_dict(data.get('baseline')), robot=_text(data.get('robot')),
                    robot_info=_dict(data.get('robot_info')))
    for s in data.get('sensors') or []:
        run.sensors.append(_read_sensor(s, values_of, family_of))
    return run


def _read_sensor(s, values_of, family_of):
    verdict = s.get('verdict')
    family = s.get('family') if isinstance(s.get('family'), str) else \
        (family_of(s['name']) if family_of is not None else '')
    r = SensorResult(
        name=s['name'], title=_text(s.get('title')), topic=s.get('topic') if isinstance(s.get('topic'), str) else None,
        msg_type=_text(s.get('msg_type')), verdict=Verdict(verdict) if verdict in _VERDICTS else verdict,
        reasons=_texts(s.get('reasons')), warnings=_texts(s.get('warnings')), notes=_texts(s.get('notes')),
        messages=int(_num(s.get('messages'), 0)), rate_hz=_num(s.get('rate_hz'), None),
        stamp_rate_hz=_num(s.get('stamp_rate_hz'), None),
        expected_rate_hz=s.get('expected_rate_hz') if _is_pair(s.get('expected_rate_hz')) else None,
        nominal_rate_hz=_num(s.get('nominal_rate_hz'), None),
        received_type=s.get('received_type') if isinstance(s.get('received_type'), str) else None,
        window_s=_num(s.get('window_s'), 0.0), stopped_because=_text(s.get('stopped_because')),
        started_at=_num(s.get('started_at'), None), ended_at=_num(s.get('ended_at'), None),
        fields=[[str(x) for x in f] for f in s.get('fields') or [] if isinstance(f, list)],
        stats=_read_stats(s.get('stats')), artifacts=_dict(s.get('artifacts')), family=family or '')
    cls = values_of(r.family) if values_of is not None and r.family else None
    if cls is not None:
        try:
            r.values = codec.join(cls, s.get('values'), s.get('series'))
        except codec.CodecError:
            r.values = None          # values of another version that do not fit: the verdict stays
    if isinstance(s.get('frame'), dict):
        try:
            r.frame = codec.from_json(FramePlacement, s['frame'])
        except codec.CodecError:
            pass                 # a frame of another version: its reason stays in reasons
    for d in s.get('drift') if isinstance(s.get('drift'), list) else []:
        try:
            r.drift.append(codec.from_json(Drift, d))
        except codec.CodecError:
            pass                 # a drift of another version: its warning stays in warnings
    series = s.get('series')
    if isinstance(series, dict) and isinstance(series.get('rate_hz'), list):
        r.rate_series = [(float(p[0]), float(p[1])) for p in series['rate_hz']
                         if isinstance(p, list) and len(p) == 2 and all(_is_number(x) for x in p)]
    return r


_VERDICTS = {v.value for v in Verdict}


def _read_stats(v: Any) -> Optional[StreamSummary]:
    """A sensor's "stats" read back; None when empty (not listened) or not a StreamSummary."""
    if not isinstance(v, dict) or not v:
        return None
    try:
        return codec.from_json(StreamSummary, v)
    except codec.CodecError:
        return None             # stats of another version that do not fit: the verdict stays


def _text(v: Any) -> str:
    return v if isinstance(v, str) else ''


def _texts(v: Any) -> List[str]:
    return [x for x in v if isinstance(x, str)] if isinstance(v, list) else []


def _dict(v: Any) -> Dict:
    return v if isinstance(v, dict) else {}


def _num(v, default):
    return v if _is_number(v) else default


def _is_pair(v):
    return isinstance(v, list) and len(v) == 2 and all(_is_number(x) for x in v)


def _is_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def malformed(data: Any) -> str:
    """Why a run's JSON cannot be listed or compared ('' when it can): every field `list` and
    `compare` read must have the type sensorTest writes (a hand-edited or truncated-and-repaired
    file, or one from another tool, must not give a traceback)."""
    if not isinstance(data, dict):
        return 'not a JSON object'
    for key in ('start', 'platform', 'mode', 'source'):
        if data.get(key) is not None and not isinstance(data[key], str):
            return '"%s" is not a text' % key
    summary = data.get('summary')
    if summary is not None and not (isinstance(summary, dict) and all(_is_number(v) for v in summary.values())):
        return '"summary" is not a table of counts'
    sensors = data.get('sensors', [])
    if not isinstance(sensors, list):
        return '"sensors" is not a list'
    for i, s in enumerate(sensors, 1):
        if not isinstance(s, dict) or not isinstance(s.get('name'), str) \
                or not isinstance(s.get('verdict'), str):
            return 'sensor %d has no name or verdict' % i
        if s.get('rate_hz') is not None and not _is_number(s['rate_hz']):
            return 'sensor %s: rate_hz is not a number' % s['name']
        reasons = s.get('reasons')
        if reasons is not None and not (isinstance(reasons, list) and all(isinstance(r, str) for r in reasons)):
            return 'sensor %s: reasons is not a list of texts' % s['name']
    return ''
