"""Every matplotlib figure of the report, as a PNG data: URI.

Figures use the Agg canvas directly (no pyplot state, no display). Sizes are chosen for a
1400-px-wide browser window at 100 % zoom: pages are about 1350 px wide inside their margins,
so the widest figure is 13 in x 100 dpi = 1300 px and is shown at its natural size, where
11 pt text is about 15 px, as large as the page's own text. Constrained layout keeps labels
inside the image; only the laser's polar plot, whose legend sits outside its axes, takes the
second drawing pass of `bbox_inches='tight'`.
"""
import base64
import io
import math
from typing import TYPE_CHECKING, Any, Optional, Sequence, Tuple

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from matplotlib.ticker import MaxNLocator

    from ...sensors.values.laser import LastScan
    from .context import RateRow
    from .values import ChannelLevel, Histogram, Series

DPI = 100
FONT_PT = 11
BLUE, RED, GREEN, GREY, AMBER, PURPLE = '#0969da', '#cf222e', '#2da44e', '#8c959f', '#9a6700', '#8250df'
CHANNEL_COLOURS = ('#1f77b4', '#ff7f0e', '#2ca02c', '#d62728')
T_LABEL = 's since listening began'


def figure(w: float, h: float, **kw: Any) -> 'Figure':
    import matplotlib
    matplotlib.rcParams.update({'font.size': FONT_PT, 'axes.titlesize': FONT_PT, 'axes.labelsize': FONT_PT,
                                'xtick.labelsize': FONT_PT - 1, 'ytick.labelsize': FONT_PT - 1,
                                'legend.fontsize': FONT_PT - 1})
    from matplotlib.figure import Figure
    # constrained_layout=True: what matplotlib 3.1 (Ubuntu 20.04) and today's both take;
    # layout='constrained', its newer spelling, arrived in 3.5
    return Figure(figsize=(w, h), dpi=DPI, constrained_layout=True, **kw)


def uri(fig: 'Figure', tight: bool = False) -> str:
    """The figure as a PNG data: URI. Constrained layout fits what is inside the figure;
    `tight` (a second drawing pass, as costly as the first) is for a legend placed outside the
    axes, which constrained layout does not make room for on a polar plot."""
    buf = io.BytesIO()
    if tight:
        fig.savefig(buf, format='png', dpi=DPI, bbox_inches='tight', pad_inches=0.08)
    else:
        fig.savefig(buf, format='png', dpi=DPI)
    return 'data:image/png;base64,' + base64.b64encode(buf.getvalue()).decode('ascii')


def _stairs(ax: 'Axes', values: Sequence[float], edges: Sequence[float], **kw: Any) -> None:
    """Axes.stairs(values, edges, baseline=None) in what matplotlib 3.1 (Ubuntu 20.04) has too
    (stairs arrived in 3.4): a step line holding each value over its bin."""
    ax.step(list(edges), list(values) + list(values[-1:]), where='post', **kw)


def _grid(*axes: 'Axes') -> None:
    for a in axes:
        a.grid(True, alpha=0.3)


def rates(rows: Sequence['RateRow'], t_end: float) -> str:
    """rows: [RateRow] (page.py): one strip per sensor, coloured by its rate's own verdict."""
    fig = figure(13, 0.62 * len(rows) + 1.0)
    axes = fig.subplots(len(rows), 1, sharex=True, squeeze=False)[:, 0]
    for ax, r in zip(axes, rows):
        colour = BLUE if r.in_band else (RED if r.in_band is False else GREY)
        top = max(r.rates + [1.0])
        if r.band:
            ax.fill_between([r.start, r.end], [r.band[0]] * 2, [r.band[1]] * 2, color=GREEN, alpha=0.18, lw=0)
            top = max(top, r.band[1])
        if r.nominal:
            ax.hlines(r.nominal, r.start, r.end, colors=GREEN, linestyles='dashed', lw=0.9)
        if r.rates:
            _stairs(ax, r.rates, r.edges, color=colour, lw=1.8)
        if not r.rates or max(r.rates) == 0:
            ax.text(0.5, 0.5, 'no messages', transform=ax.transAxes, ha='center', va='center', color=RED)
        ax.text(1.005, 0.5, r.label, transform=ax.transAxes, ha='left', va='center', color=colour,
                fontweight='bold' if r.in_band is False else 'normal')
        ax.set_ylim(0, top * 1.2)
        ax.set_ylabel(r.name, rotation=0, ha='right', va='center')
        ax.set_xlim(0, max(t_end, 1.0))
        ax.yaxis.set_major_locator(_locator(3))
        _grid(ax)
    axes[-1].set_xlabel('seconds since the start of the run')
    fig.suptitle('messages per second (1 s bins). Green band: expected rate, dashed: nominal. '
                 'Line blue: rate in band, red: rate outside its band, grey: no band', fontsize=FONT_PT)
    return uri(fig)


def _locator(n: int) -> 'MaxNLocator':
    from matplotlib.ticker import MaxNLocator
    return MaxNLocator(n)


def range_over_time(s: 'Series', lo: Optional[float], hi: Optional[float]) -> str:
    fig = figure(8, 2.6)
    ax = fig.subplots()
    ax.plot(s.t, s.v, '.-', color=BLUE, ms=4, lw=1)
    for y, label in ((lo, 'min_range'), (hi, 'max_range')):
        if y is not None:
            ax.axhline(y, color=AMBER, ls='--', lw=0.9)
            ax.text(s.t[0], y, ' ' + label, va='bottom', color=AMBER)
    bad = [t for t, v in zip(s.t, s.v) if v != v]
    if bad:
        ax.plot(bad, [0] * len(bad), 'x', color=RED, label='no finite range (inf/NaN)')
        ax.legend(loc='upper right')
    ax.set_xlabel(T_LABEL)
    ax.set_ylabel('range (m)')
    _grid(ax)
    return uri(fig)


def laser_scan(scan: 'LastScan') -> str:
    """The last scan, each beam drawn as the check judged it (returns at their distance, also
    beyond the advertised range_max: naoqi_driver does not clip; see docs/checks.md). The
    legend names each kind by its description (sensors/values/laser.py BeamKind)."""
    import numpy as np

    from ...sensors.values.laser import BeamKind
    RETURN, BLIND, NO_RETURN, INVALID = BeamKind.RETURN, BeamKind.BLIND, BeamKind.NO_RETURN, BeamKind.INVALID
    angles = scan.angle_min + scan.angle_increment * np.arange(len(scan.ranges))
    rng = np.array(scan.ranges, dtype=float)
    kinds = np.array([k.value for k in scan.kinds])
    returns = (kinds == RETURN.value) & np.isfinite(rng)
    far = float(rng[returns].max()) if returns.any() else 0.0
    edge = max(scan.range_max, far) * 1.05        # beams without a distance are drawn here
    fig = figure(8, 5.2)
    ax = fig.add_subplot(projection='polar')
    ax.set_theta_zero_location('N')      # forward (x) up, left (+y) to the left, as in ROS
    ax.set_theta_direction(1)
    if len(angles) and math.degrees(angles.max() - angles.min()) < 359:
        ax.set_thetamin(math.degrees(angles.min()))
        ax.set_thetamax(math.degrees(angles.max()))
    ax.plot(angles[returns], rng[returns], '.', color=BLUE, ms=6,
            label='%s (%d)' % (RETURN.description, (kinds == RETURN.value).sum()))
    for kind, colour, marker, value in (
            (BLIND, GREY, 'x', '%g' % scan.blind_value if scan.blind_value is not None else '?'),
            (NO_RETURN, AMBER, 'o', None),
            (INVALID, RED, 'x', '%g m' % scan.range_min)):
        label = kind.description + (' (%s)' % value if value else '')
        mask = kinds == kind.value
        if mask.any():
            ax.plot(angles[mask], np.full(mask.sum(), edge), marker, color=colour, ms=7 if kind == INVALID else 6,
                    mfc='none' if marker == 'o' else colour, label='%s (%d)' % (label, mask.sum()))
    if len(angles) and scan.range_max < edge:
        arc = np.linspace(angles.min(), angles.max(), 90)
        ax.plot(arc, np.full(90, scan.range_max), ':', color=AMBER, lw=0.9,
                label='advertised range_max %g m' % scan.range_max)
    ax.set_rmax(edge * 1.02)
    ax.set_rmin(0)
    ax.plot([0], [0], marker='^', color='k', ms=7)
    ax.legend(loc='center left', bbox_to_anchor=(1.02, 0.5), frameon=False)
    ax.set_title('last scan (m); forward is up')
    return uri(fig, tight=True)


def brightness(s: 'Series') -> str:
    fig = figure(8, 2.2)
    ax = fig.subplots()
    ax.plot(s.t, s.v, '.-', ms=4, lw=1, color=BLUE)
    ax.set_ylim(0, 255)
    ax.set_ylabel('brightness')
    ax.set_xlabel(T_LABEL)
    _grid(ax)
    return uri(fig)


def depth_over_time(median: 'Series', valid: 'Series') -> str:
    fig = figure(8, 3.2)
    a1, a2 = fig.subplots(2, 1, sharex=True)
    a1.plot(median.t, median.v, '.-', ms=4, lw=1, color=BLUE)
    a1.set_ylabel('median (m)')
    a2.plot(valid.t, [100 * y for y in valid.v], '.-', ms=4, lw=1, color=PURPLE)
    a2.set_ylabel('valid %')
    a2.set_ylim(0, 105)
    a2.set_xlabel(T_LABEL)
    _grid(a1, a2)
    return uri(fig)


def colour_scale(lo: float, hi: float) -> str:
    import matplotlib
    fig = figure(1.5, 3.0)
    ax = fig.subplots()
    norm = matplotlib.colors.Normalize(vmin=float(lo), vmax=float(hi))
    fig.colorbar(matplotlib.cm.ScalarMappable(norm=norm, cmap='jet'), cax=ax, label='depth (m)')
    return uri(fig)


def histogram(h: 'Histogram') -> str:
    fig = figure(8, 2.4)
    ax = fig.subplots()
    if len(h.edges) == len(h.counts) + 1:
        ax.hist(h.edges[:-1], bins=h.edges, weights=h.counts, histtype='stepfilled', color=BLUE,
                alpha=0.7)   # Axes.stairs(fill=True), which arrived in matplotlib 3.4
    else:
        width = (h.edges[1] - h.edges[0]) if len(h.edges) > 1 else 1.0
        ax.bar(h.edges, h.counts, width=width * 0.9, color=BLUE, alpha=0.7)
    ax.set_xlabel(h.unit)
    ax.set_ylabel('pixels')
    _grid(ax)
    return uri(fig)


def levels_per_channel(channels: Sequence['ChannelLevel']) -> str:
    """One strip per microphone channel on a shared time and dB axis; a silent channel is
    drawn on a red background with 'silent' written across it, so it cannot hide."""
    fig = figure(6.2, 0.95 * len(channels) + 0.9)
    axes = fig.subplots(len(channels), 1, sharex=True, sharey=True, squeeze=False)[:, 0]
    finite = [v for c in channels for v in c.level.v if v == v and math.isfinite(v)]
    lo = min(finite + [-60.0]) - 5
    for i, (ax, c) in enumerate(zip(axes, channels)):
        if c.level:
            ax.plot(c.level.t, c.level.v, lw=1.3, color=CHANNEL_COLOURS[i % 4])
        if c.silent:
            ax.set_facecolor('#ffebe9')
            ax.text(0.5, 0.5, 'silent', transform=ax.transAxes, ha='center', va='center', color=RED,
                    fontweight='bold')
        ax.set_ylabel(c.name, rotation=0, ha='right', va='center')
        ax.yaxis.set_major_locator(_locator(3))
        _grid(ax)
    axes[0].set_ylim(lo, 3)
    axes[-1].set_xlabel(T_LABEL)
    return uri(fig)


def waveform(path: str, name: str, max_seconds: float = 300.0, bins: int = 900) -> Optional[str]:
    """Min/max envelope of every channel of a WAV file, one row per channel, each at its own
    scale with its peak written. Returns the URI, or raises what soundfile raised."""
    import numpy as np
    import soundfile
    with soundfile.SoundFile(path) as f:
        rate, nch = f.samplerate, f.channels
        data = f.read(frames=int(max_seconds * rate), dtype='int16', always_2d=True)
    if not len(data):
        return None
    from ...sensors.values.audio import CHANNELS
    names = list(CHANNELS) if nch == 4 else ['channel %d' % (i + 1) for i in range(nch)]
    k = max(1, len(data) // bins)
    m = (len(data) // k) * k
    t = np.arange(m // k) * k / float(rate)
    fig = figure(6.2, 0.95 * nch + 0.9)
    axes = fig.subplots(nch, 1, sharex=True, squeeze=False)[:, 0]
    for i, ax in enumerate(axes):
        block = data[:m, i].reshape(-1, k) / 32768.0
        ax.fill_between(t, block.min(axis=1), block.max(axis=1), color=CHANNEL_COLOURS[i % 4], lw=0.3)
        peak = float(np.abs(block).max()) if block.size else 0.0
        ax.set_ylim(-max(peak, 1e-4) * 1.1, max(peak, 1e-4) * 1.1)   # each channel at its own scale
        ax.text(0.995, 0.92, 'peak %.1f dBFS' % (20 * math.log10(peak)) if peak > 0 else 'silent: all samples zero',
                transform=ax.transAxes, ha='right', va='top', color=RED if peak == 0 else '#1f2328',
                bbox={'facecolor': 'white', 'alpha': 0.8, 'edgecolor': 'none', 'pad': 1})
        ax.set_ylabel(names[i], rotation=0, ha='right', va='center')
        ax.set_yticks([])
        _grid(ax)
    axes[-1].set_xlabel('s (%s, %d Hz, %d channel%s)' % (name, rate, nch, '' if nch == 1 else 's'))
    return uri(fig)


def odometry(x: 'Series', y: 'Series') -> str:
    fig = figure(10, 3.0)
    a1, a2 = fig.subplots(1, 2, gridspec_kw={'width_ratios': [2.2, 1]})
    a1.plot(x.t, x.v, lw=1.4, label='x')
    if len(y.v) == len(x.t):
        a1.plot(x.t, y.v, lw=1.4, label='y')
        a2.plot(x.v, y.v, '.-', ms=3, lw=1, color=PURPLE)
        a2.plot(x.v[:1], y.v[:1], 'o', color=GREEN, ms=6)
        a2.set_xlabel('x (m)')
        a2.set_ylabel('y (m)')
        a2.set_aspect('equal', adjustable='datalim')
        a2.set_title('path (start: green dot)')
        _grid(a2)
    a1.set_xlabel(T_LABEL)
    a1.set_ylabel('position (m)')
    a1.legend()
    _grid(a1)
    return uri(fig)


def imu(acc: 'Series', gyro: 'Series') -> str:
    fig = figure(8, 3.2)
    a1, a2 = fig.subplots(2, 1, sharex=True)
    a1.plot(acc.t, acc.v, lw=1.3, color=BLUE)
    a1.set_ylabel('|a| (m/s²)')
    a2.plot(gyro.t, gyro.v, lw=1.3, color='#bf3989')
    a2.set_ylabel('|ω| (rad/s)')
    a2.set_xlabel(T_LABEL)
    _grid(a1, a2)
    return uri(fig)


def trend(label: str, unit: str, points: Sequence[Any], baseline: Optional[str]) -> str:
    """One value over the runs of the history, oldest first: points [(run id, value)], the
    baseline run's point and this run's (the last) marked."""
    fig = figure(6.2, 2.0)
    ax = fig.subplots()
    xs = list(range(len(points)))
    ys = [v for _, v in points]
    ax.plot(xs, ys, '.-', ms=5, lw=1, color=GREY)
    for i, (run_id, v) in enumerate(points):
        if run_id == baseline:
            ax.plot([i], [v], 'o', ms=7, color=GREEN, label='baseline')
    ax.plot([xs[-1]], [ys[-1]], 'o', ms=7, color=AMBER, label='this run')
    ax.set_xticks(xs[::max(1, len(xs) // 6)])
    ax.set_xticklabels([points[i][0] for i in xs[::max(1, len(xs) // 6)]], rotation=0, fontsize=FONT_PT - 3)
    ax.set_ylabel(unit or label)
    ax.set_title(label)
    ax.legend(loc='best')
    _grid(ax)
    return uri(fig)


def motion(base: Sequence[Tuple[str, 'Series']], head: Sequence[Tuple[str, 'Series']],
           shift: 'Series') -> str:
    """The motion check: the base's commanded yaw against each witness (odometry, integrated
    gyro, laser turn), HeadYaw commanded against measured, and the picture's sideways shift."""
    fig = figure(10, 5.4)
    a1, a2 = fig.subplots(2, 1, sharex=True)
    for label, s in base:
        if s:
            a1.plot(s.t, s.v, lw=2.2 if label == 'commanded' else 1.3, label=label,
                    drawstyle='steps-post' if label == 'commanded' else 'default')
    a1.set_ylabel('base yaw change (rad)')
    a1.legend(fontsize=8)
    for label, s in head:
        if s:
            a2.plot(s.t, s.v, lw=1.8 if label == 'HeadYaw commanded' else 1.3, label=label,
                    drawstyle='steps-post' if label == 'HeadYaw commanded' else 'default')
    a2.set_ylabel('HeadYaw (rad)')
    if shift:
        a3 = a2.twinx()
        a3.plot(shift.t, shift.v, lw=1.0, color=PURPLE, ls='--', label='picture shift')
        a3.set_ylabel('picture shift (px)')
        a3.legend(loc='lower right', fontsize=8)
    a2.legend(loc='upper right', fontsize=8)
    a2.set_xlabel(T_LABEL)
    _grid(a1, a2)
    return uri(fig)
