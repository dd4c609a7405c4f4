"""The robot's transform tree: drawn from its root, each sensor's frame marked with the sensor
and whether its data could be placed in base_footprint (sensors/frames.py)."""
from typing import Dict, List, Set, Tuple

from ....results import SensorResult
from ....sensors.values.tf import TfValues
from ..blocks import KV, Block, Details, Heading, Span, Table
from ..context import View
from .fmt import num

INDENT = '\u00a0\u00a0'     # HTML keeps non-breaking spaces: the tree's depth


def _sensor_frames(ctx: View) -> Dict[str, List[Tuple[str, bool]]]:
    """frame -> [(sensor, placed)] from every row's frame placement."""
    out: Dict[str, List[Tuple[str, bool]]] = {}
    for r in (ctx.run.sensors if ctx.run is not None else []):
        f = getattr(r, 'frame', None)
        if f is not None and f.frame_id:
            out.setdefault(f.frame_id, []).append((r.name, f.judged > 0 and f.placed == f.judged))
    return out


def _rows(v: TfValues, marks: Dict[str, List[Tuple[str, bool]]], only: Set[str]) -> List[List[object]]:
    children: Dict[str, List[str]] = {}
    for link in v.links:
        children.setdefault(link.parent, []).append(link.child)
    rows: List[List[object]] = []
    drawn: Set[str] = set()

    def walk(frame: str, depth: int) -> None:
        if only and frame not in only:
            return
        sensors = marks.get(frame, [])
        cell: List[object] = [Span(', '.join(n for n, _ in sensors),
                                   cls='' if all(ok for _, ok in sensors) else 'fail-text', strong=True)] \
            if sensors else []
        drawn.add(frame)
        rows.append([INDENT * depth + ('\u2514 ' if depth else '') + frame, cell])
        for c in sorted(children.get(frame, [])):
            walk(c, depth + 1)

    for root in v.roots:
        walk(root, 0)
    for frame in sorted(marks):         # sensors' frames the tree never held
        if frame not in drawn:
            rows.append([Span(frame + ' (not in /tf)', cls='fail-text'),
                         Span(', '.join(n for n, _ in marks[frame]), cls='fail-text', strong=True)])
    return rows


def _ancestors(v: TfValues, frames: List[str]) -> Set[str]:
    parent = {link.child: link.parent for link in v.links}
    keep: Set[str] = set(v.roots)
    for f in frames:
        while f and f not in keep:
            keep.add(f)
            f = parent.get(f, '')
    return keep


def render(r: SensorResult, v: TfValues, ctx: View) -> List[Block]:
    if not v.messages:
        return []
    marks = _sensor_frames(ctx)
    blocks: List[Block] = [KV([
        ('messages (/tf and /tf_static)', str(v.messages)), ('parent-child pairs', str(v.pairs)),
        ('roots', ', '.join(v.roots) or '-'), ('publishers', ', '.join(v.publishers) or '-'),
        ('frames published by two nodes', ', '.join(v.second_publishers) or 'none'),
        ('newest stamp ahead of arrival', num(v.max_ahead_s, 3, 's')),
        ('newest stamp behind arrival', num(v.max_behind_s, 3, 's')),
        ('odometry against odom -> base_link', '%s (%d compared)' % (num(v.odom_worst, 3, 'm'), v.odom_compared)),
        ('HeadYaw against torso -> Neck', '%s (%d compared)' % (num(v.head_worst_rad, 3, 'rad'), v.head_compared))])]
    head = ['frame', 'sensors in it']
    blocks += [Heading('The sensors\' frames in the tree'),
               Table(head, _rows(v, marks, _ancestors(v, list(marks))))]
    blocks.append(Details('The whole tree (%d pairs)' % v.pairs, [Table(head, _rows(v, marks, set()))]))
    return blocks
