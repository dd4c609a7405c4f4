"""The report's drift block: under a sensor's warnings, each value that drifted since the
baseline (outputs/drift.py), then and now side by side, and, when the output folder keeps more
than two runs, a small plot of each drifted value over the runs (the baseline and this run
marked), read back from the run history."""
import os
import statistics
from typing import Dict, List, Optional, Tuple

from ...results import RunResult, SensorResult
from .. import drift
from ..history import RUNS_DIR, list_runs
from . import plots
from .blocks import Block, Heading, Image, Para, Span, Table

MAX_RUNS = 30           # the trend reads at most the latest 30 runs' JSON
MAX_PLOTS = 4           # trend plots per sensor


class History:
    """The runs of the output folder a run folder belongs to, read once for all sensors:
    sensor name -> [(run id, its measures)], oldest first."""

    def __init__(self, run_folder: str, run_id: str) -> None:
        self.points: Dict[str, List[Tuple[str, Dict[str, float]]]] = {}
        parent = os.path.dirname(os.path.abspath(run_folder))
        if os.path.basename(parent) != RUNS_DIR:       # --no-history: no run history to read
            return
        runs = [r for r in list_runs(os.path.dirname(parent)) if r.complete and r.run_id != run_id]
        for info in runs[-MAX_RUNS:]:
            for s in info.result().sensors:
                self.points.setdefault(s.name, []).append((info.run_id, drift.measures(s)))

    def series(self, sensor: str, measure: str) -> List[Tuple[str, float]]:
        out = []
        for run_id, values in self.points.get(sensor, []):
            if measure.endswith(':*'):            # a group: the median of its subjects
                kind = measure[:-1]
                group = [v for k, v in values.items() if k.startswith(kind)]
                if group:
                    out.append((run_id, statistics.median(group)))
            elif measure in values:
                out.append((run_id, values[measure]))
        return out


def history_for(run: RunResult, folder: str) -> Optional[History]:
    """The history when some sensor of `run` drifted (else nothing is read)."""
    if not any(r.drift for r in run.sensors):
        return None
    try:
        return History(folder, run.run_id)
    except Exception:       # an unreadable history costs the trend plots, never the report
        return None


def _now_value(r: SensorResult, measure: str) -> Optional[float]:
    values = drift.measures(r)
    if measure.endswith(':*'):
        group = [v for k, v in values.items() if k.startswith(measure[:-1])]
        return statistics.median(group) if group else None
    return values.get(measure)


def blocks(r: SensorResult, run: RunResult, history: Optional[History]) -> List[Block]:
    """The drift block of one sensor ([] when nothing drifted)."""
    if not r.drift:
        return []
    base = run.baseline or {}
    day = str(base.get('start') or '').split('.')[0]
    out: List[Block] = [
        Heading('Drift since the baseline run %s%s' % (base.get('run_id', '?'), ' of %s' % day if day else '')),
        Para([Span('warnings, not failures: ', strong=True),
              'each value beyond its margin (docs/drift.md) since the run this robot was pinned to']),
        Table(['value', 'then (baseline)', 'now', 'change', 'margin'],
              [[d.label, _fmt(d.then, d.unit), Span(_fmt(d.now, d.unit), cls='warn-text'), d.change, d.margin]
               for d in r.drift], numeric=[1, 2])]
    if history is None:
        return out
    for d in r.drift[:MAX_PLOTS]:
        points = history.series(r.name, d.measure)
        now = _now_value(r, d.measure)
        if now is None or len(points) + 1 <= 2:        # a trend needs more than two runs
            continue
        points.append((run.run_id or 'this run', now))
        out.append(Image(plots.trend(d.label, d.unit, points, base.get('run_id')),
                         'trend of %s over %d runs' % (d.label, len(points)),
                         caption='%s over the last %d runs (baseline and this run marked)'
                                 % (d.label, len(points))))
    return out


def _fmt(v: Optional[float], unit: str) -> str:
    if v is None:
        return '-'
    text = '%.3g' % v
    return text + ('' if not unit else unit if unit[0] in '/%' else ' ' + unit)

