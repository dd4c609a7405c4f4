"""This robot's baseline: the run it is compared with, pinned in the output folder.

`sensorTestHistory baseline set RUN` checks the run (`why_not`) and writes <output_dir>/baseline.json
(run id, its folder, when it was pinned) with outputs/atomicfile.py; `baseline show` reads it,
`baseline clear` removes it. sensorTest compares every run with the pinned baseline, or with
`--baseline RUN`, or with none (`--no-baseline`): `Compare` is the runner observer that puts
each sensor's drift (outputs/drift.py) on its result before the outputs see it.

A run is refused as a baseline, with its reason, when it cannot be read, was written by an
incompatible results version, was interrupted, had a sensor fail, or came from another
platform than the run compared with it (and from another robot, when both runs name it in
their JSON's "robot").
"""
import json
import os
import sys
import time
from typing import Dict, Optional, TextIO, Tuple

from .. import results
from ..observer import RunObserver
from ..results import FAIL, RunResult, SensorResult
from . import drift, files
from .atomicfile import write_atomic
from .history import HistoryError, RunInfo, list_runs, resolve
from .terminal import fill

POINTER = 'baseline.json'


def find(base: str, ref: str) -> RunInfo:
    """The run `ref` names: a run id of <base>/runs (or 'latest', -1, a unique prefix), a run
    folder, or a sensorTestResults.json. Raises HistoryError naming what was not found."""
    path = os.path.abspath(os.path.expanduser(ref))
    if os.path.isdir(path) or os.path.isfile(path):
        json_path = os.path.join(path, results.JSON_FILE) if os.path.isdir(path) else path
        folder = os.path.dirname(json_path)
        if not os.path.isfile(json_path):
            raise HistoryError('%s has no %s: not a run folder' % (path, results.JSON_FILE))
        try:
            data = files.load_json(json_path)
        except (OSError, ValueError, RecursionError) as e:
            return RunInfo(os.path.basename(folder), folder, None, 'cannot read %s: %s' % (json_path, e))
        why = results.malformed(data)
        if why:
            return RunInfo(os.path.basename(folder), folder, None, 'malformed %s (%s)' % (json_path, why))
        named = data.get('run_id')
        run_id = named if isinstance(named, str) and named else os.path.basename(folder)
        return RunInfo(run_id, folder, data)
    return resolve(list_runs(base), ref)


def why_not(run: RunInfo, platform: Optional[str] = None, robot: Optional[str] = None) -> str:
    """Why `run` cannot serve as a baseline ('' when it can); `platform` and `robot`: those of
    the run it would be compared with, when known."""
    if run.data is None:
        return 'it cannot be read: %s' % run.problem
    data = run.data
    if data.get('schema_version') != results.SCHEMA_VERSION:
        return ('it was written by results version %s, this sensorTest reads version %d: run '
                'sensorTest once more and pin that run' % (data.get('schema_version'), results.SCHEMA_VERSION))
    if data.get('interrupted'):
        return 'it was interrupted (%s): its windows were cut short' % (data.get('interrupt_reason') or 'Ctrl-C')
    failed = [s['name'] for s in data.get('sensors', []) if s.get('verdict') == FAIL]
    if failed:
        return ('%d sensor%s failed in it (%s): a baseline is a run where every sensor passed'
                % (len(failed), '' if len(failed) == 1 else 's', ', '.join(failed)))
    if not any(s.get('verdict') == results.PASS for s in data.get('sensors', [])):
        return 'no sensor passed in it: there is nothing to compare with'
    if platform and data.get('platform') and data.get('platform') != platform:
        return 'it ran on the %s, this run is on the %s' % (data.get('platform'), platform)
    theirs = data.get('robot')     # naoqi_driver's BodyId (sources/identity.py), when the runs knew it
    if robot and isinstance(theirs, str) and theirs and theirs != robot:
        return 'baseline from robot %s, this run is robot %s: pin a baseline of this robot' % (theirs, robot)
    return ''


def pin(base: str, run: RunInfo, now: Optional[float] = None) -> Dict[str, str]:
    """Write <base>/baseline.json naming `run` (checked by why_not first). Raises HistoryError."""
    why = why_not(run)
    if why:
        raise HistoryError('run %s cannot be the baseline: %s' % (run.run_id, why))
    os.makedirs(base, exist_ok=True)
    record = {'run_id': run.run_id, 'path': run.path,
              'pinned_at': time.strftime('%Y-%m-%d %H:%M:%S', time.localtime(now))}
    write_atomic(os.path.join(base, POINTER), json.dumps(record, indent=1) + '\n')
    return record


def pinned(base: str) -> Optional[Dict[str, str]]:
    """The pointer <base>/baseline.json ({run_id, path, pinned_at}), None when none is pinned.
    Raises HistoryError when the file is there but unreadable."""
    path = os.path.join(base, POINTER)
    if not os.path.exists(path):
        return None
    try:
        with open(path, encoding='utf-8') as f:
            data = json.load(f)
    except (OSError, ValueError) as e:
        raise HistoryError('cannot read %s: %s (sensorTestHistory baseline clear removes it)' % (path, e)) from None
    if not isinstance(data, dict) or not isinstance(data.get('path'), str):
        raise HistoryError('%s names no run (sensorTestHistory baseline clear removes it)' % path)
    return {k: str(v) for k, v in data.items()}


def clear(base: str) -> bool:
    """Remove the pointer; False when none was pinned."""
    try:
        os.unlink(os.path.join(base, POINTER))
    except FileNotFoundError:
        return False
    return True


def load_pinned(base: str) -> Tuple[Optional[RunInfo], str]:
    """(the pinned run, '') or (None, why not: '' when none is pinned)."""
    try:
        record = pinned(base)
    except HistoryError as e:
        return None, str(e)
    if record is None:
        return None, ''
    try:
        return find(base, record['path']), ''
    except HistoryError as e:
        return None, 'the pinned baseline %s is gone: %s' % (record.get('run_id'), e)


def ref_of(run: RunInfo) -> drift.Ref:
    start = (run.data or {}).get('start') or ''
    return drift.Ref(run.run_id, start.split('.')[0] if isinstance(start, str) else '')


class Compare(RunObserver):
    """Puts each finished sensor's drift from the baseline on its result (a warning each);
    called before every other observer so that all outputs show it."""

    def __init__(self, baseline: RunInfo, pinned_one: bool, out: Optional[TextIO] = None) -> None:
        self.baseline = baseline
        self.pinned_one = pinned_one
        self.then: Dict[str, SensorResult] = {}
        self.ref = ref_of(baseline)
        self.out = out
        self.active = False
        self.count = 0

    def _say(self, text: str) -> None:
        s = self.out or sys.stdout
        s.write(fill('sensorTest: %s' % results.printable(text, 400)) + '\n')
        s.flush()

    def run_started(self, run: RunResult, plan: object) -> None:
        why = why_not(self.baseline, run.platform, run.robot)
        if why:      # a pinned one that no longer serves: said, no comparison (--baseline was checked before)
            self._say('note: baseline %s not used: %s' % (self.baseline.run_id, why))
            return
        self.active = True
        self.then = self.baseline.sensors()
        run.baseline = {'run_id': self.baseline.run_id, 'start': (self.baseline.data or {}).get('start'),
                        'path': self.baseline.path, 'pinned': self.pinned_one}
        self._say('comparing with the baseline run %s of %s%s' % (
            self.baseline.run_id, self.ref.day, ' (pinned)' if self.pinned_one else ''))

    def sensor_done(self, result: SensorResult) -> None:
        then = self.then.get(result.name) if self.active else None
        if then is not None:
            self.count += len(drift.apply(result, then, self.ref))


def for_run(output_dir: str, option: object, platform: str,
            robot: str = '') -> Tuple[Optional[Compare], str]:
    """The observer that compares a run with its baseline, and a note for the run header ('' or
    why the pinned baseline is not used). `option`: --baseline's value (a run, 'none'), False
    (--no-baseline) or None (the pinned one); `robot`: this run's identity ('' unknown). Raises
    HistoryError when the run --baseline names is not found or cannot serve (the run does not start)."""
    if option is False or (isinstance(option, str) and option.strip().lower() in ('none', 'false', '')):
        return None, ''
    if isinstance(option, str):
        run = find(output_dir, option)
        why = why_not(run, platform, robot)
        if why:
            raise HistoryError('run %s cannot be the baseline: %s' % (run.run_id, why))
        return Compare(run, pinned_one=False), ''
    pinned_run, why = load_pinned(output_dir)
    if pinned_run is None:
        return None, ('baseline not used: %s' % why) if why else ''
    return Compare(pinned_run, pinned_one=True), ''
