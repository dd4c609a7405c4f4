"""sensorTestHistory's text output: `list` and `compare` as tables that fit the terminal (its
width, else $COLUMNS, else 80 columns), free-text cells wrapped inside their column."""
import os
import textwrap
from typing import Any, Collection, Dict, List, Optional, Sequence, Tuple

from .. import results
from ..results import PASSING
from .history import RATE_FLAG, RUNS_DIR, RunInfo
from .terminal import columns


def width() -> int:
    """Columns to fit: $COLUMNS, else the terminal's, else 80 (less the one column kept free);
    never under 60."""
    return columns(80, minimum=60)


def _counts(data: Dict[str, Any]) -> Tuple[int, int, int]:
    c = data.get('summary') or {}
    return c.get(results.PASS, 0), c.get(results.FAIL, 0), c.get(results.SKIPPED, 0)


def _table(rows: Sequence[Sequence[str]], right: Collection[int] = ()) -> List[str]:
    """Columns padded to their widest cell; columns in `right` right-aligned."""
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    return ['  '.join(r[i].rjust(widths[i]) if i in right else r[i].ljust(widths[i])
                      for i in range(len(r))).rstrip() for r in rows]


def _wrapped_rows(rows: Sequence[Sequence[str]], total: int) -> List[str]:
    """Rows whose last cell is free text, wrapped inside its column so every line fits `total`;
    when the column would be narrower than 24, the text goes under the row, indented."""
    head = [r[:-1] for r in rows]
    widths = [max(len(r[i]) for r in head) for i in range(len(head[0]))]
    indent = sum(widths) + 2 * len(widths)
    lines = []
    for r in rows:
        start = '  '.join(r[i].ljust(widths[i]) for i in range(len(widths))) + '  '
        if total - indent >= 24:
            parts = textwrap.wrap(r[-1], total - indent) or ['']
            lines.append((start + parts[0]).rstrip())
            lines += [' ' * indent + p for p in parts[1:]]
        else:
            lines.append(start.rstrip())
            lines += textwrap.wrap(r[-1], total - 4, initial_indent='    ', subsequent_indent='    ')
    return lines


def format_list(runs: Sequence[RunInfo], base: str) -> str:
    if not runs:
        return 'no runs in %s\n' % os.path.join(base, RUNS_DIR)
    rows = [('run id', 'start', 'platform', 'mode', 'source', 'pass', 'fail', 'skip', 'failed sensors')]
    for r in runs:
        d = r.data
        if d is None:     # not complete
            rows.append((r.run_id, '-', '-', '-', '-', '-', '-', '-', 'incomplete: ' + r.problem))
            continue
        p, f, s = _counts(d)
        failed = ', '.join(x['name'] for x in d.get('sensors', []) if x.get('verdict') == results.FAIL)
        if d.get('interrupted'):
            failed = (failed + '; ' if failed else '') + 'INTERRUPTED'
        source = d.get('source') or '-'
        rows.append((r.run_id, (d.get('start') or '-').replace('.', ' '), d.get('platform') or '-',
                     d.get('mode') or '-', 'live' if source == 'live' else 'bag', str(p), str(f), str(s),
                     failed or '-'))
    lines = _table(rows, right=(5, 6, 7))
    lines.append('%d run%s in %s' % (len(runs), '' if len(runs) == 1 else 's', os.path.join(base, RUNS_DIR)))
    return '\n'.join(lines) + '\n'


def format_compare(a: RunInfo, b: RunInfo, rows: Sequence[Dict[str, Any]], threshold: float = RATE_FLAG,
                   total: int = 80) -> str:
    """Every sensor of either run (verdicts, rates), then the verdict changes as a table with
    the reasons wrapped inside their column, then the flagged rate changes; fits `total`."""
    def rate(v: Optional[float]) -> str:
        return '%.2f' % v if v is not None else '-'

    lines = ['compare %s (A) -> %s (B)' % (a.run_id, b.run_id)]
    for tag, run in (('A', a), ('B', b)):
        d = run.data or {}     # compare() took only complete runs
        p, f, s = _counts(d)
        lines += textwrap.wrap('%s: %s, %s, %s, %d passed, %d failed, %d skipped%s' % (
            tag, (d.get('start') or '-').replace('.', ' '), d.get('platform'), d.get('mode'), p, f, s,
            ', INTERRUPTED' if d.get('interrupted') else ''), total - 2,
            initial_indent='  ', subsequent_indent='     ')
    table = [('sensor', 'verdict A', 'verdict B', '', 'A Hz', 'B Hz', 'change')]
    for row in rows:
        change = '%+.1f%%' % (100 * row['rate_change']) if row['rate_change'] is not None else '-'
        table.append((row['sensor'], row['verdict_a'] or '(absent)', row['verdict_b'] or '(absent)',
                      '*' if row['verdict_changed'] else '', rate(row['rate_a']), rate(row['rate_b']),
                      change + (' !' if row['rate_flag'] else '')))
    lines += [''] + _table(table, right=(4, 5))
    changed = [r for r in rows if r['verdict_changed']]
    lines.append('')
    if changed:
        lines.append('%d verdict change%s:' % (len(changed), '' if len(changed) == 1 else 's'))
        vt = [('sensor', 'A', 'B', 'why')]
        for r in changed:
            if r['verdict_b'] not in PASSING and r['verdict_b'] and r['reasons_b']:
                why = '; '.join(r['reasons_b'])
            elif r['verdict_a'] not in PASSING and r['verdict_a'] and r['reasons_a']:
                why = 'was: ' + '; '.join(r['reasons_a'])
            else:
                why = '-'
            vt.append((r['sensor'], r['verdict_a'] or '(absent)', r['verdict_b'] or '(absent)', why))
        lines += ['  ' + line for line in _wrapped_rows(vt, total - 2)]
    else:
        lines.append('no verdict changed')
    flagged = [r for r in rows if r['rate_flag']]
    lines.append('')
    if flagged:
        lines.append('%d rate change%s over %g%%:' % (len(flagged), '' if len(flagged) == 1 else 's',
                                                       100 * threshold))
        lines += _table([('  ' + r['sensor'], rate(r['rate_a']) + ' Hz', '->',
                          rate(r['rate_b']) + ' Hz' if r['rate_b'] is not None else 'no messages')
                         for r in flagged], right=(1,))
    else:
        lines.append('no rate changed by more than %g%%' % (100 * threshold))
    lines.append('')
    lines += format_drift(rows, total)
    return '\n'.join(lines) + '\n'


def format_drift(rows: Sequence[Dict[str, Any]], total: int = 80) -> List[str]:
    """The drift of B from A (outputs/drift.py): each value beyond its margin, in the words of
    sensorTest's warning, or that none was."""
    compared = sum(len(r.get('values') or []) for r in rows)
    drifted = [(r['sensor'], text) for r in rows for text in r.get('drift') or []]
    if not drifted:
        return ['no value drifted beyond its margin (%d values compared; docs/drift.md)' % compared]
    lines = ['%s drifted beyond %s margin (of %d compared; docs/drift.md):'
             % ('1 value' if len(drifted) == 1 else '%d values' % len(drifted),
                'its' if len(drifted) == 1 else 'their', compared)]
    for sensor, text in drifted:
        lines += textwrap.wrap('%s: %s' % (sensor, text), total - 2, initial_indent='  ',
                               subsequent_indent='      ', break_on_hyphens=False)
    return lines
