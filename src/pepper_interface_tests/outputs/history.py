"""Run history: every run in its own folder, the latest run at the spec's paths, past runs read back.

Layout of an output folder (`--output-dir`, default data/ of the package):

    <output_dir>/sensorTestOutput.dat          appended by every run, as the spec says
    <output_dir>/sensorTestResults.json, .xml  \\
    <output_dir>/sensorTestReport.html          > the latest run's files (hard links, else copies)
    <output_dir>/frontCameraOutput.mp4, ...    /
    <output_dir>/runs/<run id>/                 one folder per run with all of its files,
                                                including its own sensorTestOutput.dat

A run id is the local start time, YYYYmmdd-HHMMSS, suffixed -2, -3, ... when that folder is
taken (two runs in the same second, or two machines writing to one share): the folder is
created with mkdir, which is atomic, so two runs never get the same folder.

`RunFolder.create()` picks the folder before the run starts; the checks write their recordings
straight into it. `LatestRun` (a runner observer) appends each finished sensor's block to
<output_dir>/sensorTestOutput.dat while the run goes on, and after the run (also an interrupted
one) links the run's files into <output_dir>. Files a previous run published there and this
run did not produce (e.g. a camera video when the camera was not tested this time) are removed,
but only when they are unchanged since they were published (same size and mtime, recorded in
<output_dir>/.sensorTestLatest.json), so nothing a user put there is ever deleted.

`list_runs()`, `resolve()` and `compare()` read the runs back for `sensorTestHistory`
(its commands are in history_cli.py; see docs/results.md).
"""
import json
import os
import shutil
import sys
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Dict, List, Optional, Sequence, TextIO, Tuple

from .. import results
from ..observer import RunObserver
from ..plan import catalog
from ..results import malformed
from ..sensors import families
from . import drift, files
from .atomicfile import write_atomic, write_error
from .terminal import fill

if TYPE_CHECKING:
    from ..plan.settings import TestPlan

RUNS_DIR = 'runs'
ID_FORMAT = '%Y%m%d-%H%M%S'
MANIFEST = '.sensorTestLatest.json'
RATE_FLAG = 0.20        # relative rate change flagged by `compare`
EXIT_OK, EXIT_USAGE = 0, 2


class HistoryError(Exception):
    """A problem a user can fix (unknown run id, no runs yet); sensorTestHistory exits 2."""


# ---------------------------------------------------------------- the run's folder

@dataclass(frozen=True)
class RunFolder:
    run_id: str
    path: str          # where this run's files go
    base: str          # the output folder the user chose
    kept: bool         # True: path is <base>/runs/<run_id>; False (--no-history): path == base

    @classmethod
    def create(cls, output_dir: str, keep: bool = True, now: Optional[float] = None) -> 'RunFolder':
        """A new run id and, with `keep`, its folder <output_dir>/runs/<run id> (created here).
        Raises OSError when the folder cannot be made."""
        base = os.path.abspath(output_dir)
        stamp = time.strftime(ID_FORMAT, time.localtime(time.time() if now is None else now))
        if not keep:
            return cls(stamp, base, base, False)
        runs = os.path.join(base, RUNS_DIR)
        os.makedirs(runs, exist_ok=True)
        n = 0
        while True:
            n += 1
            run_id = stamp if n == 1 else '%s-%d' % (stamp, n)
            try:
                os.mkdir(os.path.join(runs, run_id))
            except FileExistsError:
                continue
            return cls(run_id, os.path.join(runs, run_id), base, True)


def _publish_file(src: str, dst: str) -> str:
    """Make dst the same file as src: a hard link when the file system allows, else a copy.
    Replaces dst atomically (never a half-written file at the spec's path)."""
    folder = os.path.dirname(dst)
    tmp = os.path.join(folder, '.%s.latest-%d' % (os.path.basename(dst), os.getpid()))
    if os.path.lexists(tmp):
        os.unlink(tmp)
    try:
        try:
            os.link(src, tmp)
            how = 'link'
        except OSError:
            shutil.copy2(src, tmp)
            how = 'copy'
        os.replace(tmp, dst)
    except BaseException:       # a full disk mid-copy: no half-copied temporary file left
        if os.path.lexists(tmp):
            os.unlink(tmp)
        raise
    return how


def _signature(path: str) -> List[int]:
    st = os.stat(path)
    return [st.st_size, st.st_mtime_ns]


class LatestRun(RunObserver):
    """Runner observer: keeps <output_dir> holding the latest run while each run has its folder.

    The output folder's sensorTestOutput.dat receives this run's whole section in one locked
    append when the run ends (the run folder's own .dat is written block by block): two runs
    sharing an output folder never interleave their blocks there. A failure to append or to
    publish is a write error of the run (exit 3): the output folder would otherwise show an
    older run's results as the latest."""

    def __init__(self, folder: RunFolder, out: Optional[TextIO] = None) -> None:
        self.folder = folder
        self.out = out
        self.dat: Optional[List[str]] = None     # this run's section of the shared .dat, as text

    def _stream(self) -> TextIO:
        return self.out or sys.stdout

    def _warn(self, text: str) -> None:
        s = self._stream()
        s.write('sensorTest: warning: %s\n' % text)
        s.flush()

    def run_started(self, run: results.RunResult, plan: 'TestPlan') -> None:
        self.dat = [files.dat_begin(run)]

    def sensor_done(self, result: results.SensorResult) -> None:
        if self.dat is not None:
            self.dat.append(files.dat_block(result))

    def run_ended(self, run: results.RunResult) -> None:
        path = os.path.join(self.folder.base, results.OUTPUT_FILE)
        try:
            shared = files.OutputFile(path)
            try:
                shared.write_text(''.join(self.dat or [files.dat_begin(run)]) + files.dat_end(run))
            finally:
                shared.close()
        except OSError as e:
            write_error(run, path, e)
        try:
            published = publish_latest(self.folder)
            s = self._stream()
            files_count = '(%d files)' % len(published)
            s.write(fill('run %s kept in %s; latest run also in %s %s'
                         % (self.folder.run_id, self.folder.path, self.folder.base, files_count),
                         keep=['latest run also in', files_count]) + '\n')
            s.flush()
        except Exception as e:   # a full disk, or anything else: never lose the run over the copies, say so
            write_error(run, 'latest run in %s' % self.folder.base, e)


def read_manifest(base: str) -> Dict[str, Any]:
    """The output folder's record of the run its latest files came from ({} when none or unreadable)."""
    try:
        with open(os.path.join(base, MANIFEST), encoding='utf-8') as f:
            data = json.load(f)
    except (OSError, ValueError):
        return {}
    return data if isinstance(data, dict) else {}


def publish_latest(folder: RunFolder) -> List[str]:
    """Link (or copy) every file of the run's folder into the output folder; returns the names.

    The run's own sensorTestOutput.dat is not published: the output folder's one is appended to.
    """
    names = sorted(n for n in os.listdir(folder.path)
                   if not n.startswith('.') and n != results.OUTPUT_FILE
                   and os.path.isfile(os.path.join(folder.path, n)))
    manifest_path = os.path.join(folder.base, MANIFEST)
    previous = read_manifest(folder.base).get('files') or {}
    published = {}
    for name in names:
        dst = os.path.join(folder.base, name)
        _publish_file(os.path.join(folder.path, name), dst)
        published[name] = _signature(dst)
    for name, sig in previous.items():
        if name in published or os.path.basename(name) != name or name == results.OUTPUT_FILE:
            continue
        path = os.path.join(folder.base, name)
        try:
            if _signature(path) == list(sig):     # still what an earlier run published
                os.unlink(path)
        except OSError:
            pass
    write_atomic(manifest_path, json.dumps(
        {'run_id': folder.run_id, 'run_folder': os.path.relpath(folder.path, folder.base),
         'files': published}, indent=1) + '\n')
    return list(published)


# ---------------------------------------------------------------- reading runs back

@dataclass
class RunInfo:
    run_id: str
    path: str
    data: Optional[Dict[str, Any]]       # the run's sensorTestResults.json, None when missing/unreadable
    problem: str = ''          # why data is None

    @property
    def complete(self) -> bool:
        return self.data is not None

    def result(self) -> results.RunResult:
        """The run read back (each sensor's values in its family's dataclass); an empty run
        when its JSON could not be read."""
        return read_back(self.data or {})

    def sensors(self) -> Dict[str, results.SensorResult]:
        return {s.name: s for s in self.result().sensors}


def read_back(data: Dict[str, Any]) -> results.RunResult:
    """A run's JSON (checked by results.malformed) as a RunResult with typed values; a JSON
    written before the family was recorded names it by the catalog's row of the sensor."""
    def family_of(name: str) -> str:
        sensor = catalog.SENSORS.get(name)
        return sensor.family if sensor is not None else ''
    return results.read_run(data, families.values_of, family_of)


def _sort_key(run_id: str) -> Tuple[str, int, str]:
    """Run ids sort by time, then by suffix as a number (-2 before -10)."""
    parts = run_id.split('-')
    suffix = parts[2] if len(parts) > 2 else ''
    return ('-'.join(parts[:2]), int(suffix) if suffix.isdigit() else 0, run_id)


def list_runs(output_dir: str) -> List[RunInfo]:
    """Every run folder under <output_dir>/runs, oldest first."""
    runs_dir = os.path.join(os.path.abspath(output_dir), RUNS_DIR)
    if not os.path.isdir(runs_dir):
        return []
    out = []
    for run_id in sorted(os.listdir(runs_dir), key=_sort_key):
        path = os.path.join(runs_dir, run_id)
        if run_id.startswith('.') or not os.path.isdir(path):
            continue
        json_path = os.path.join(path, results.JSON_FILE)
        data, problem = None, ''
        if not os.path.exists(json_path):
            problem = 'no %s (the run is still going, or was killed)' % results.JSON_FILE
        else:
            try:
                data = files.load_json(json_path)
            except (OSError, ValueError, RecursionError) as e:
                problem = 'cannot read %s: %s' % (json_path, e)
            else:
                why = malformed(data)
                if why:
                    data, problem = None, 'malformed %s (%s)' % (results.JSON_FILE, why)
        out.append(RunInfo(run_id, path, data, problem))
    return out






def resolve(runs: Sequence[RunInfo], ref: str) -> RunInfo:
    """The run named by `ref`: an exact run id, a unique prefix of one, 'latest' (or 'last'),
    or a negative index (-1 the latest, -2 the one before)."""
    if not runs:
        raise HistoryError('no runs recorded yet')
    ids = [r.run_id for r in runs]
    if ref in ('latest', 'last'):
        return runs[-1]
    if ref.startswith('-') and ref[1:].isdigit():
        k = int(ref[1:])
        if 1 <= k <= len(runs):
            return runs[-k]
        raise HistoryError('run %s: there are only %d runs' % (ref, len(runs)))
    if ref in ids:
        return runs[ids.index(ref)]
    matches = [r for r in runs if r.run_id.startswith(ref)]
    if len(matches) == 1:
        return matches[0]
    if matches:
        raise HistoryError('run id "%s" is ambiguous: %s' % (ref, ', '.join(r.run_id for r in matches)))
    shown = ', '.join(ids[-5:])
    raise HistoryError('unknown run id "%s"; the latest runs are: %s (sensorTestHistory list shows all)'
                       % (ref, shown))


def compare(a: RunInfo, b: RunInfo, threshold: float = RATE_FLAG) -> List[Dict[str, Any]]:
    """What changed from run `a` to run `b`: one row per sensor of either run."""
    for r in (a, b):
        if not r.complete:
            raise HistoryError('run %s cannot be compared: %s' % (r.run_id, r.problem))
    sa, sb = a.sensors(), b.sensors()
    start = (a.data or {}).get('start') or ''
    ref = drift.Ref(a.run_id, start.split('.')[0] if isinstance(start, str) else '')
    names = list(sa) + [n for n in sb if n not in sa]
    rows = []
    for name in names:
        x, y = sa.get(name), sb.get(name)
        row: Dict[str, Any] = {'sensor': name, 'verdict_a': x.verdict if x else None,
               'verdict_b': y.verdict if y else None,
               'rate_a': x.rate_hz if x else None, 'rate_b': y.rate_hz if y else None,
               'reasons_a': x.reasons if x else [], 'reasons_b': y.reasons if y else []}
        row['verdict_changed'] = row['verdict_a'] != row['verdict_b']
        ra, rb = row['rate_a'], row['rate_b']
        row['rate_change'] = (rb - ra) / ra if ra and rb is not None else None
        row['rate_flag'] = row['rate_change'] is not None and abs(row['rate_change']) > threshold
        if ra and rb is None and y is not None and y.verdict != results.SKIPPED:
            row['rate_flag'] = True       # it had a rate, now nothing arrives
        # the drift table of B against A (outputs/drift.py): every value both measured
        row['values'] = [{'value': v[0], 'a': v[1], 'b': v[2], 'margin': v[3], 'drifted': v[4]}
                         for v in (drift.table(x, y) if x and y else [])]
        row['drift'] = [d.text for d in (drift.drift(x, y, ref) if x and y else [])]
        rows.append(row)
    return rows
