"""One verdict model, rendered by every writer.

SensorResult / RunResult hold what a run found; writers turn them into the spec's output file
(sensorTestOutput.dat, appended), sensorTestResults.json and sensorTestResults.xml (JUnit).
JSON and JUnit are written whole by atomicfile.write_atomic (a temporary file, fsync and a
rename; the temporary file is removed when writing fails, e.g. on a full disk, and the error
names the file). Strings that came from
the robot (frame ids, type names, reasons quoting them) are made safe per output: `printable`
escapes control characters (no raw ANSI escape reaches a terminal or a text file) and bounds the
length; JUnit gets the same before xml.etree.ElementTree escapes it, so the XML always parses.
"""
import datetime
import errno
import fcntl
import json
import os
import re
from dataclasses import asdict, dataclass, field
from typing import Dict, List, Optional
from xml.etree import ElementTree as ET

from .atomicfile import write_atomic

PASS, FAIL, SKIPPED = 'PASS', 'FAIL', 'SKIPPED'
INTERRUPTED = 'INTERRUPTED'   # the window was cut short by an interrupt: not judged, not a failure
VERDICTS = (PASS, FAIL, SKIPPED, INTERRUPTED)
OUTPUT_FILE = 'sensorTestOutput.dat'
JSON_FILE = 'sensorTestResults.json'
JUNIT_FILE = 'sensorTestResults.xml'
SCHEMA_VERSION = 1

EXIT_PASS, EXIT_FAIL, EXIT_CANNOT_START, EXIT_INTERRUPTED = 0, 1, 2, 130
EXIT_NOT_WRITTEN = 3    # a results file could not be written (full disk, removed folder, ...)

# C0 controls but tab and newline, DEL, C1 controls, and what XML 1.0 cannot hold
_CONTROL = re.compile('[\x00-\x08\x0b-\x1f\x7f-\x9f\u2028\u2029\ud800-\udfff\ufffe\uffff]')
_NEWLINE = re.compile('[\t\n]')


def printable(text, limit=None, one_line=True):
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


def timestamp(t=None):
    """The spec's time format: YYYY-MM-DD.HH:MM:SS (local time)."""
    dt = datetime.datetime.fromtimestamp(t) if t is not None else datetime.datetime.now()
    return dt.strftime('%Y-%m-%d.%H:%M:%S')


@dataclass
class SensorResult:
    name: str
    title: str
    topic: Optional[str]
    msg_type: str
    verdict: str
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
    stats: Dict = field(default_factory=dict)
    values: Dict = field(default_factory=dict)
    series: Dict = field(default_factory=dict)
    artifacts: Dict = field(default_factory=dict)

    @property
    def ok(self):
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

    @property
    def exit_code(self):
        if self.write_errors:
            return EXIT_NOT_WRITTEN
        if self.interrupted:
            return EXIT_INTERRUPTED
        return EXIT_PASS if all(s.ok for s in self.sensors) else EXIT_FAIL

    def counts(self):
        out = {PASS: 0, FAIL: 0, SKIPPED: 0, INTERRUPTED: 0}
        for s in self.sensors:
            out[s.verdict] += 1
        return out

    def to_dict(self, with_series=False):
        sensors = []
        for s in self.sensors:
            d = asdict(s)
            if not with_series:
                d.pop('series')
            sensors.append(d)
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
            'sensors': sensors,
        }


# ------------------------------------------------------------------ sensorTestOutput.dat

class OutputFile:
    """The spec's appended text file, written block by block as sensors finish.

    Each block is one write(2) to a file opened O_APPEND, under an exclusive fcntl lock: two runs
    appending to one file never tear each other's blocks. Write errors (ENOSPC, ...) raise
    OSError; the caller names the file."""

    def __init__(self, path):
        self.path = path
        self._fd: Optional[int] = os.open(path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o666)

    def _write(self, text):
        data = text.encode('utf-8', 'backslashreplace')
        fd = self._fd
        if fd is None:
            raise OSError(errno.EBADF, 'written after close', self.path)
        fcntl.flock(fd, fcntl.LOCK_EX)
        try:
            while data:
                n = os.write(fd, data)
                data = data[n:]
        finally:
            fcntl.flock(fd, fcntl.LOCK_UN)

    def write_text(self, text):
        """Append `text` (e.g. a whole run's section) in one locked write."""
        self._write(text)

    def begin(self, run):
        self._write(dat_begin(run))

    def sensor(self, r):
        self._write(dat_block(r))

    def end(self, run):
        self._write(dat_end(run))

    def close(self):
        if self._fd is not None:
            os.close(self._fd)
            self._fd = None


def dat_begin(run):
    return ('[TESTING] ############ SENSORS ############\n\n[START TIME] %s\n'
            '[RUN] platform %s, mode %s, source %s%s\n'
            % (timestamp(run.start), run.platform, run.mode, printable(run.source, FILE_LIMIT),
               (', run id ' + run.run_id) if run.run_id else '')
            + ''.join('[RUN] ROS param %s\n' % line for line in param_lines(run)) + '\n')


def param_lines(run):
    """Where options given as ROS params came from (for the run header)."""
    return ['%s = %s from the %s' % (k, printable(run.options.get(k), 200), printable(v, 200))
            for k, v in sorted(run.param_sources.items())]


def dat_block(r):
    """One sensor's block of sensorTestOutput.dat; robot strings escaped, one per line."""
    def p(text):
        return printable(text, FILE_LIMIT)
    lines = ['[TESTING] ---- %s ----' % r.title]
    if r.verdict != SKIPPED:
        lines.append('[TOPIC] %s (%s)' % (r.topic, r.msg_type))
    if r.fields:
        lines.append('[MESSAGES] Printing %s data received.' % r.title.lower())
        lines += ['%s: %s' % (p(k), p(v)) for k, v in r.fields]
        lines.append('[END MESSAGES] Finished printing.')
    if r.verdict != SKIPPED:
        lines.append('[SUMMARY] ' + p(summary_line(r)))
        lines += ['[SUMMARY] ' + p(n) for n in r.notes]
        for kind, name in r.artifacts.items():
            lines.append('[FILE] %s: %s' % (kind, p(name)))
        lines += ['[WARNING] ' + p(w) for w in r.warnings]
    lines.append('[RESULT] %s%s' % (r.verdict, (': ' + p('; '.join(r.reasons))) if r.reasons else ''))
    return '\n'.join(lines) + '\n\n'


def count_line(c):
    text = '%d passed, %d failed, %d skipped' % (c[PASS], c[FAIL], c[SKIPPED])
    return text + (', %d interrupted' % c[INTERRUPTED] if c.get(INTERRUPTED) else '')


def dat_end(run):
    text = ''
    if run.interrupted:
        text += '[INTERRUPTED] %s\n' % printable(run.interrupt_reason or 'run interrupted', FILE_LIMIT)
    text += '[SUMMARY] %s\n' % count_line(run.counts())
    return text + '[END TIME] %s\n\n' % timestamp(run.end)


def summary_line(r):
    parts = ['%d messages in %.1f s' % (r.messages, r.window_s)]
    if r.rate_hz is not None:
        rate = 'rate %.2f Hz' % r.rate_hz
        if r.stamp_rate_hz is not None:
            rate += ' (header stamps %.2f Hz)' % r.stamp_rate_hz
        if r.expected_rate_hz:
            rate += ', expected %g-%g Hz' % tuple(r.expected_rate_hz)
        parts.append(rate)
    delay = (r.stats or {}).get('delay_s')
    if delay:
        parts.append('delay %.3f s mean, %.3f s max' % (delay['mean'], delay['max']))
    if r.stopped_because:
        parts.append('stopped: ' + r.stopped_because)
    return ', '.join(parts)


# ------------------------------------------------------------------ JSON and JUnit

def write_json(run, path):
    write_atomic(path, json.dumps(run.to_dict(), indent=2, default=str) + '\n')


def _xml(text, one_line=True):
    """A robot string fit for XML 1.0: controls escaped by `printable`, bounded length."""
    return printable(text, FILE_LIMIT, one_line=one_line)


def _indent(elem, level=0):
    """Two-space indentation (ET.indent is Python 3.9+; Noetic's Ubuntu 20.04 has 3.8)."""
    pad = '\n' + '  ' * level
    if len(elem):
        if not (elem.text or '').strip():
            elem.text = pad + '  '
        for child in elem:
            _indent(child, level + 1)
        if not (child.tail or '').strip():
            child.tail = pad
    if level and not (elem.tail or '').strip():
        elem.tail = pad


def junit_text(run):
    """JUnit XML (built with xml.etree.ElementTree, which escapes &, <, > and quotes).
    INTERRUPTED sensors are <skipped> (with what was measured in system-out): an interrupted
    window is no failure of the robot. Robot strings pass through `printable` first, so no
    character XML 1.0 forbids reaches the file and it always parses."""
    c = run.counts()
    total_time = (run.end or run.start) - run.start
    suite = ET.Element('testsuite', name='sensorTest', tests=str(len(run.sensors)),
                       failures=str(c[FAIL]), errors='0',
                       skipped=str(c[SKIPPED] + c[INTERRUPTED]), time='%.3f' % total_time)
    props = ET.SubElement(suite, 'properties')
    for k, v in (('platform', run.platform), ('mode', run.mode), ('source', run.source),
                 ('interrupted', str(run.interrupted).lower())):
        ET.SubElement(props, 'property', name=k, value=_xml(v))
    for s in run.sensors:
        case = ET.SubElement(suite, 'testcase', classname='pepper_interface_tests.sensorTest',
                             name=_xml(s.name), time='%.3f' % s.window_s)
        detail = _xml('\n'.join(['topic: %s' % s.topic, summary_line(s)] + s.notes
                                 + ['WARNING: ' + w for w in s.warnings]),
                      one_line=False)
        if s.verdict == FAIL:
            ET.SubElement(case, 'failure', message=_xml('; '.join(s.reasons))).text = detail
        elif s.verdict in (SKIPPED, INTERRUPTED):
            ET.SubElement(case, 'skipped', message=_xml('; '.join(s.reasons)))
            if s.verdict == INTERRUPTED:
                ET.SubElement(case, 'system-out').text = detail
        else:
            ET.SubElement(case, 'system-out').text = detail
    _indent(suite)
    return ('<?xml version="1.0" encoding="utf-8"?>\n'
            + ET.tostring(suite, encoding='unicode') + '\n')


def write_junit(run, path):
    write_atomic(path, junit_text(run))


def load_json(path):
    with open(path, encoding='utf-8') as f:
        return json.load(f)
