"""sensorTestHistory prune: delete old run folders under <output_dir>/runs.

A run is deleted only when every rule lets it go:
- `--keep N`: the N newest runs stay (by run id, i.e. start time);
- `--days D`: runs that started less than D days ago stay (age from the run id);
  with both options a run either of them keeps is kept;
- the run whose files are published in the output folder (the "latest" files, named by
  <output_dir>/.sensorTestLatest.json) stays, and the output says so when a rule would have
  deleted it;
- a run folder without a readable JSON whose files changed in the last STILL_GOING seconds may
  be a run still going: it stays, with a line saying why;
- a folder whose name is not a run id is not sensorTest's: it stays, with a line saying why.
`--dry-run` prints the same lines with "would delete" and deletes nothing.
"""
import os
import shutil
import textwrap
import time
from typing import List, Optional, Sequence, TextIO, Tuple

from .history import EXIT_OK, ID_FORMAT, RunInfo, read_manifest

STILL_GOING = 600.0      # s; a full sequential run writes a file at least every 40 s
EXIT_PARTIAL = 1


def run_start(run_id: str) -> Optional[float]:
    """Seconds since the epoch of a run id's start (local time), or None when it is no run id."""
    try:
        return time.mktime(time.strptime(run_id[:15], ID_FORMAT))
    except (ValueError, OverflowError):
        return None


def _folder_size_and_mtime(path: str) -> Tuple[int, float]:
    size, newest = 0, 0.0
    for root, _, names in os.walk(path):
        for name in names:
            try:
                st = os.lstat(os.path.join(root, name))
            except OSError:
                continue
            size += st.st_size
            newest = max(newest, st.st_mtime)
    try:
        newest = max(newest, os.stat(path).st_mtime)
    except OSError:
        pass
    return size, newest


def _published_run(base: str) -> Optional[str]:
    """The run id whose files the output folder holds, or None."""
    run_id = read_manifest(base).get('run_id')
    return run_id if isinstance(run_id, str) else None


def _mb(size: float) -> str:
    return '%.1f MB' % (size / 1e6)


def decide(runs: Sequence[RunInfo], base: str, keep: Optional[int] = None, days: Optional[float] = None,
           now: Optional[float] = None) -> List[Tuple[RunInfo, bool, str, int, bool]]:
    """[(run, delete, why, size, by_rule)] for every run, oldest first; by_rule: kept by --keep
    or --days themselves (not worth a line of its own)."""
    now = time.time() if now is None else now
    published = _published_run(base)
    ours = [r for r in runs if run_start(r.run_id) is not None]
    newest = {r.run_id for r in ours[max(0, len(ours) - keep):]} if keep else set()
    out = []
    for r in runs:
        size, mtime = _folder_size_and_mtime(r.path)
        start = run_start(r.run_id)
        if start is None:
            out.append((r, False, 'kept: not a run id (not a folder sensorTest made)', size, False))
            continue
        age_days = (now - start) / 86400.0
        if keep and r.run_id in newest:
            out.append((r, False, 'kept: one of the %d newest runs' % keep, size, True))
            continue
        if days is not None and age_days < days:
            out.append((r, False, 'kept: %.1f days old (newer than %g days)' % (age_days, days), size, True))
            continue
        if r.run_id == published:
            out.append((r, False, 'kept: the output folder\'s latest files (report, JSON, videos) '
                                  'are this run\'s; delete it by hand if you mean to', size, False))
            continue
        if not r.complete and now - mtime < STILL_GOING:
            out.append((r, False, 'kept: no results yet and files changed %.0f s ago (may still be '
                                  'going)' % (now - mtime), size, False))
            continue
        rule = 'not one of the %d newest runs' % keep if keep is not None else ''
        if days is not None:
            rule += ('; ' if rule else '') + '%.1f days old' % age_days
        out.append((r, True, rule, size, False))
    return out


def _line(out: TextIO, verb: str, run_id: str, text: str, total: int) -> None:
    out.write('\n'.join(textwrap.wrap('%-12s %s  %s' % (verb, run_id, text), total,
                                       subsequent_indent=' ' * 15)) + '\n')


def prune(runs: Sequence[RunInfo], base: str, keep: Optional[int], days: Optional[float], dry_run: bool,
          out: TextIO, total: int = 80) -> int:
    """Print one line per deleted run and per run kept for a reason other than the rules
    (the published run, a run maybe still going, a foreign folder), then a total."""
    verb = 'would delete' if dry_run else 'deleted'
    code, freed, deleted, kept = EXIT_OK, 0, 0, 0
    for run, delete, why, size, by_rule in decide(runs, base, keep, days):
        if not delete:
            kept += 1
            if not by_rule:
                _line(out, 'keep', run.run_id, why, total)
            continue
        if not dry_run:
            try:
                shutil.rmtree(run.path)
            except OSError as e:
                _line(out, 'error', run.run_id, 'cannot delete %s: %s' % (run.path, e), total)
                code = EXIT_PARTIAL
                kept += 1
                continue
        _line(out, verb, run.run_id, '%s, %s' % (_mb(size), why), total)
        freed += size
        deleted += 1
    out.write('%s %d run%s (%s), kept %d, in %s%s\n' % (
        verb, deleted, '' if deleted == 1 else 's', _mb(freed), kept, os.path.join(base, 'runs'),
        ' (dry run: nothing deleted)' if dry_run else ''))
    return code
