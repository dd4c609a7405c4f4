"""The page: the run's results -> the template's context -> HTML (Jinja2, autoescaping on).

Everything shown goes through the template, which escapes it; `finalize` turns a None into
'-' and control characters into visible \\xNN, so no 'None' and no raw control byte reaches
the page. Verdicts other than PASS / FAIL / SKIPPED (e.g. a future INTERRUPTED) are shown
with their own name in a neutral grey badge.
"""
import os
import re
from collections import Counter
from typing import TYPE_CHECKING, Any, Dict, List, Optional, Tuple

from ... import codec
from ...plan import catalog
from ...results import (
    FAIL,
    PASS,
    PASSING,
    SKIPPED,
    RunResult,
    SensorResult,
    robot_line,
    summary_line,
    timestamp,
)
from ...sensors import families
from .. import formats
from . import drift_view, plots, views
from .blocks import KV, Span
from .context import RateRow, View, anchor
from .files import RunFiles
from .views.fmt import clean, num

if TYPE_CHECKING:
    import jinja2

TEMPLATES = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'templates')
KNOWN = (PASS, FAIL, SKIPPED)


def verdict_class(verdict: str) -> str:
    return verdict if verdict in KNOWN else 'OTHER'


def _finalize(value: Any) -> Any:
    import markupsafe
    if value is None:
        return '-'
    if isinstance(value, str) and not isinstance(value, markupsafe.Markup):
        return clean(value) if value and not value.startswith('data:') else value
    return value


def environment() -> 'jinja2.Environment':
    import jinja2
    return jinja2.Environment(loader=jinja2.FileSystemLoader(TEMPLATES), autoescape=True, finalize=_finalize,
                              trim_blocks=True, lstrip_blocks=True, undefined=jinja2.StrictUndefined)


def family(r: SensorResult) -> Optional[str]:
    """The sensor's family: as its result says, else (a result without one) its catalog row's."""
    if r.family:
        return r.family
    sensor = catalog.SENSORS.get(r.name)
    return sensor.family if sensor else None


def no_values(fam: Optional[str]) -> Any:
    """The family's values when its check handed none over (every field at its default), so
    that a view still shows what the result's artifacts and notes say."""
    cls = families.values_of(fam) if fam else None
    return cls() if cls is not None else None


def periodic(r: SensorResult) -> bool:
    """The sensor streams at a rate (not speech, not an event topic such as a touch sensor)."""
    fam = family(r)
    return fam is None or families.family(fam).traits.periodic


def headline(r: SensorResult) -> bool:
    """The sensor's state explains other sensors' (Traits.headline: the robot's health)."""
    fam = family(r)
    return fam is not None and families.family(fam).traits.headline


def in_band(r: SensorResult) -> Optional[bool]:
    """The rate's own verdict: True inside the expected band, False outside, None without one."""
    band = r.expected_rate_hz
    if not band or r.rate_hz is None:
        return None
    return band[0] <= r.rate_hz <= band[1]


# ---------------------------------------------------------------- rates over the run

def rate_steps(r: SensorResult) -> Tuple[List[float], List[float]]:
    """The sensor's 1 s rate bins as stairs on the run's time axis: (edges, rates).
    The last bin usually covers only part of a second; its rate is scaled to that part
    (a bin shorter than 0.25 s is dropped rather than shown as a false drop)."""
    pts = []
    for p in r.rate_series or []:
        try:
            if p[1] is not None:
                pts.append((float(p[0]), float(p[1])))
        except (TypeError, ValueError, IndexError):
            continue
    start = r.started_at or 0.0
    end = r.window_s if r.window_s else (pts[-1][0] + 0.5 if pts else 0.0)
    edges: List[float] = []
    rates: List[float] = []
    for t, v in pts:
        lo, hi = t - 0.5, min(t + 0.5, end)
        if hi - lo < 0.25:
            break
        if not edges:
            edges.append(start + lo)
        edges.append(start + hi)
        rates.append(v / (hi - lo))
    return edges, rates


def rates_figure(run: RunResult) -> Optional[str]:
    rows = []
    for r in run.sensors:
        if r.verdict == SKIPPED or not r.rate_series or not periodic(r):    # speech, event topics: no rate
            continue
        edges, rates = rate_steps(r)
        start = r.started_at or 0.0
        end = r.ended_at if r.ended_at is not None else (edges[-1] if edges else start)
        ok = in_band(r)
        label = ('%s Hz' % num(r.rate_hz, 1) if r.rate_hz is not None else 'no rate') + \
            {True: ' in band', False: ' out of band', None: ''}[ok]
        rows.append(RateRow(r.name, edges, rates, start, end, r.expected_rate_hz, r.nominal_rate_hz, ok, label))
    if not rows:
        return None
    t_end = max([(run.end - run.start) if run.end else 0.0] + [r.end for r in rows])
    return plots.rates(rows, t_end)


# ---------------------------------------------------------------- one sensor

def _flatten(prefix: str, value: Any, out: List[Tuple[str, str]], depth: int = 0) -> None:
    if isinstance(value, dict) and depth < 3:
        for k, v in value.items():
            _flatten('%s.%s' % (prefix, k) if prefix else str(k), v, out, depth + 1)
    elif isinstance(value, (list, tuple)) and (len(value) > 8 or any(isinstance(v, (list, dict)) for v in value)):
        out.append((prefix, '[%d items]' % len(value)))
    elif isinstance(value, float):
        out.append((prefix, num(value, 4)))
    elif isinstance(value, (list, tuple)):
        out.append((prefix, '[%s]' % ', '.join(num(v, 4) if isinstance(v, float) else clean(v) for v in value)))
    else:
        out.append((prefix, clean(value)))


def stats_rows(r: SensorResult) -> List[Tuple[str, Any]]:
    s = r.stats
    band = r.expected_rate_hz
    ok = in_band(r)
    rows = [('messages', num(r.messages)),
            ('rate (receive times)', Span(num(r.rate_hz, 2, 'Hz'), cls='fail-text' if ok is False else '')),
            ('rate (header stamps)', num(r.stamp_rate_hz, 2, 'Hz')),
            ('expected / nominal', '%s Hz / %s' % ('%g-%g' % tuple(band) if band else '-',
                                                   num(r.nominal_rate_hz, 2, 'Hz'))),
            ('window', '%s, %s' % (num(r.window_s, 1, 's'), r.stopped_because or '-')),
            ('started at', num(r.started_at, 1, 's into the run'))]
    if s is not None:
        delay = s.delay_s
        rows += [('first message after', num(s.first_message_after_s, 3, 's')),
                 ('jitter (std of intervals)', num(s.jitter_s, 4, 's')),
                 ('longest interval', num(s.max_interval_s, 3, 's')),
                 ('delay now - stamp', '%s mean, %s max' % (num(delay.mean, 4, 's'), num(delay.max, 4, 's'))
                  if delay is not None else '-'),
                 ('zero / backwards / repeated stamps', '%s / %s / %s' % (
                     num(s.zero_stamps), num(s.backwards_stamps), num(s.repeated_stamps)))]
    if r.received_type and r.received_type != r.msg_type:
        rows.append(('received type', Span(r.received_type, cls='fail-text')))
    return rows


def section(r: SensorResult, run: RunResult, view: View, history: Optional[Any] = None) -> Dict[str, Any]:
    sec = {'name': r.name, 'anchor': anchor(r.name), 'title': r.title or r.name, 'verdict': r.verdict,
           'vcls': verdict_class(r.verdict), 'topic': r.topic or '-', 'msg_type': r.msg_type or '-',
           'reasons': [clean(x) for x in r.reasons or []], 'warnings': [clean(x) for x in r.warnings or []],
           'skipped': r.verdict == SKIPPED, 'body': [], 'stats': None, 'notes': [], 'values': [],
           'fields': [], 'error': None, 'drift': []}
    if sec['skipped']:
        return sec
    sec['drift'] = drift_view.blocks(r, run, history)
    try:
        sec['summary'] = clean(summary_line(r))
    except Exception:        # a result with odd numbers still gets its section
        sec['summary'] = '%s messages' % num(r.messages)
    fam = family(r)
    sec['body'] = views.render(fam, r, r.values if r.values is not None else no_values(fam), view)
    sec['stats'] = KV(stats_rows(r))
    sec['notes'] = [clean(x) for x in r.notes or []]
    values: List[Tuple[str, str]] = []
    for k, v in (codec.split(r.values)[0] if r.values is not None else {}).items():
        if k != 'joints':
            _flatten(k, v, values)
    sec['values'] = values
    sec['fields'] = [(clean(f[0]), clean(f[1])) for f in r.fields or [] if len(f) >= 2]
    return sec


# ---------------------------------------------------------------- the page

def header(run: RunResult) -> Dict[str, Any]:
    counts = Counter(r.verdict for r in run.sensors)
    order = [v for v in KNOWN] + sorted(v for v in counts if v not in KNOWN)
    words = {PASS: 'passed', FAIL: 'failed', SKIPPED: 'skipped'}
    try:
        exit_code = run.exit_code
    except Exception:
        exit_code = None
    return {
        'title': 'sensorTest report: %s, %s mode' % (run.platform, run.mode),
        'run_id': run.run_id or '-',
        'source': 'live topics' if run.source == 'live' else 'bag %s' % run.source,
        'robot': clean(robot_line(run)),
        'start': timestamp(run.start).replace('.', ' '),
        'end': timestamp(run.end).replace('.', ' ') if run.end else '-',
        'duration': '%.1f s' % (run.end - run.start) if run.end else '-',
        'exit_code': exit_code,
        'counts': [(verdict_class(v), '%d %s' % (counts.get(v, 0), words.get(v, v))) for v in order],
        # the summary's verdict column as wide as its longest badge ("PASS*", "NOT JUDGED",
        # "INTERRUPTED": report.css --verdict-chars), so that no badge wraps or spills over
        'verdict_chars': max([5] + [len(r.verdict) + (r.verdict == PASS and bool(r.warnings)) for r in run.sensors]),
        'interrupted': clean(run.interrupt_reason or 'run interrupted') if run.interrupted else None,
        'failed': [(anchor(r.name), r.name) for r in run.sensors if r.verdict == FAIL],
        # a family whose WARN or FAIL explains the others' (the robot's health), first
        'headlines': [(anchor(r.name), r.title, 'bad' if r.verdict == FAIL else 'warn',
                       clean('; '.join(r.reasons + r.warnings + r.notes)))
                      for r in run.sensors
                      if headline(r) and (r.verdict == FAIL or (r.verdict == PASS and r.warnings))],
        'all_passed': bool(run.sensors) and not run.interrupted and all(r.verdict in PASSING for r in run.sensors),
    }


def summary_rows(run: RunResult, files: RunFiles) -> List[Dict[str, Any]]:
    rows = []
    for r in run.sensors:
        art = r.artifacts if isinstance(r.artifacts, dict) else {}
        rec = [n for k, n in art.items() if k in ('video', 'audio', 'wav') or str(k).startswith('audio_')]
        rows.append({'anchor': anchor(r.name), 'name': r.name, 'verdict': r.verdict,
                     # where a narrow column may break a name: before each capital (a sensor's
                     # camelCase name), after each '/' of a topic
                     'name_parts': re.split(r'(?<=[a-z])(?=[A-Z])', r.name),
                     'topic': r.topic or '-',
                     'vcls': verdict_class(r.verdict), 'messages': '-' if r.verdict == SKIPPED else num(r.messages),
                     'rate': num(r.rate_hz), 'out': in_band(r) is False,
                     'band': '%g-%g' % tuple(r.expected_rate_hz) if r.expected_rate_hz else '-',
                     'recordings': files.links(rec), 'reasons': '; '.join(clean(x) for x in r.reasons or []),
                     'warnings': '; '.join(clean(x) for x in r.warnings or [])})
    return rows


def render(run: RunResult, folder: str, max_embed: int) -> str:
    """The report of `run` as one HTML string; recordings are read from `folder`."""
    files = RunFiles(folder, max_embed=max_embed)
    view = View(files, run)
    history = drift_view.history_for(run, folder)
    sections = []
    for r in run.sensors:
        try:
            sections.append(section(r, run, view, history))
        except Exception as e:     # one odd sensor must not lose the whole report
            files.problems.append('%s: %s: %s' % (r.name, type(e).__name__, e))
            sections.append({'name': r.name, 'anchor': anchor(r.name), 'title': r.title or r.name,
                             'verdict': r.verdict, 'vcls': verdict_class(r.verdict),
                             'error': '%s: %s' % (type(e).__name__, e)})
    try:
        rates = rates_figure(run)
    except Exception as e:
        files.problems.append('rates figure: %s: %s' % (type(e).__name__, e))
        rates = None
    context = {'h': header(run), 'summary': summary_rows(run, files), 'rates': rates, 'sections': sections,
               'result_files': files.links(formats.results_files()), 'inputs': dict(run.files or {}),
               'options': ', '.join('%s=%s' % kv for kv in sorted((run.options or {}).items(), key=str)),
               'problems': files.problems, 'written': timestamp().replace('.', ' '),
               'embedded': files.embedded}
    return environment().get_template('report.html.j2').render(**context)
