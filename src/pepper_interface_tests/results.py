"""One verdict model, rendered by every writer.

SensorResult / RunResult hold what a run found; writers turn them into the spec's output file
(sensorTestOutput.dat, appended), sensorTestResults.json and sensorTestResults.xml (JUnit).
JSON and JUnit are written whole (a temporary file and a rename; the temporary file is removed
when writing fails, e.g. on a full disk, and the error names the file). Strings that came from
the robot (frame ids, type names, reasons quoting them) are made safe per output: `printable`
escapes control characters (no raw ANSI escape reaches a terminal or a text file) and bounds the
length; JUnit gets the same, so the XML always parses.
"""
import datetime
import fcntl
import json
import os
import re
import tempfile
from dataclasses import asdict, dataclass, field
from typing import Dict, List, Optional
from xml.sax.saxutils import escape, quoteattr

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
        self._fd = os.open(path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o666)

    def _write(self, text):
        data = text.encode('utf-8', 'backslashreplace')
        fcntl.flock(self._fd, fcntl.LOCK_EX)
        try:
            while data:
                n = os.write(self._fd, data)
                data = data[n:]
        finally:
            fcntl.flock(self._fd, fcntl.LOCK_UN)

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

def _atomic_write(path, text):
    """Write `text` to `path` whole (temporary file, rename). On any error the temporary file
    is removed and OSError is raised with `path` as its filename."""
    folder = os.path.dirname(path) or '.'
    fd, tmp = tempfile.mkstemp(prefix='.tmp-', dir=folder)
    try:
        with os.fdopen(fd, 'w', encoding='utf-8', errors='backslashreplace') as f:
            f.write(text)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)   # mkstemp creates 0600; results are ordinary files
        os.replace(tmp, path)
    except OSError as e:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise OSError(e.errno, e.strerror, path) from e


def write_json(run, path):
    _atomic_write(path, json.dumps(run.to_dict(), indent=2, default=str) + '\n')


def _xml_text(text):
    return escape(printable(text, FILE_LIMIT, one_line=False))


def _xml_attr(text):
    return quoteattr(printable(text, FILE_LIMIT))


def junit_text(run):
    """JUnit XML. INTERRUPTED sensors are <skipped> (with what was measured in system-out):
    an interrupted window is no failure of the robot. Robot strings pass through `printable`."""
    c = run.counts()
    total_time = (run.end or run.start) - run.start
    out = ['<?xml version="1.0" encoding="utf-8"?>',
           '<testsuite name="sensorTest" tests="%d" failures="%d" errors="0" skipped="%d" time="%.3f">'
           % (len(run.sensors), c[FAIL], c[SKIPPED] + c[INTERRUPTED], total_time)]
    out.append('  <properties>')
    for k, v in (('platform', run.platform), ('mode', run.mode), ('source', run.source),
                 ('interrupted', str(run.interrupted).lower())):
        out.append('    <property name=%s value=%s/>' % (quoteattr(k), _xml_attr(v)))
    out.append('  </properties>')
    for s in run.sensors:
        head = '  <testcase classname="pepper_interface_tests.sensorTest" name=%s time="%.3f"' % (
            quoteattr(s.name), s.window_s)
        detail = '\n'.join(['topic: %s' % s.topic, summary_line(s)] + s.notes
                           + ['WARNING: ' + w for w in s.warnings])
        if s.verdict == FAIL:
            out.append(head + '>')
            out.append('    <failure message=%s>%s</failure>' % (_xml_attr('; '.join(s.reasons)),
                                                                  _xml_text(detail)))
            out.append('  </testcase>')
        elif s.verdict in (SKIPPED, INTERRUPTED):
            out.append(head + '>')
            out.append('    <skipped message=%s/>' % _xml_attr('; '.join(s.reasons)))
            if s.verdict == INTERRUPTED:
                out.append('    <system-out>%s</system-out>' % _xml_text(detail))
            out.append('  </testcase>')
        else:
            out.append(head + '>')
            out.append('    <system-out>%s</system-out>' % _xml_text(detail))
            out.append('  </testcase>')
    out.append('</testsuite>')
    return '\n'.join(out) + '\n'


def write_junit(run, path):
    _atomic_write(path, junit_text(run))


def load_json(path):
    with open(path, encoding='utf-8') as f:
        return json.load(f)
