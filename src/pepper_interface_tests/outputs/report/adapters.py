"""Adapters: today's `SensorResult.values` / `.series` dicts -> the typed values of values.py.

Every dict key the report reads is in this one module (docs/results.md lists the keys). The
adapters are tolerant of missing keys, unknown keys and None, so a check that adds a value or
a new verdict never breaks the page. When a check produces its dataclass directly, its adapter
here is deleted and nothing else changes.
"""
import math
import re
from typing import Any, Callable, Dict, Optional

from ...results import RunResult, SensorResult, printable
from ...sensors.health import HealthValues, JointRow
from ...sensors.touch import TouchValues, ZoneRow
from .values import (
    AudioValues,
    CameraValues,
    ChannelLevel,
    DepthValues,
    FamilyValues,
    Histogram,
    ImuValues,
    Joint,
    JointValues,
    LaserScanValues,
    OdometryValues,
    RangeValues,
    Series,
    SpeechValues,
    Spread,
    VideoInfo,
    mapping,
    number,
)


def _range(r: SensorResult, run: RunResult) -> RangeValues:
    limits = dict((k, v) for k, v in (tuple(f[:2]) for f in r.fields or [] if len(f) >= 2))
    return RangeValues(Series.of(r.series.get('range_m')), number(limits.get('Minimum range value')),
                       number(limits.get('Maximum range value')))


def _laser(r: SensorResult, run: RunResult) -> Optional[LaserScanValues]:
    s = mapping(r.series.get('last_scan'))
    try:
        return LaserScanValues(float(s['angle_min']), float(s['angle_increment']),
                               [float('nan') if v is None else float(v) for v in s['ranges']],
                               float(s['range_min']), float(s['range_max']), number(s.get('blind_value')),
                               [str(k) for k in s['kinds']])
    except (KeyError, TypeError, ValueError):
        return None


def _video(r: SensorResult) -> Optional[VideoInfo]:
    v = r.values
    recording_off = 'recording off' in (r.notes or [])
    if not isinstance(v.get('video'), dict):
        if r.artifacts.get('video'):
            return VideoInfo(file=r.artifacts['video'])
        return VideoInfo(recording_off=True) if recording_off else None
    d = v['video']
    return VideoInfo(file=r.artifacts.get('video') or d.get('file'), codec=d.get('codec'), fps=number(d.get('fps')),
                     frames_received=d.get('frames_received'), frames_written=d.get('frames_written'),
                     error=d.get('error'), notes=[n[len('video: '):] for n in r.notes or [] if n.startswith('video: ')])


def _camera(r: SensorResult, run: RunResult) -> CameraValues:
    v = r.values
    frames = [(r.artifacts[k], c) for k, c in (('first_frame', 'first frame'), ('last_frame', 'last frame'))
              if r.artifacts.get(k)]
    return CameraValues(frames, _video(r), v.get('width'), v.get('height'), v.get('encoding'),
                        Spread.of(v.get('brightness_mean')), Spread.of(v.get('brightness_spread')),
                        v.get('frames_black'), v.get('frames_constant'), v.get('longest_identical_run'),
                        v.get('stereo') if isinstance(v.get('stereo'), dict) else None,
                        Series.of(r.series.get('brightness')))


def _histogram(hist: Any) -> Optional[Histogram]:
    """{'edges'|'centres': [...], 'counts': [...]} or rows [low, high, count] / [centre, count]."""
    edges = counts = None
    if isinstance(hist, dict):
        counts = hist.get('counts') or hist.get('count')
        for key in ('edges', 'edges_m', 'bins_m', 'bins', 'centres', 'centers'):
            edges = edges or hist.get(key)
    elif isinstance(hist, (list, tuple)) and hist and isinstance(hist[0], (list, tuple)):
        if len(hist[0]) >= 3:
            edges, counts = [h[0] for h in hist] + [hist[-1][1]], [h[2] for h in hist]
        else:
            edges, counts = [h[0] for h in hist], [h[1] for h in hist]
    elif isinstance(hist, (list, tuple)):
        counts = list(hist)
    try:
        counts = [float(c) for c in counts or []]
        edges = [float(e) for e in edges] if edges else None
    except (TypeError, ValueError):
        return None
    if not counts:
        return None
    if edges is None or len(edges) not in (len(counts), len(counts) + 1):
        return Histogram(list(range(len(counts) + 1)), counts, 'bin')
    return Histogram(edges, counts)


def _depth(r: SensorResult, run: RunResult) -> DepthValues:
    v = r.values
    lo_hi = v.get('video_range_m')
    if not (isinstance(lo_hi, (list, tuple)) and len(lo_hi) >= 2 and None not in lo_hi[:2]):
        lo_hi = (0.0, 5.0)           # expectations.DepthExpect.video_range's default
    return DepthValues(_camera(r, run), tuple(lo_hi[:2]), Spread.of(v.get('depth_m'), 'median'),
                       Spread.of(v.get('valid_share')), v.get('frames_all_zero'),
                       _histogram(v.get('depth_histogram')), Series.of(r.series.get('median_depth_m')),
                       Series.of(r.series.get('valid_share')))


def _audio(r: SensorResult, run: RunResult) -> AudioValues:
    v = r.values
    chans = mapping(v.get('channels') or v.get('levels'))
    names = list(chans) or [k[len('level_dbfs_'):] for k in r.series if k.startswith('level_dbfs_')]
    out = []
    for name in names:
        lv = mapping(chans.get(name))
        level = Series.of(r.series.get('level_dbfs_' + name))
        rms = number(lv.get('rms_dbfs'))
        silent = bool(lv.get('all_zero')) or (bool(lv) and rms is None) or \
            (bool(level) and all(math.isnan(y) for y in level.v))
        out.append(ChannelLevel(str(name), rms, number(lv.get('peak_dbfs')), number(lv.get('clipping_share')),
                                silent, level))
    for c in out:          # a channel the check failed as silent (below silence_dbfs) is marked too
        if any('microphone %s is silent' % c.name in str(x) for x in r.reasons or []):
            c.silent = True
    wavs = [r.artifacts.get('audio') or r.artifacts.get('wav')]
    wavs += [n for k, n in r.artifacts.items() if k.startswith('audio_')]
    speech = next((s for s in run.sensors if s.name == 'speech'), None)
    in_run = speech is not None and bool(speech.messages)
    sv = mapping(speech.values) if speech is not None and in_run else {}
    return AudioValues(out, number(v.get('sample_rate_hz')), number(v.get('sample_rate_expected_hz')),
                       [w for w in wavs if w], 'recording off' in (r.notes or []),
                       sv.get('heard'), in_run, number(sv.get('level_rise_db')))


def _joints(r: SensorResult, run: RunResult) -> JointValues:
    joints = mapping(r.values.get('joints'))
    return JointValues([Joint(str(n), Spread.of(mapping(d).get('position')), Spread.of(mapping(d).get('velocity')),
                              Spread.of(mapping(d).get('effort'))) for n, d in joints.items()])


def _odometry(r: SensorResult, run: RunResult) -> OdometryValues:
    return OdometryValues(Series.of(r.series.get('x_m')), Series.of(r.series.get('y_m')))


def _imu(r: SensorResult, run: RunResult) -> ImuValues:
    return ImuValues(Series.of(r.series.get('acceleration_m_s2')), Series.of(r.series.get('angular_velocity_rad_s')))


def _speech(r: SensorResult, run: RunResult) -> SpeechValues:
    v = r.values
    subs = v.get('subscribers')
    subs = subs if isinstance(subs, (list, tuple)) else []
    return SpeechValues(v.get('text'), [str(s) for s in subs], v.get('heard'), number(v.get('level_rise_db')))


def _rows(items: Any, cls: Any) -> tuple:
    """Dicts of a dataclass's fields -> its objects (unknown keys dropped, bad items skipped)."""
    names = set(cls.__dataclass_fields__)
    out = []
    for item in items if isinstance(items, (list, tuple)) else []:
        if isinstance(item, dict):
            try:
                out.append(cls(**{k: v for k, v in item.items() if k in names}))
            except TypeError:
                continue
    return tuple(out)


def _touch(r: SensorResult, run: RunResult) -> Optional[TouchValues]:
    v = r.values
    if 'zones' not in v:
        return None
    return TouchValues(str(v.get('mode') or '-'), _rows(v.get('zones'), ZoneRow))


def _health(r: SensorResult, run: RunResult) -> Optional[HealthValues]:
    v = r.values
    if 'driver_arrays' not in v:
        return None
    return HealthValues(v.get('driver_arrays') or 0, v.get('battery_percent'), v.get('charging'),
                        v.get('fully_charged'), v.get('battery_level'), v.get('battery_message'),
                        number(v.get('highest_temperature_c')), _rows(v.get('hottest'), JointRow),
                        _rows(v.get('hot'), JointRow))


Adapter = Callable[[SensorResult, RunResult], Optional[FamilyValues]]
ADAPTERS: Dict[str, Adapter] = {
    'range': _range, 'laser': _laser, 'camera': _camera, 'depth': _depth, 'audio': _audio,
    'joints': _joints, 'odometry': _odometry, 'imu': _imu, 'speech': _speech,
    'touch': _touch, 'health': _health}


def adapt(family: Optional[str], result: SensorResult, run: RunResult) -> Optional[FamilyValues]:
    """The family's values object for `result`, or None for a family without an adapter."""
    fn = ADAPTERS.get(family) if family is not None else None
    if fn is None:
        return None
    if not isinstance(result.series, dict):
        result.series = {}
    if not isinstance(result.values, dict):
        result.values = {}
    return fn(result, run)


# ---------------------------------------------------------------- text shown on the page

_NONE = re.compile(r'(?<![\w+/=])None(?![\w+/=])')


def clean(text: Any) -> str:
    """Text for the page: None -> '-', Python's 'None' inside a message -> '-', control
    characters shown as \\xNN instead of breaking the layout."""
    if text is None:
        return '-'
    return printable(_NONE.sub('-', str(text)), one_line=False)
