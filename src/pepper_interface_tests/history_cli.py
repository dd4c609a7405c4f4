"""sensorTestHistory: the command line over the run history (history.py reads the runs).

    sensorTestHistory [--output-dir DIR] list [--json]
    sensorTestHistory [--output-dir DIR] compare [A] [B] [--threshold PERCENT] [--json]
    sensorTestHistory [--output-dir DIR] path [RUN]
    sensorTestHistory [--output-dir DIR] open [RUN] [--browser]
    sensorTestHistory [--output-dir DIR] failed [RUN]
    sensorTestHistory [--output-dir DIR] prune (--keep N | --days D) [--dry-run]
    sensorTestHistory [--output-dir DIR] baseline (set RUN | show | clear)

`--output-dir` may also come after the command. Text output fits the terminal's width (80
columns when it is not a terminal, or `COLUMNS`). Exit codes: 0 done; 1 `failed`: no sensor
failed, `prune`: a folder could not be deleted, `baseline show`: none pinned; 2 unknown run id, no runs, bad usage.
"""
import argparse
import json
import os
import shlex
import shutil
import subprocess
import sys
import textwrap
from typing import List, Optional, Sequence, TextIO

from . import results
from .outputs.history import (
    EXIT_OK,
    EXIT_USAGE,
    RATE_FLAG,
    RUNS_DIR,
    HistoryError,
    RunInfo,
    compare,
    list_runs,
    resolve,
)
from .outputs.history_format import format_compare, format_list, width
from .outputs.history_prune import prune
from .outputs.terminal import HelpFormatter
from .results import REPORT_FILE, not_passed

EXIT_NOTHING = 1


# ---------------------------------------------------------------- commands

def _note(text):
    sys.stderr.write('sensorTestHistory: note: %s\n' % text)


def _note_skipped(runs, since):
    """One note on stderr per incomplete run after `since` (all of them when None)."""
    later = runs if since is None else runs[runs.index(since) + 1:]
    for r in later:
        if not r.complete:
            _note('skipping run %s: %s' % (r.run_id, r.problem))


def cmd_compare(args: argparse.Namespace, runs: List[RunInfo], base: str, out: TextIO) -> int:
    # runs not named explicitly are the latest complete ones; incomplete runs (still going,
    # killed, malformed JSON) are skipped with a note
    complete = [r for r in runs if r.complete]
    if args.a is None:
        _note_skipped(runs, complete[-2] if len(complete) >= 2 else None)
        if len(complete) < 2:
            raise HistoryError('compare needs two runs; %s has %d complete%s'
                               % (os.path.join(base, RUNS_DIR), len(complete),
                                  ' (and %d incomplete)' % (len(runs) - len(complete))
                                  if len(runs) > len(complete) else ''))
        a, b = complete[-2], complete[-1]
    else:
        a = resolve(runs, args.a)
        if args.b is not None:
            b = resolve(runs, args.b)
        else:
            _note_skipped(runs, a)
            if not complete:
                raise HistoryError('no complete run to compare %s with' % a.run_id)
            b = complete[-1]
    threshold = args.threshold / 100.0
    rows = compare(a, b, threshold)
    if args.json:
        out.write(json.dumps({'a': a.run_id, 'b': b.run_id, 'threshold': threshold, 'sensors': rows},
                             indent=1) + '\n')
    else:
        out.write(format_compare(a, b, rows, threshold, width()))
    return EXIT_OK


def _run_or_latest(runs, ref, usable, what):
    """The run named by `ref`, or the latest run for which usable(run) holds (newer runs that
    do not qualify are skipped with a note)."""
    if ref is not None:
        run = resolve(runs, ref)
        why = usable(run)
        if why:
            raise HistoryError('run %s %s' % (run.run_id, why))
        return run
    if not runs:
        raise HistoryError('no runs recorded yet')
    for run in reversed(runs):
        why = usable(run)
        if not why:
            return run
        _note('skipping run %s: it %s' % (run.run_id, why))
    raise HistoryError('no run has %s' % what)


def cmd_baseline(args: argparse.Namespace, base: str, out: TextIO) -> int:
    """Pin, show or clear this robot's baseline run (outputs/baseline.py)."""
    from .outputs import baseline
    if args.action == 'set':
        if not args.run:
            raise HistoryError('baseline set needs a run: an id (sensorTestHistory list), a run '
                               'folder or its %s' % results.JSON_FILE)
        run = baseline.find(base, args.run)
        record = baseline.pin(base, run)
        out.write('\n'.join(textwrap.wrap('baseline: run %s (%s), pinned in %s' % (
            record['run_id'], (run.data or {}).get('start', '-'), os.path.join(base, baseline.POINTER)),
            width(), subsequent_indent='  ', break_on_hyphens=False)) + '\n')
        _note('every later sensorTest run in %s is compared with it (--no-baseline: not)' % base)
        return EXIT_OK
    if args.run:
        raise HistoryError('baseline %s takes no run' % args.action)
    if args.action == 'clear':
        if baseline.clear(base):
            out.write('baseline cleared in %s\n' % base)
        else:
            _note('no baseline was pinned in %s' % base)
        return EXIT_OK
    shown = baseline.pinned(base)
    if shown is None:
        out.write('no baseline pinned in %s (sensorTestHistory baseline set RUN pins one)\n' % base)
        return EXIT_NOTHING
    pinned_run, why = baseline.load_pinned(base)
    usable = why or (baseline.why_not(pinned_run) if pinned_run is not None else '')
    out.write('baseline: run %s, pinned %s\n  %s\n' % (shown.get('run_id'), shown.get('pinned_at', '-'),
                                                       shown.get('path')))
    if usable:
        out.write('  not used: %s\n' % usable)
    return EXIT_OK


def cmd_open(args: argparse.Namespace, runs: List[RunInfo], out: TextIO) -> int:
    def has_report(run):
        return '' if os.path.isfile(os.path.join(run.path, REPORT_FILE)) else \
            'has no %s (run with --no-report, still going, or killed)' % REPORT_FILE
    run = _run_or_latest(runs, args.run, has_report, 'an HTML report')
    path = os.path.join(run.path, REPORT_FILE)
    out.write(path + '\n')
    out.flush()
    if args.browser:
        display = os.environ.get('DISPLAY') or os.environ.get('WAYLAND_DISPLAY')
        opener = shutil.which('xdg-open')
        if not display:
            _note('no display (DISPLAY and WAYLAND_DISPLAY are unset): not opening a browser')
        elif not opener:
            _note('xdg-open is not installed (Debian: xdg-utils): open the path above in a browser')
        else:
            # detached and not waited for: the command never blocks, even when the browser
            # stays open or asks something on a terminal
            subprocess.Popen([opener, path], stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL, start_new_session=True, close_fds=True)
            _note('opening it with %s' % opener)
    return EXIT_OK


def cmd_failed(args: argparse.Namespace, runs: List[RunInfo], out: TextIO) -> int:
    run = _run_or_latest(runs, args.run, lambda r: '' if r.complete else 'cannot be read: ' + r.problem,
                         'a readable %s' % results.JSON_FILE)
    data = run.data or {}     # a complete run: its JSON was read
    failed = not_passed(run.result())
    if not failed:
        _note('no sensor failed in run %s: nothing to re-run' % run.run_id)
        return EXIT_NOTHING
    words = []
    if data.get('platform') == 'simulator':
        words += ['--platform', 'simulator']
    source = data.get('source')
    if source and source != 'live':
        words += ['--bag', source]
    words += ['--sensors', ','.join(failed)]
    out.write(' '.join(shlex.quote(w) for w in words) + '\n')
    _note('run %s: %d sensor%s to re-run: sensorTest $(sensorTestHistory failed)'
          % (run.run_id, len(failed), '' if len(failed) == 1 else 's'))
    return EXIT_OK


# ---------------------------------------------------------------- parser and main

class _Parser(argparse.ArgumentParser):
    def error(self, message):
        self.print_usage(sys.stderr)
        sys.stderr.write('%s: error: %s\n' % (self.prog, message))
        sys.exit(EXIT_USAGE)


def _non_negative_int(text):
    try:
        n = int(text)
    except ValueError:
        n = -1
    if n < 0:
        raise argparse.ArgumentTypeError('"%s" is not a whole number of runs (0 or more)' % text)
    return n


def _positive_days(text):
    try:
        d = float(text)
    except ValueError:
        d = -1.0
    if not 0 < d < float('inf'):
        raise argparse.ArgumentTypeError('"%s" is not a positive number of days' % text)
    return d


def build_parser() -> argparse.ArgumentParser:
    # --output-dir is accepted before and after the command: the copy in each command does not
    # overwrite the first one's value unless it is given (default SUPPRESS)
    where = _Parser(add_help=False)
    where.add_argument('--output-dir', metavar='DIR', default=argparse.SUPPRESS,
                       help='the output folder sensorTest wrote to (default: sensorTest\'s default)')
    p = _Parser(prog='sensorTestHistory', formatter_class=HelpFormatter,
                description='List, compare, open and prune past sensorTest runs kept in '
                            '<output dir>/runs/, and print the sensors that failed.',
                epilog='run ids: an exact id (20260121-091500), a unique prefix, "latest", or -1, -2, ...\n'
                       'exit codes: 0 done; 1 failed: no sensor failed, prune: a folder could not be '
                       'deleted, baseline show: none pinned; 2 unknown run id, no runs, or bad usage')
    p.add_argument('--output-dir', metavar='DIR', help='the output folder sensorTest wrote to '
                   '(default: sensorTest\'s default); also accepted after the command')
    sub = p.add_subparsers(dest='command', metavar='{list,compare,path,open,failed,prune,baseline}',
                           parser_class=_Parser)
    sub.required = True
    ls = sub.add_parser('list', parents=[where], help='list past runs, oldest first')
    ls.add_argument('--json', action='store_true', help='machine-readable output')
    cmp_ = sub.add_parser('compare', parents=[where],
                          help='sensors whose verdict or rate changed between two runs '
                               '(default: the last two; one id: that run vs the latest)')
    cmp_.add_argument('a', nargs='?', metavar='A')
    cmp_.add_argument('b', nargs='?', metavar='B')
    cmp_.add_argument('--threshold', type=float, default=100 * RATE_FLAG, metavar='PERCENT',
                      help='flag rate changes larger than this (default %(default)g %%)')
    cmp_.add_argument('--json', action='store_true', help='machine-readable output')
    path = sub.add_parser('path', parents=[where], help='print the folder of a run (default: the latest)')
    path.add_argument('run', nargs='?', default='latest')
    op = sub.add_parser('open', parents=[where],
                        help='print the path of a run\'s HTML report (default: the latest run that has one)')
    op.add_argument('run', nargs='?')
    op.add_argument('--browser', action='store_true',
                    help='also open it with xdg-open (never waits; does nothing without a display)')
    fl = sub.add_parser('failed', parents=[where],
                        help='print sensorTest options that re-run the sensors that did not pass in '
                             'a run (default: the latest complete run), e.g. --sensors laser,imu')
    fl.add_argument('run', nargs='?')
    pr = sub.add_parser('prune', parents=[where],
                        help='delete old run folders: keep the last N runs and/or those newer than '
                             'D days (both given: a run either keeps is kept)')
    pr.add_argument('--keep', type=_non_negative_int, metavar='N', help='keep the N newest runs')
    pr.add_argument('--days', type=_positive_days, metavar='D', help='keep runs newer than D days')
    pr.add_argument('--dry-run', action='store_true', help='say what would be deleted, delete nothing')
    bl = sub.add_parser('baseline', parents=[where],
                        help='this robot\'s baseline: "set RUN" pins a run where every sensor passed '
                             '(an id, a run folder or its sensorTestResults.json), every later run '
                             'is compared with it; "show" names it; "clear" unpins it')
    bl.add_argument('action', choices=('set', 'show', 'clear'),
                    help='set RUN: pin it (refused, with the reason, when a sensor failed in it, it '
                         'was interrupted or cannot be read); show: the pinned run; clear: unpin it')
    bl.add_argument('run', nargs='?', metavar='RUN',
                    help='for set: a run id (or a unique prefix, latest, -1, -2, ...), a run folder or '
                         'its sensorTestResults.json')
    return p


def main(argv: Optional[Sequence[str]] = None, out: Optional[TextIO] = None) -> int:
    out = out or sys.stdout
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command == 'prune' and args.keep is None and args.days is None:
        parser.error('prune needs --keep N (the N newest runs stay) or --days D (runs newer than '
                     'D days stay), e.g. prune --keep 10')
    if args.output_dir:
        base = os.path.abspath(os.path.expanduser(args.output_dir))
    else:
        from .plan.settings import default_output_dir
        base = default_output_dir()
    try:
        runs = list_runs(base)
        if args.command == 'list':
            if args.json:
                out.write(json.dumps([{'run_id': r.run_id, 'path': r.path, 'complete': r.complete,
                                       'problem': r.problem,
                                       'platform': (r.data or {}).get('platform'),
                                       'mode': (r.data or {}).get('mode'),
                                       'summary': (r.data or {}).get('summary'),
                                       'failed': [s['name'] for s in (r.data or {}).get('sensors', [])
                                                  if s.get('verdict') == results.FAIL]}
                                      for r in runs], indent=1) + '\n')
            else:
                out.write(format_list(runs, base))
            return EXIT_OK
        if args.command == 'path':
            out.write(resolve(runs, args.run).path + '\n')
            return EXIT_OK
        if args.command == 'open':
            return cmd_open(args, runs, out)
        if args.command == 'failed':
            return cmd_failed(args, runs, out)
        if args.command == 'baseline':
            return cmd_baseline(args, base, out)
        if args.command == 'prune':
            return prune(runs, base, args.keep, args.days, args.dry_run, out, width())
        return cmd_compare(args, runs, base, out)
    except HistoryError as e:
        sys.stderr.write('sensorTestHistory: error: %s\n' % e)
        return EXIT_USAGE
