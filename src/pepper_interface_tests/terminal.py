"""What the terminal shows: a line when each sensor starts and ends, live progress during the
windows (one rewritten line on a terminal, a plain line every few seconds otherwise), and a
summary table at the end (coloured on a terminal, plain text when not).

Strings from the robot go through results.printable: control characters (ANSI escapes) are
shown escaped and each reason is cut to REASON_LIMIT characters. A broken stdout or stderr
(`| head` that exited, `| tee` killed by the same Ctrl-C, a closed ssh session) never stops the
run: see protect_std_streams."""
import os
import shutil
import sys
import textwrap

from .results import FAIL, INTERRUPTED, PASS, SKIPPED, count_line, param_lines, printable

COLOURS = {PASS: '\033[32m', FAIL: '\033[31m', SKIPPED: '\033[33m', INTERRUPTED: '\033[35m'}
RESET, BOLD = '\033[0m', '\033[1m'
REASON_LIMIT = 300      # characters of one reason on the terminal; the files keep more


class SafeStream:
    """Wraps sys.stdout / sys.stderr: once a write fails (EPIPE, EIO, ...), the stream is
    pointed at /dev/null and every later write is dropped silently, so that the results files
    are still written and the interpreter's final flush cannot fail either."""

    def __init__(self, stream):
        self._stream = stream
        self.broken = False

    def _broke(self):
        self.broken = True
        try:
            fd = self._stream.fileno()
            null = os.open(os.devnull, os.O_WRONLY)
            os.dup2(null, fd)
            os.close(null)
        except (OSError, ValueError, AttributeError):
            pass

    def write(self, text):
        if self.broken:
            return len(text)
        try:
            return self._stream.write(text)
        except (OSError, ValueError):
            self._broke()
            return len(text)

    def flush(self):
        if self.broken:
            return
        try:
            self._stream.flush()
        except (OSError, ValueError):
            self._broke()

    def isatty(self):
        try:
            return not self.broken and self._stream.isatty()
        except (OSError, ValueError):
            return False

    def __getattr__(self, name):
        return getattr(self._stream, name)


def protect_std_streams():
    """Make sys.stdout and sys.stderr SafeStreams (once)."""
    for name in ('stdout', 'stderr'):
        stream = getattr(sys, name)
        if stream is not None and not isinstance(stream, SafeStream):
            setattr(sys, name, SafeStream(stream))


def _reasons(texts):
    return '; '.join(printable(t, REASON_LIMIT) for t in texts)


class Terminal:
    def __init__(self, stream=None, plain_every=5.0):
        self.out = stream or sys.stdout
        self.tty = self.out.isatty() and os.environ.get('TERM') != 'dumb'
        self.colour = self.tty and 'NO_COLOR' not in os.environ
        self.plain_every = plain_every
        self._last_plain = None
        self._last_tty = 0.0
        self._status_shown = False
        self.plan = None

    def _paint(self, text, verdict):
        return COLOURS[verdict] + text + RESET if self.colour else text

    def _clear(self):
        if self._status_shown:
            self.out.write('\r\033[K')
            self._status_shown = False

    def line(self, text=''):
        self._clear()
        self.out.write(text + '\n')
        self.out.flush()

    # ------------------------------------------------------------------ observer methods
    def run_started(self, run, plan):
        self.plan = plan
        n = len(plan.sensors)
        self.line('sensorTest: %d sensor%s on the %s (%s mode, %s), results in %s'
                  % (n, '' if n == 1 else 's', 'simulator' if plan.platform == 'simulator'
                     else ('robot' if run.source == 'live' else 'bag ' + run.source),
                     plan.mode, 'quick' if plan.quick else '%g s each' % round(plan.duration, 1),
                     plan.output_dir))
        for text in param_lines(run):
            self.line('  ROS param ' + text)
        width = max(40, shutil.get_terminal_size((80, 20)).columns - 1)
        for note in plan.notes:      # what is left out and why; windows other than --duration
            self.line(textwrap.fill(note, width, initial_indent='  note: ', subsequent_indent=' ' * 8))

    def sensor_started(self, sensor_run):
        p = sensor_run.plan
        if sensor_run.check.active:
            self.line('  start  %-22s publishing on %s' % (p.name, p.topic))
        else:
            self.line('  start  %-22s listening on %s for %g s' % (p.name, p.topic, round(sensor_run.window, 1)))

    def sensor_done(self, r):
        text = '  %-6s %-22s' % (r.verdict.lower() if r.verdict != FAIL else 'FAIL', r.name)
        if r.verdict == SKIPPED:
            text += ' skipped: ' + _reasons(r.reasons)
        else:
            text += ' %d msgs' % r.messages
            if r.rate_hz is not None:
                text += ', %.2f Hz' % r.rate_hz
            if r.reasons:
                text += ': ' + _reasons(r.reasons)
        self.line(self._paint(text, r.verdict))

    def tick(self, runs, now):
        if not runs:
            return
        if self.tty:
            if now - self._last_tty < 0.2:
                return
            self._last_tty = now
            parts = ['%s %.0f s left, %d msgs' % (r.plan.name, max(0.0, r.window - (now - r.t0)),
                                                   r.stats.count) for r in runs]
            width = shutil.get_terminal_size((100, 20)).columns - 1
            text = '  ... ' + ' | '.join(parts)
            self.out.write('\r\033[K' + text[:width])
            self.out.flush()
            self._status_shown = True
        else:
            if self._last_plain is None:
                self._last_plain = now
            if now - self._last_plain >= self.plain_every:
                self._last_plain = now
                self.line('  ... ' + ', '.join('%s %d msgs, %.0f s left' % (
                    r.plan.name, r.stats.count, max(0.0, r.window - (now - r.t0))) for r in runs))

    def run_ended(self, run):
        self._clear()
        self.line()
        if run.interrupted:
            self.line('INTERRUPTED: %s' % printable(run.interrupt_reason, REASON_LIMIT))
        header = '%-22s %-8s %8s %10s %13s  %s' % ('sensor', 'verdict', 'messages', 'rate Hz',
                                                   'expected Hz', 'reasons')
        self.line(BOLD + header + RESET if self.colour else header)
        width = max(60, shutil.get_terminal_size((120, 20)).columns - 68)
        for r in run.sensors:
            rate = '%.2f' % r.rate_hz if r.rate_hz is not None else '-'
            band = '%g-%g' % tuple(r.expected_rate_hz) if r.expected_rate_hz else '-'
            reasons = _reasons(r.reasons) or ('warning: ' + _reasons(r.warnings) if r.warnings else '')
            wrapped = textwrap.wrap(reasons, width) or ['']
            # a PASS that carries warnings reads "PASS*" at a glance (legend under the table)
            verdict = r.verdict + ('*' if r.verdict == PASS and r.warnings else '')
            row = '%-22s %-8s %8d %10s %13s  %s' % (r.name, verdict, r.messages, rate, band, wrapped[0])
            self.line(self._paint(row, r.verdict))
            for more in wrapped[1:]:
                self.line(' ' * 68 + more)
        c = run.counts()
        warned = sum(1 for r in run.sensors if r.verdict == PASS and r.warnings)
        self.line()
        if warned:
            self.line('PASS* = passed with %d warning%s to read (not a failure)'
                      % (warned, '' if warned == 1 else 's'))
        self.line(count_line(c))
