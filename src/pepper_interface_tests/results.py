"""One verdict model, rendered by every writer.

SensorResult / RunResult hold what a run found; writers turn them into the spec's output file
(sensorTestOutput.dat, appended), sensorTestResults.json and sensorTestResults.xml (JUnit).
Writers never raise on their way out of an interrupted run: each file is written whole
(JSON and JUnit through a temporary file and a rename).
"""
import datetime
import json
import os
import tempfile
from dataclasses import asdict, dataclass, field
from typing import Dict, List, Optional
from xml.sax.saxutils import escape, quoteattr

PASS, FAIL, SKIPPED = 'PASS', 'FAIL', 'SKIPPED'
OUTPUT_FILE = 'sensorTestOutput.dat'
JSON_FILE = 'sensorTestResults.json'
JUNIT_FILE = 'sensorTestResults.xml'
SCHEMA_VERSION = 1

EXIT_PASS, EXIT_FAIL, EXIT_CANNOT_START, EXIT_INTERRUPTED = 0, 1, 2, 130


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

    @property
    def exit_code(self):
        if self.interrupted:
            return EXIT_INTERRUPTED
        return EXIT_PASS if all(s.ok for s in self.sensors) else EXIT_FAIL

    def counts(self):
        out = {PASS: 0, FAIL: 0, SKIPPED: 0}
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
            'summary': self.counts(),
            'output_dir': self.output_dir,
            'files': self.files,
            'options': self.options,
            'sensors': sensors,
        }


# ------------------------------------------------------------------ sensorTestOutput.dat

class OutputFile:
    """The spec's appended text file, written block by block as sensors finish."""

    def __init__(self, path):
        self.path = path
        self._f = open(path, 'a', encoding='utf-8')

    def _write(self, text):
        self._f.write(text)
        self._f.flush()

    def begin(self, run):
        self._write('[TESTING] ############ SENSORS ############\n\n'
                    '[START TIME] %s\n' % timestamp(run.start))
        self._write('[RUN] platform %s, mode %s, source %s%s\n\n'
                    % (run.platform, run.mode, run.source,
                       (', run id ' + run.run_id) if run.run_id else ''))

    def sensor(self, r):
        lines = ['[TESTING] ---- %s ----' % r.title]
        if r.verdict != SKIPPED:
            lines.append('[TOPIC] %s (%s)' % (r.topic, r.msg_type))
        if r.fields:
            lines.append('[MESSAGES] Printing %s data received.' % r.title.lower())
            lines += ['%s: %s' % (k, v) for k, v in r.fields]
            lines.append('[END MESSAGES] Finished printing.')
        if r.verdict != SKIPPED:
            lines.append('[SUMMARY] ' + summary_line(r))
            lines += ['[SUMMARY] ' + n for n in r.notes]
            for kind, name in r.artifacts.items():
                lines.append('[FILE] %s: %s' % (kind, name))
            lines += ['[WARNING] ' + w for w in r.warnings]
        lines.append('[RESULT] %s%s' % (r.verdict, (': ' + '; '.join(r.reasons)) if r.reasons else ''))
        self._write('\n'.join(lines) + '\n\n')

    def end(self, run):
        if run.interrupted:
            self._write('[INTERRUPTED] %s\n' % (run.interrupt_reason or 'run interrupted'))
        c = run.counts()
        self._write('[SUMMARY] %d passed, %d failed, %d skipped\n' % (c[PASS], c[FAIL], c[SKIPPED]))
        self._write('[END TIME] %s\n\n' % timestamp(run.end))

    def close(self):
        if not self._f.closed:
            self._f.close()


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
    folder = os.path.dirname(path) or '.'
    fd, tmp = tempfile.mkstemp(prefix='.tmp-', dir=folder)
    with os.fdopen(fd, 'w', encoding='utf-8') as f:
        f.write(text)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)   # mkstemp creates 0600; results are ordinary files
    os.replace(tmp, path)


def write_json(run, path):
    _atomic_write(path, json.dumps(run.to_dict(), indent=2, default=str) + '\n')


def junit_text(run):
    c = run.counts()
    total_time = (run.end or run.start) - run.start
    out = ['<?xml version="1.0" encoding="utf-8"?>',
           '<testsuite name="sensorTest" tests="%d" failures="%d" errors="0" skipped="%d" time="%.3f">'
           % (len(run.sensors), c[FAIL], c[SKIPPED], total_time)]
    out.append('  <properties>')
    for k, v in (('platform', run.platform), ('mode', run.mode), ('source', run.source),
                 ('interrupted', str(run.interrupted).lower())):
        out.append('    <property name=%s value=%s/>' % (quoteattr(k), quoteattr(str(v))))
    out.append('  </properties>')
    for s in run.sensors:
        head = '  <testcase classname="pepper_interface_tests.sensorTest" name=%s time="%.3f"' % (
            quoteattr(s.name), s.window_s)
        detail = '\n'.join(['topic: %s' % s.topic, summary_line(s)] + s.notes + s.warnings)
        if s.verdict == FAIL:
            out.append(head + '>')
            out.append('    <failure message=%s>%s</failure>' % (quoteattr('; '.join(s.reasons)),
                                                                  escape(detail)))
            out.append('  </testcase>')
        elif s.verdict == SKIPPED:
            out.append(head + '>')
            out.append('    <skipped message=%s/>' % quoteattr('; '.join(s.reasons)))
            out.append('  </testcase>')
        else:
            out.append(head + '>')
            out.append('    <system-out>%s</system-out>' % escape(detail))
            out.append('  </testcase>')
    out.append('</testsuite>')
    return '\n'.join(out) + '\n'


def write_junit(run, path):
    _atomic_write(path, junit_text(run))


def load_json(path):
    with open(path, encoding='utf-8') as f:
        return json.load(f)
