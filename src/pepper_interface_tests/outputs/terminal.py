"""What the terminal shows: a line when each sensor starts and ends, live progress during the
windows (one rewritten line on a terminal, a plain line every few seconds otherwise), and a
summary table at the end (coloured on a terminal, plain text when not).

Strings from the robot go through results.printable: control characters (ANSI escapes) are
shown escaped and each reason is cut to REASON_LIMIT characters. A broken stdout or stderr
(`| head` that exited, `| tee` killed by the same Ctrl-C, a closed ssh session) never stops the
run: see protect_std_streams."""
import argparse
import os
import shutil
import sys
import textwrap
from typing import TYPE_CHECKING, Any, List, Optional, Sequence, TextIO

from ..observer import RunObserver, no_publisher_at_all
from ..plan import catalog
from ..progress import Progress
from ..results import (
    EXIT_NOT_JUDGED,
    FAIL,
    INTERRUPTED,
    NOT_JUDGED,
    PASS,
    SKIPPED,
    RunResult,
    SensorResult,
    Verdict,
    count_line,
    param_lines,
    printable,
    robot_line,
)
from ..sensors.families import traits
from ..sources import Graph, ros1_graph

if TYPE_CHECKING:
    from ..plan.settings import TestPlan

COLOURS = {PASS: '\033[32m', FAIL: '\033[31m', SKIPPED: '\033[33m', INTERRUPTED: '\033[35m',
           NOT_JUDGED: '\033[35m'}
RESET, BOLD = '\033[0m', '\033[1m'
REASON_LIMIT = 300      # characters of one reason on the terminal; the files keep more
# The summary table: its verdict column as wide as the longest verdict of the run, at least
# VERDICT_WIDTH ("PASS*", "FAIL"; "NOT JUDGED" and "INTERRUPTED" widen it); reasons start at
# column table_fixed(width)
VERDICT_WIDTH = 8
MIN_REASON_COLUMN = 36  # narrower than this (a terminal under 104 columns): one block per sensor


def row_format(verdict_width: int = VERDICT_WIDTH) -> str:
    return '%%-22s %%-%ds %%8s %%10s %%13s  %%s' % verdict_width


ROW = row_format()
TABLE_FIXED = len(ROW % ('', '', '', '', '', ''))   # with the narrowest verdict column


def table_fixed(verdict_width: int) -> int:
    """The column the reasons start at, with a verdict column `verdict_width` wide."""
    return TABLE_FIXED + max(0, verdict_width - VERDICT_WIDTH)


class SafeStream:
    """Wraps sys.stdout / sys.stderr: once a write fails (EPIPE, EIO, ...), the stream is
    pointed at /dev/null and every later write is dropped silently, so that the results files
    are still written and the interpreter's final flush cannot fail either."""

    def __init__(self, stream: TextIO) -> None:
        self._stream = stream
        self.broken = False

    def _broke(self) -> None:
        self.broken = True
        try:
            fd = self._stream.fileno()
            null = os.open(os.devnull, os.O_WRONLY)
            os.dup2(null, fd)
            os.close(null)
        except (OSError, ValueError, AttributeError):
            pass

    def write(self, text: str) -> int:
        if self.broken:
            return len(text)
        try:
            return self._stream.write(text)
        except (OSError, ValueError):
            self._broke()
            return len(text)

    def flush(self) -> None:
        if self.broken:
            return
        try:
            self._stream.flush()
        except (OSError, ValueError):
            self._broke()

    def isatty(self) -> bool:
        try:
            return not self.broken and self._stream.isatty()
        except (OSError, ValueError):
            return False

    def __getattr__(self, name: str) -> Any:
        return getattr(self._stream, name)


def protect_std_streams() -> None:
    """Make sys.stdout and sys.stderr SafeStreams (once)."""
    for name in ('stdout', 'stderr'):
        stream = getattr(sys, name)
        if stream is not None and not isinstance(stream, SafeStream):
            setattr(sys, name, SafeStream(stream))


def _reasons(texts: Sequence[str]) -> str:
    return '; '.join(printable(t, REASON_LIMIT) for t in texts)


class HelpFormatter(argparse.RawDescriptionHelpFormatter):
    """--help of every program: the description's and epilog's own line breaks are kept (one
    example per line), and a line wider than the terminal wraps, continued under itself. The
    section of options is titled "options" on every Python (3.10 renamed argparse's "optional
    arguments" so, bpo-9694)."""

    def start_section(self, heading: Optional[str]) -> None:
        super().start_section('options' if heading == 'optional arguments' else heading)

    def _fill_text(self, text: str, width: int, indent: str) -> str:
        lines = []
        for line in text.splitlines():
            lead = ' ' * (len(line) - len(line.lstrip(' ')))
            lines.append(textwrap.fill(line, width, initial_indent=indent,
                                       subsequent_indent=indent + lead + '  ', break_long_words=False,
                                       break_on_hyphens=False) if line.strip() else '')
        return '\n'.join(lines)


def columns(fallback: int = 120, minimum: int = 20) -> int:
    """Usable columns: $COLUMNS, else the width of the terminal on stdout, else of the one on
    stderr (`sensorTest | tee run.log` in a terminal: the lines still fit the screen they are
    read on), else `fallback` (a pipe or a file with no terminal at all); one column is kept
    free so that no line makes the terminal wrap; never under `minimum`."""
    width = shutil.get_terminal_size((0, 0)).columns
    if not width:
        try:
            width = os.get_terminal_size(sys.__stderr__.fileno()).columns if sys.__stderr__ else 0
        except (OSError, ValueError):   # stderr is not a terminal, or closed
            width = 0
    return max(minimum, (width or fallback) - 1)


def fill(text: str, width: Optional[int] = None, indent: str = '  ',
         keep: Sequence[str] = ()) -> str:
    """`text` broken at spaces into lines of at most `width` columns (default: columns()), the
    later ones indented: a path, or any word too long for a line, is never cut but stands alone
    on its own line. The phrases in `keep` ("(1.1 MB, 5.5 s)") are not broken either."""
    glue = '\x00'
    for phrase in keep:
        text = text.replace(phrase, phrase.replace(' ', glue))
    return textwrap.fill(text, width or columns(minimum=40), subsequent_indent=indent,
                         break_long_words=False, break_on_hyphens=False).replace(glue, ' ')


def under_roslaunch(argv: Optional[Sequence[str]] = None) -> bool:
    """roslaunch starts nodes with __log:= (and __name:=); their stdout is shared with every
    other node's log lines, so no carriage-return tricks there even on a terminal."""
    return any(a.startswith('__log:=') for a in (sys.argv if argv is None else argv))


def _fit(text: str, width: int) -> str:
    return text if len(text) <= width else text[:max(0, width - 3)] + '...'


def _troubled(p: Progress) -> bool:
    """A running sensor with a provisional problem (wrong type, bad header, its check's
    failures so far): the same question /diagnostics asks (diagnostics.live_status)."""
    return p.wrong_type or bool(p.problems)


def progress_text(runs: Sequence[Progress], now: float, failed_done: Sequence[str] = (),
                  width: int = 79) -> str:
    """One line that stays readable at 80 columns: time left once, then for several sensors
    the counts receiving / silent / failing so far and the names of the silent and failing
    ones (`failed_done`: sensors that already ended with FAIL)."""
    left = max(r.left for r in runs)
    if len(runs) == 1 and not failed_done:
        r = runs[0]
        return _fit('  ... %s: %.0f s left, %d %s' % (r.name, left, r.count,
                                                     'sent' if r.drives_itself else 'msgs'), width)
    silent, failing, receiving = [], list(failed_done), 0
    for r in runs:
        if _troubled(r):
            failing.append(r.name)
        elif not r.drives_itself and r.received == 0 and r.periodic:   # events: silence is normal
            silent.append(r.name)
        else:
            receiving += 1
    text = '  ... %.0f s left: %d receiving, %d silent' % (left, receiving, len(silent))
    if silent:
        text += ' (%s)' % ', '.join(silent)
    text += ', %d failing' % len(failing)
    if failing:
        text += ' (%s)' % ', '.join(failing)
    return _fit(text, width)


class Terminal(RunObserver):
    def __init__(self, stream: Optional[TextIO] = None, plain_every: float = 5.0) -> None:
        self.out = stream or sys.stdout
        self.tty = (self.out.isatty() and os.environ.get('TERM') != 'dumb'
                    and not under_roslaunch())
        self.colour = self.tty and 'NO_COLOR' not in os.environ
        self.plain_every = plain_every
        self._last_plain: Optional[float] = None
        self._last_tty = 0.0
        self._status_shown = False
        self._failed: List[str] = []       # sensors that ended with FAIL, for the progress line
        self._said_once: Optional[str] = None   # a reason every sensor shares, said once already

    def _paint(self, text: str, verdict: Verdict) -> str:
        return COLOURS[verdict] + text + RESET if self.colour else text

    def _clear(self) -> None:
        if self._status_shown:
            self.out.write('\r\033[K')
            self._status_shown = False

    def line(self, text: str = '') -> None:
        self._clear()
        self.out.write(text + '\n')
        self.out.flush()

    # ------------------------------------------------------------------ observer methods
    def run_started(self, run: RunResult, plan: 'TestPlan') -> None:
        n = len(plan.sensors)
        width = columns()
        self.line(textwrap.fill(
                  'sensorTest: %d sensor%s on the %s (%s mode, %s), results in %s'
                  % (n, '' if n == 1 else 's', 'simulator' if plan.platform == 'simulator'
                     else ('robot' if run.source == 'live' else 'bag ' + run.source),
                     plan.mode, 'quick' if plan.quick else '%g s each' % round(plan.duration, 1),
                     plan.output_dir), max(40, width), subsequent_indent='  ',
                  break_long_words=False, break_on_hyphens=False))
        for text in param_lines(run):
            self.line('  ROS param ' + text)
        width = max(40, width)
        said = robot_line(run)
        if said:
            self.line(textwrap.fill(said, width, initial_indent='  ', subsequent_indent=' ' * 4,
                                    break_long_words=False, break_on_hyphens=False))
        for note in plan.notes:      # what is left out and why; windows other than --duration
            self.line(textwrap.fill(note, width, initial_indent='  note: ', subsequent_indent=' ' * 8))

    def sensor_started(self, progress: Progress) -> None:
        p = progress
        if p.drives_itself:
            text = '  start  %-22s publishing on %s' % (p.name, p.topic)
        else:
            text = '  start  %-22s listening on %s for %g s' % (p.name, p.topic, round(p.window, 1))
        for part in textwrap.wrap(text, columns(), subsequent_indent=' ' * 9) or [text]:
            self.line(part)

    def sensor_done(self, result: SensorResult) -> None:
        if result.verdict == FAIL:
            self._failed.append(result.name)
        text = '  %-6s %-22s' % (FAIL if result.verdict == FAIL else result.verdict.lower(), result.name)
        if result.verdict == SKIPPED:
            text += ' skipped: ' + _reasons(result.reasons)
        else:
            text += ' %d msgs' % result.messages
            if result.rate_hz is not None:
                text += ', %.2f Hz' % result.rate_hz
            if result.reasons:
                text += ': ' + _reasons(self._unsaid(result.reasons))
        for part in textwrap.wrap(text, columns(), subsequent_indent=' ' * 9,
                                  break_on_hyphens=False) or [text]:
            self.line(self._paint(part, result.verdict))

    def nothing_published(self, topics: List[str], waited: float, graph: Optional[Graph]) -> None:
        """Said once, at the start, instead of once per silent sensor (runner._nothing_published)."""
        graph = graph or ros1_graph('')
        text = ('nothing is published: not one of the %d sensor topics of this run has a publisher '
                '%s%s after %g s. Likely causes: the robot is off or unreachable; %s; '
                'naoqi_driver (or the emulator) is not started; the topics file names other '
                'topics (--platform, --topics). Every listened-to sensor FAILs for this reason.'
                % (len(topics), graph.place, graph.address, waited, graph.other_cause))
        self._said_once = ': ' + no_publisher_at_all(graph)
        self.line(self._paint(textwrap.fill(text, columns(), initial_indent='sensorTest: ',
                                            subsequent_indent='  '), FAIL))

    def tick(self, progress: Sequence[Progress], now: float) -> None:
        if not progress:
            return
        if self.tty:
            if now - self._last_tty < 0.5:
                return
            self._last_tty = now
            if any(p.asking for p in progress):
                return    # a person is asked a question (--move's Enter): it stands alone on the screen
            self.out.write('\r\033[K' + progress_text(progress, now, self._failed, columns(100)))
            self.out.flush()
            self._status_shown = True
        else:
            if self._last_plain is None:
                self._last_plain = now
            if now - self._last_plain >= self.plain_every and not any(p.asking for p in progress):
                self._last_plain = now
                self.line(progress_text(progress, now, self._failed, columns()))

    def run_ended(self, run: RunResult) -> None:
        self._clear()
        self.line()
        width = columns()
        if run.interrupted:
            for i, text in enumerate(textwrap.wrap('INTERRUPTED: %s' % printable(
                    run.interrupt_reason, REASON_LIMIT), width)):
                self.line(text if not i else '  ' + text)
        self._headlines(run, width)
        verdict_width = max([VERDICT_WIDTH] + [len(self._verdict_cell(r)) for r in run.sensors])
        if width - table_fixed(verdict_width) >= MIN_REASON_COLUMN:
            self._table(run, width, verdict_width)
        else:
            self._blocks(run, width, verdict_width)
        self._drift(run, width)
        c = run.counts()
        warned = sum(1 for r in run.sensors if r.verdict == PASS and r.warnings)
        self.line()
        if warned:
            self.line('PASS* = passed with %d warning%s to read (not a failure)'
                      % (warned, '' if warned == 1 else 's'))
        self.line(count_line(c))
        unjudged = [r.name for r in run.sensors if r.verdict == NOT_JUDGED]
        if unjudged:
            for text in textwrap.wrap(
                    'This run could not judge everything: this PC was too busy to judge %s (each row names '
                    'the load and sensorTest\'s own lag); no sensor is faulted for it. Test again when the PC '
                    'is quieter (exit code %d).' % (', '.join(unjudged), EXIT_NOT_JUDGED), width):
                self.line(text)

    def _headlines(self, run: RunResult, width: int) -> None:
        """Above the table: the sensors whose state explains the others' (Traits.headline: the
        robot's health), with their figures, and in capitals when they warn or fail."""
        for r in run.sensors:
            sensor = catalog.SENSORS.get(r.name)
            if sensor is None or r.verdict not in (PASS, FAIL) or not traits(sensor).headline:
                continue
            bad = r.verdict == FAIL or bool(r.warnings)
            state = FAIL if r.verdict == FAIL else 'WARN' if r.warnings else 'OK'
            head = '%s %s: ' % (r.title if bad else r.name, state)
            text = head + '; '.join([printable(t, REASON_LIMIT) for t in r.reasons + r.warnings + r.notes])
            for i, part in enumerate(textwrap.wrap(text, width, subsequent_indent='    ',
                                                   break_on_hyphens=False)):
                self.line(self._paint(part, FAIL if r.verdict == FAIL else SKIPPED if bad else PASS)
                          if i == 0 else part)
            self.line()

    def _drift(self, run: RunResult, width: int) -> None:
        """Under the table, when the run was compared with a baseline (outputs/baseline.py):
        every value that drifted beyond its margin, sensor by sensor, or that none did."""
        if not run.baseline:
            return
        drifted = [r for r in run.sensors if r.drift]
        self.line()
        base = 'the baseline run %s' % printable(run.baseline.get('run_id'), 80)
        if not drifted:
            self.line('no drift since %s' % base)
            return
        count = sum(len(r.drift) for r in drifted)
        for part in textwrap.wrap('drift since %s (%d value%s, warnings, not failures):'
                                  % (base, count, '' if count == 1 else 's'), width, subsequent_indent='  '):
            self.line(part)
        for r in drifted:
            for d in r.drift:
                for part in textwrap.wrap('%s: %s' % (r.name, printable(d.text, REASON_LIMIT)), width,
                                          initial_indent='  ', subsequent_indent='      ',
                                          break_on_hyphens=False):
                    self.line(part)

    def _verdict_cell(self, r: SensorResult) -> str:
        """The verdict column's text: a PASS that carries warnings reads "PASS*" at a glance
        (legend under the table)."""
        return r.verdict + ('*' if r.verdict == PASS and r.warnings else '')

    def _unsaid(self, reasons: Sequence[str]) -> List[str]:
        """The reasons without what the terminal already said once for every sensor."""
        said = self._said_once
        return [r.replace(said, '') for r in reasons] if said else list(reasons)

    def _summary_reasons(self, r: SensorResult) -> str:
        drifted = {d.text for d in r.drift}      # said in full under the table (_drift)
        warnings = [w for w in r.warnings if w not in drifted]
        if drifted:
            warnings.append('drifted since the baseline: %s (below)' % ', '.join(d.label for d in r.drift))
        return _reasons(self._unsaid(r.reasons)) or ('warning: ' + _reasons(warnings) if warnings else '')

    def _table(self, run: RunResult, width: int, verdict_width: int = VERDICT_WIDTH) -> None:
        """One row per sensor, reasons wrapped inside their own column."""
        fmt, fixed = row_format(verdict_width), table_fixed(verdict_width)
        header = fmt % ('sensor', 'verdict', 'messages', 'rate Hz', 'expected Hz', 'reasons')
        self.line(BOLD + header.rstrip() + RESET if self.colour else header.rstrip())
        for r in run.sensors:
            rate = '%.2f' % r.rate_hz if r.rate_hz is not None else '-'
            band = '%g-%g' % tuple(r.expected_rate_hz) if r.expected_rate_hz else '-'
            wrapped = textwrap.wrap(self._summary_reasons(r), width - fixed,
                                    break_on_hyphens=False) or ['']
            row = fmt % (r.name, self._verdict_cell(r), r.messages, rate, band, wrapped[0])
            self.line(self._paint(row.rstrip(), r.verdict))
            for more in wrapped[1:]:
                self.line(' ' * fixed + more)

    def _blocks(self, run: RunResult, width: int, verdict_width: int = VERDICT_WIDTH) -> None:
        """Narrow terminals: one block per sensor, its figures on the first line and its reasons
        wrapped below, indented, over the whole width."""
        for r in run.sensors:
            figures = '%d msgs' % r.messages
            if r.rate_hz is not None:
                figures += ', %.2f Hz' % r.rate_hz
            if r.expected_rate_hz:
                figures += ' (expected %g-%g)' % tuple(r.expected_rate_hz)
            head = textwrap.wrap('%-22s %-*s %s' % (r.name, verdict_width, self._verdict_cell(r), figures), width,
                                 subsequent_indent='    ')
            self.line(self._paint(head[0], r.verdict))
            for more in head[1:] + textwrap.wrap(self._summary_reasons(r), width,
                                                 initial_indent='    ', subsequent_indent='    ',
                                                 break_on_hyphens=False):
                self.line(more)
