"""The results files: sensorTestOutput.dat (the spec's text file, appended block by block),
sensorTestResults.json and sensorTestResults.xml (JUnit), rendered from results.RunResult.

JSON and JUnit are written whole by atomicfile.write_atomic (a temporary file, fsync and a
rename; the temporary file is removed when writing fails, e.g. on a full disk, and the error
names the file). Robot strings pass through results.printable first; JUnit gets the same before
xml.etree.ElementTree escapes it, so the XML always parses.
"""
import errno
import fcntl
import json
import os
from typing import Any, Dict, Optional
from xml.etree import ElementTree as ET

from ..results import (
    FAIL,
    FILE_LIMIT,
    INTERRUPTED,
    NOT_JUDGED,
    SKIPPED,
    RunResult,
    SensorResult,
    count_line,
    frame_line,
    param_lines,
    printable,
    robot_line,
    summary_line,
    timestamp,
)
from .atomicfile import write_atomic

# ------------------------------------------------------------------ sensorTestOutput.dat

class OutputFile:
    """The spec's appended text file, written block by block as sensors finish.

    Each block is one write(2) to a file opened O_APPEND, under an exclusive fcntl lock: two runs
    appending to one file never tear each other's blocks. Write errors (ENOSPC, ...) raise
    OSError; the caller names the file."""

    def __init__(self, path: str) -> None:
        self.path = path
        self._fd: Optional[int] = os.open(path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o666)

    def _write(self, text: str) -> None:
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

    def write_text(self, text: str) -> None:
        """Append `text` (e.g. a whole run's section) in one locked write."""
        self._write(text)

    def begin(self, run: RunResult) -> None:
        self._write(dat_begin(run))

    def sensor(self, r: SensorResult) -> None:
        self._write(dat_block(r))

    def end(self, run: RunResult) -> None:
        self._write(dat_end(run))

    def close(self) -> None:
        if self._fd is not None:
            os.close(self._fd)
            self._fd = None


def dat_begin(run: RunResult) -> str:
    return ('[TESTING] ############ SENSORS ############\n\n[START TIME] %s\n'
            '[RUN] platform %s, mode %s, source %s%s\n'
            % (timestamp(run.start), run.platform, run.mode, printable(run.source, FILE_LIMIT),
               (', run id ' + run.run_id) if run.run_id else '')
            + ''.join('[RUN] ROS param %s\n' % line for line in param_lines(run))
            + ''.join('[RUN] %s\n' % line for line in [robot_line(run)] if line) + '\n')




def dat_block(r: SensorResult) -> str:
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
        lines += ['[FRAME] ' + line for line in [frame_line(r)] if line]
        for kind, name in r.artifacts.items():
            lines.append('[FILE] %s: %s' % (kind, p(name)))
        lines += ['[WARNING] ' + p(w) for w in r.warnings]
    lines.append('[RESULT] %s%s' % (r.verdict, (': ' + p('; '.join(r.reasons))) if r.reasons else ''))
    return '\n'.join(lines) + '\n\n'




def dat_end(run: RunResult) -> str:
    text = ''
    if run.interrupted:
        text += '[INTERRUPTED] %s\n' % printable(run.interrupt_reason or 'run interrupted', FILE_LIMIT)
    text += '[SUMMARY] %s\n' % count_line(run.counts())
    return text + '[END TIME] %s\n\n' % timestamp(run.end)




# ------------------------------------------------------------------ JSON and JUnit

def write_json(run: RunResult, path: str) -> None:
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


def junit_text(run: RunResult) -> str:
    """JUnit XML (built with xml.etree.ElementTree, which escapes &, <, > and quotes).
    INTERRUPTED sensors are <skipped> (with what was measured in system-out): an interrupted
    window is no failure of the robot. Robot strings pass through `printable` first, so no
    character XML 1.0 forbids reaches the file and it always parses."""
    c = run.counts()
    total_time = (run.end or run.start) - run.start
    suite = ET.Element('testsuite', name='sensorTest', tests=str(len(run.sensors)),
                       failures=str(c[FAIL]), errors='0',
                       skipped=str(c[SKIPPED] + c[INTERRUPTED] + c.get(NOT_JUDGED, 0)), time='%.3f' % total_time)
    props = ET.SubElement(suite, 'properties')
    for k, v in (('platform', run.platform), ('mode', run.mode), ('source', run.source),
                 ('interrupted', str(run.interrupted).lower())) + ((('robot', run.robot),) if run.robot else ()):
        ET.SubElement(props, 'property', name=k, value=_xml(v))
    for s in run.sensors:
        case = ET.SubElement(suite, 'testcase', classname='pepper_interface_tests.sensorTest',
                             name=_xml(s.name), time='%.3f' % s.window_s)
        detail = _xml('\n'.join(['topic: %s' % s.topic, summary_line(s)] + s.notes
                                 + [line for line in [frame_line(s)] if line]
                                 + ['WARNING: ' + w for w in s.warnings]),
                      one_line=False)
        if s.verdict == FAIL:
            ET.SubElement(case, 'failure', message=_xml('; '.join(s.reasons))).text = detail
        elif s.verdict in (SKIPPED, INTERRUPTED, NOT_JUDGED):
            ET.SubElement(case, 'skipped', message=_xml('; '.join(s.reasons)))
            if s.verdict != SKIPPED:
                ET.SubElement(case, 'system-out').text = detail
        else:
            ET.SubElement(case, 'system-out').text = detail
    _indent(suite)
    return ('<?xml version="1.0" encoding="utf-8"?>\n'
            + ET.tostring(suite, encoding='unicode') + '\n')


def write_junit(run: RunResult, path: str) -> None:
    write_atomic(path, junit_text(run))


def load_json(path: str) -> Dict[str, Any]:
    with open(path, encoding='utf-8') as f:
        return json.load(f)
