"""Watch a running launch while a command runs: a node of it that ends mid-run is named at once,
with its own last words, and the run's outcome says the launch broke (tools/demo.sh).

    python -m pepper_interface_tests.launch.watch ROSLAUNCH_PID ROSLAUNCH_OUTPUT -- COMMAND ...

The demo starts the emulator's launch, waits until it is up (rosmaster.wait_for_launch), then runs
sensorTest through this. A node of the emulator that ends while sensorTest listens (the audio
bridge losing its port, a crash, a kill) leaves sensorTest judging a stream that stopped: its
verdict would blame a sensor for what the emulator did. So while COMMAND runs, the launch's
output is read every WATCH_EVERY s for roslaunch's own words about a process that ended, and
for roslaunch itself ending. roslaunch (Debian's python3-roslaunch 1.15.15) writes them in
pmon.py:563-572 ("[name-N] " + the exit description, or for a required node "REQUIRED process
[name-N] has died!" and the description on the next line) from nodeprocess.py:392-406
("process has died [pid P, exit code C, cmd ...]." / "process has died without exit code
[...]" / "process has finished cleanly", then "log file: <dir>/<name-N>*.log"). A node that
ends with exit code 0 mid-run broke the launch as much as one that crashed: a rospy node
stopped by SIGTERM exits 0. The first is printed at
once, with the node's last words:

- its own log files (the glob roslaunch names: rospy's log file from __log:=, and -stdout/-stderr
  with output="log"), the lines the node itself logged (not rospy's shutdown chatter);
- its lines in roslaunch's output (output="screen"): those the node prefixes with its own name
  ("naoqiAudio: ...", as the bridge's capture and the NAOqi endpoint do), and the exception line
  of a Python traceback printed just before roslaunch's report.

COMMAND keeps running (its other sensors' verdicts are whole, and its files are written); when it
ends, the break is said again, last, so it is what the person reads, and the exit code is
EXIT_BROKE (2): the verdicts of the sensors the dead node fed say nothing about a robot.
Otherwise the exit code is COMMAND's. Ctrl-C reaches COMMAND (same terminal); this watcher then
waits for it to write its files.
"""
import glob
import os
import re
import shutil
import signal
import subprocess
import sys
import textwrap
import time
from dataclasses import dataclass, field
from typing import IO, List, Optional, Sequence

WATCH_EVERY = 0.3      # s between two reads of the launch's output
EXIT_BROKE = 2         # the launch broke during the run (sensorTest's "could not run" code)
WORDS = 3              # last words shown per node
WIDTH = 300            # characters kept of one line of them
TRACEBACK_BACK = 60    # lines before roslaunch's report searched for a traceback

_ANSI = re.compile(r'\x1b\[[0-9;]*[A-Za-z]')
_ENDED = re.compile(
    r'(?:\[(?P<name>[^\]\s]+)\] |REQUIRED process \[(?P<required>[^\]\s]+)\] has died!\n)'
    r'process has (?P<how>died|finished cleanly)'
    r'(?: without exit code| \[pid \d+, exit code (?P<code>-?\d+))?[^\n]*'
    r'(?:\nlog file: (?P<log>[^\n]+))?')
# rospy's own loggers in a node's log file: its start-up and shutdown, not the node's words
_ROSPY_CHATTER = re.compile(r'^\[(rospy|rosgraph|xmlrpc|tcpros)[\w.]*\]')
# what the node itself logged (rospy.loginfo, logerr ...): "[rosout][ERROR] 2026-11-27 03:11:16,359: text"
_ROSOUT_LINE = re.compile(r'^\[rosout\]\[(\w+)\] [\d-]+ [\d:,]+: ')


@dataclass
class NodeEnd:
    """One process of the launch that ended, as roslaunch reported it."""
    process: str                 # roslaunch's process name, e.g. naoqiAudio-5
    code: Optional[int]          # exit code (negative: killed by that signal), None if unknown
    log_glob: str                # roslaunch's "log file:" glob, '' when it gave none
    at: int                      # offset of roslaunch's report in its output
    words: List[str] = field(default_factory=list)

    @property
    def node(self) -> str:
        return re.sub(r'-\d+$', '', self.process)

    def how(self) -> str:
        if self.code is None:
            return 'died'
        if self.code == 0:
            return 'ended (exit code 0) in the middle of the run'
        if self.code < 0:
            try:
                name = signal.Signals(-self.code).name
            except ValueError:
                name = 'signal %d' % -self.code
            return 'died (killed by %s)' % name
        return 'died (exit code %d)' % self.code


def plain(text: str) -> str:
    return _ANSI.sub('', text)


def ended_nodes(output: str) -> List[NodeEnd]:
    """The processes roslaunch reported as ended in its `output`, in order."""
    text = plain(output)
    ends = []
    for m in _ENDED.finditer(text):
        code = m.group('code')
        ends.append(NodeEnd(m.group('name') or m.group('required') or '?',
                            int(code) if code is not None else (0 if m.group('how') == 'finished cleanly'
                                                                else None),
                            (m.group('log') or '').strip(), m.start()))
    return ends


def _log_file_words(log_glob: str) -> List[str]:
    lines: List[str] = []
    for path in sorted(glob.glob(log_glob)) if log_glob else []:
        try:
            with open(path, 'rb') as f:
                text = f.read()[-65536:].decode('utf-8', 'replace')
        except OSError:
            continue
        lines += [_ROSOUT_LINE.sub(r'\1: ', ln.strip()) for ln in text.splitlines()
                  if ln.strip() and not _ROSPY_CHATTER.match(ln.strip())]
    return lines


def _screen_words(end: NodeEnd, output: str) -> List[str]:
    before = plain(output)[:end.at].splitlines()
    mine = [ln.strip() for ln in before if ln.startswith(end.node + ':')]
    # a Python traceback just before roslaunch's report: its last line is the exception
    recent = before[-TRACEBACK_BACK:]
    starts = [i for i, ln in enumerate(recent) if ln.startswith('Traceback (most recent call last)')]
    if starts:
        tail = [ln for ln in recent[starts[-1] + 1:] if ln.strip() and not ln.startswith(' ')]
        if tail:
            mine.append(tail[0].strip())
    return mine


def last_words(end: NodeEnd, output: str, limit: int = WORDS) -> List[str]:
    """The last `limit` lines the node itself said before it ended (module docstring)."""
    words = _log_file_words(end.log_glob) + _screen_words(end, output)
    return [w[:WIDTH] for w in words[-limit:]]


def _read(path: str) -> str:
    try:
        with open(path, 'rb') as f:
            return f.read().decode('utf-8', 'replace')
    except OSError:
        return ''


def _alive(pid: int) -> bool:
    try:
        with open('/proc/%d/stat' % pid) as f:
            return f.read().rsplit(')', 1)[1].split()[0] not in ('Z', 'X')
    except (OSError, IndexError):
        return False


class LaunchWatch:
    """What broke in a launch (roslaunch `pid`, its combined output in `log_path`) since now."""

    def __init__(self, pid: int, log_path: str) -> None:
        self.pid, self.log_path = pid, log_path
        self.seen = len(ended_nodes(_read(log_path)))   # ended before the run: not this run's
        self.broke: Optional[List[str]] = None

    def check(self) -> Optional[List[str]]:
        """None while the launch is whole; else the lines saying what broke (kept)."""
        if self.broke is not None:
            return self.broke
        output = _read(self.log_path)
        ends = ended_nodes(output)[self.seen:]
        if ends:
            first = ends[0]
            lines = ['%s %s' % (first.node, first.how())]
            words = last_words(first, output)
            if words:
                lines += ['  its last words: ' + words[0]] + ['    ' + w for w in words[1:]]
            else:
                lines.append('  (it said nothing before it ended)')
            others = sorted({e.node for e in ends[1:]} - {first.node})
            if others:
                lines.append('  then also ended: %s' % ', '.join(others))
            self.broke = lines
        elif not _alive(self.pid):
            self.broke = ['roslaunch (pid %d) ended, and with it every node of the launch' % self.pid]
        return self.broke


def say_broke(lines: List[str], log_path: str, out: IO[str], final: bool) -> None:
    """The break, in lines that fit the terminal (the launch's output path on a line of its own,
    never cut, so it can be copied)."""
    width = max(40, shutil.get_terminal_size((80, 24)).columns)

    def wrap(line: str) -> List[str]:
        indent = ' ' * (len(line) - len(line.lstrip()) + 2)
        return textwrap.wrap(line, width - 1, subsequent_indent=indent, break_on_hyphens=False) or ['']
    text = ['']
    for line in ['demo: the emulator broke during the run: ' + lines[0]] + lines[1:] + [
            '  the launch\'s whole output:']:
        text += wrap(line)
    text.append('  ' + log_path)
    if final:
        text += wrap('demo: the verdicts of the sensors it fed say nothing about a robot (exit %d)'
                     % EXIT_BROKE)
    out.write('\n'.join(text) + '\n')
    out.flush()


def run_watched(pid: int, log_path: str, command: Sequence[str], out: IO[str] = sys.stdout,
                every: float = WATCH_EVERY) -> int:
    """Run `command` while watching the launch; its exit code, or EXIT_BROKE when it broke."""
    watch = LaunchWatch(pid, log_path)
    proc = subprocess.Popen(list(command))
    # the terminal's Ctrl-C reaches the command too: it ends the run itself and writes its
    # files, and this watcher waits for that (set after the start: the command keeps SIGINT)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    said = False
    while True:
        try:
            code = proc.wait(every)
            break
        except subprocess.TimeoutExpired:
            pass
        if not said and watch.check() is not None:
            say_broke(watch.broke or [], log_path, out, final=False)
            said = True
    time.sleep(every)           # roslaunch reports a death within a moment of it
    broke = watch.check()
    if broke is None:
        return code
    say_broke(broke, log_path, out, final=True)
    return EXIT_BROKE


def main(argv: Optional[Sequence[str]] = None) -> int:
    args = list(sys.argv[1:] if argv is None else argv)
    if len(args) < 4 or args[2] != '--' or not args[0].isdigit():
        sys.stderr.write('usage: python -m pepper_interface_tests.launch.watch ROSLAUNCH_PID '
                         'ROSLAUNCH_OUTPUT -- COMMAND ...\n')
        return 2
    if not os.path.isfile(args[1]):
        sys.stderr.write('launch watch: no roslaunch output at %s\n' % args[1])
        return 2
    return run_watched(int(args[0]), args[1], args[3:])


if __name__ == '__main__':
    sys.exit(main())
