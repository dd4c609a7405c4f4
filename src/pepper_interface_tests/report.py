"""HTML report: one self-contained file per run, sensorTestReport.html in the run's folder.

Everything the page shows is inside the file: plots are matplotlib figures (Agg, no display,
no pyplot state) embedded as PNG, camera frames as the JPEG files the checks wrote, videos and
WAV files as data: URIs when a file is at most `max_embed` bytes (default 20 MB; larger files
are played from a relative link to the file next to the report). No script, font or style is
loaded from anywhere else, so the page opens offline and can be mailed as one file (or with
its folder when it links large recordings).

Contents: run header (platform, mode, source, run id, times, counts, interruption), a summary
table (sensor, topic, verdict and reasons, messages, rate against the expected band, links to
the recordings), one plot of every sensor's rate over the run with its expected band, then one
section per sensor (id "sensor-<name>") with its reasons, warnings, notes, stream statistics
and what its family measured:
  sonar       range over time with the sensor's limits
  laser       polar plot of the last scan, invalid and blind beams marked
  camera      first and last frame, the video (H.264 plays in the page; an MPEG-4 part 2 file
              cannot play in browsers and is linked instead), brightness / frozen statistics
  depth       the colour-mapped first and last frame with the colour scale, the video, the depth
              histogram when the check recorded one ('depth_histogram' in values), median depth
              and valid pixels over time
  microphone  levels per channel, waveform per channel (read from the WAV), the WAV player, and
              whether the speech check's sentence was heard
  joints      a table of every joint's position / velocity / effort range
  odometry    x and y over time and the path; IMU: |acceleration| and |angular velocity|
  speech      the sentence, who received it, whether the microphones heard it
Missing parts (no recording, a check that produced no series) are left out or said in words.

`HtmlReport` is the runner observer: it writes the report on run_ended (also for an interrupted
run) and never fails the run; a report error is printed as one warning line.
"""
import base64
import html
import io
import math
import os
import sys
import time

from . import catalog
from .results import FAIL, PASS, SKIPPED, summary_line, timestamp

REPORT_FILE = 'sensorTestReport.html'
MAX_EMBED_BYTES = 20 * 1024 * 1024
DPI = 80
COLOURS = {PASS: '#1a7f37', FAIL: '#cf222e', SKIPPED: '#9a6700'}
CHANNEL_COLOURS = ('#1f77b4', '#ff7f0e', '#2ca02c', '#d62728')
BROWSER_CODECS = ('avc1', 'avc3', 'vp09', 'av01')


class HtmlReport:
    """Runner observer: writes sensorTestReport.html into `folder` when the run ends."""

    def __init__(self, folder, out=None, max_embed=MAX_EMBED_BYTES):
        self.folder = folder
        self.out = out
        self.max_embed = max_embed

    def run_started(self, run, plan):
        # import matplotlib now, in the background, so that writing the report at the end
        # (also after Ctrl-C) does not wait for it
        import threading
        threading.Thread(target=_warm_up, daemon=True, name='report-warm-up').start()

    def run_ended(self, run):
        stream = self.out or sys.stdout
        t0 = time.monotonic()
        try:
            path = write_report(run, self.folder, max_embed=self.max_embed)
            size = os.path.getsize(path)
            stream.write('report: %s (%s, %.1f s)\n' % (
                path, '%.1f MB' % (size / 1e6) if size >= 1e6 else '%d kB' % round(size / 1e3),
                time.monotonic() - t0))
        except (Exception, KeyboardInterrupt) as e:   # the report never fails the run
            text = str(e).strip().splitlines()[0] if str(e).strip() else ''
            stream.write('sensorTest: warning: HTML report not written: %s%s\n'
                         % (type(e).__name__, (': ' + text) if text else ''))
        stream.flush()


def _warm_up():
    try:
        import matplotlib
        from matplotlib.figure import Figure  # noqa: F401
        from matplotlib.backends import backend_agg  # noqa: F401
    except Exception:  # the report says what went wrong when it is written
        pass


def write_report(run, folder=None, max_embed=MAX_EMBED_BYTES):
    """Render `run` and write <folder>/sensorTestReport.html (folder: the run's output_dir).
    Returns the path."""
    folder = folder or run.output_dir or '.'
    path = os.path.join(folder, REPORT_FILE)
    text = render(run, folder, max_embed)
    tmp = os.path.join(folder, '.%s.%d.tmp' % (REPORT_FILE, os.getpid()))
    try:   # a whole file or none; created with the user's umask (a report is meant to be shared)
        with open(tmp, 'w', encoding='utf-8') as f:
            f.write(text)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    return path


# ---------------------------------------------------------------- small helpers

def esc(x):
    return html.escape('' if x is None else str(x), quote=True)


def num(v, nd=2, unit=''):
    if v is None:
        return '-'
    if isinstance(v, float):
        if not math.isfinite(v):
            return str(v)
        text = '%.*f' % (nd, v)
    else:
        text = str(v)
    return text + ((' ' + unit) if unit else '')


def band_text(band):
    return '%g&ndash;%g' % tuple(band) if band else '-'


def anchor(name):
    return 'sensor-' + ''.join(c if c.isalnum() or c in '-_' else '-' for c in name)


def _series_xy(points):
    """[(t, v)] with None values -> two float lists (None -> nan)."""
    xs, ys = [], []
    for p in points or []:
        try:
            t, v = p[0], p[1]
        except (TypeError, IndexError):
            continue
        xs.append(float(t))
        ys.append(float('nan') if v is None else float(v))
    return xs, ys


def _figure(w, h, **kw):
    import matplotlib
    matplotlib.rcParams['font.size'] = 9
    from matplotlib.figure import Figure
    return Figure(figsize=(w, h), dpi=DPI, layout='constrained', **kw)


def png(fig, alt):
    buf = io.BytesIO()
    fig.savefig(buf, format='png', dpi=DPI)
    data = base64.b64encode(buf.getvalue()).decode('ascii')
    return '<img class="plot" alt="%s" src="data:image/png;base64,%s">' % (esc(alt), data)


def video_codec(data):
    """The sample format of the first track of an mp4 (e.g. 'avc1', 'mp4v'), or None."""
    i = data.rfind(b'stsd')
    if i < 0 or i + 20 > len(data):
        return None
    tag = data[i + 16:i + 20]
    try:
        return tag.decode('ascii')
    except UnicodeDecodeError:
        return None


def _flatten(prefix, value, out, depth=0):
    if isinstance(value, dict) and depth < 3:
        for k, v in value.items():
            _flatten('%s.%s' % (prefix, k) if prefix else str(k), v, out, depth + 1)
    elif isinstance(value, (list, tuple)) and (len(value) > 8 or any(isinstance(v, (list, dict)) for v in value)):
        out.append((prefix, '[%d items]' % len(value)))
    elif isinstance(value, float):
        out.append((prefix, num(value, 4)))
    else:
        out.append((prefix, '-' if value is None else str(value)))


def _kv_table(rows, cls='kv'):
    body = ''.join('<tr><th>%s</th><td>%s</td></tr>' % (esc(k), v) for k, v in rows)
    return '<table class="%s">%s</table>' % (cls, body)


# ---------------------------------------------------------------- the page

CSS = '''
:root { --pass: #1a7f37; --fail: #cf222e; --skip: #9a6700; --line: #d0d7de; --soft: #f6f8fa; }
* { box-sizing: border-box; }
body { font-family: system-ui, -apple-system, "Segoe UI", Roboto, "DejaVu Sans", sans-serif;
       margin: 0; padding: 0 24px 48px; color: #1f2328; background: #fff; font-size: 14px; }
header { padding: 16px 0 8px; border-bottom: 1px solid var(--line); margin-bottom: 16px; }
h1 { font-size: 22px; margin: 0 0 6px; } h2 { font-size: 18px; margin: 0 0 8px; }
h3 { font-size: 14px; margin: 14px 0 6px; }
.meta { color: #59636e; } .meta b { color: #1f2328; }
.badge { display: inline-block; padding: 1px 8px; border-radius: 10px; color: #fff; font-weight: 600;
         font-size: 12px; vertical-align: middle; }
.PASS { background: var(--pass); } .FAIL { background: var(--fail); } .SKIPPED { background: var(--skip); }
.banner { padding: 8px 12px; border-radius: 6px; margin: 8px 0; font-weight: 600; }
.banner.bad { background: #ffebe9; color: var(--fail); border: 1px solid #ff8182; }
.banner.good { background: #dafbe1; color: var(--pass); border: 1px solid #4ac26b; }
.banner.warn { background: #fff8c5; color: var(--skip); border: 1px solid #d4a72c; }
table { border-collapse: collapse; margin: 4px 0 8px; }
th, td { border: 1px solid var(--line); padding: 3px 8px; text-align: left; vertical-align: top; }
th { background: var(--soft); font-weight: 600; }
td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
td.out { color: var(--fail); font-weight: 600; }
table.summary td.reasons { max-width: 560px; }
table.kv th { width: 220px; }
.warn-text { color: var(--skip); } .fail-text { color: var(--fail); }
section.sensor { border: 1px solid var(--line); border-left: 6px solid var(--line); border-radius: 6px;
                 padding: 12px 16px; margin: 16px 0; }
section.sensor.PASS-box { border-left-color: var(--pass); }
section.sensor.FAIL-box { border-left-color: var(--fail); }
section.sensor.SKIPPED-box { border-left-color: var(--skip); }
ul { margin: 4px 0 8px; padding-left: 22px; }
ul.reasons li { color: var(--fail); } ul.warnings li { color: var(--skip); } ul.notes li { color: #59636e; }
.row { display: flex; flex-wrap: wrap; gap: 16px; align-items: flex-start; }
figure { margin: 0; } figcaption { color: #59636e; font-size: 12px; }
img.frame { max-width: 360px; max-height: 280px; border: 1px solid var(--line); display: block; }
img.plot { max-width: 100%; height: auto; display: block; }
video { max-width: 480px; max-height: 360px; background: #000; display: block; }
audio { width: 420px; display: block; }
details { margin: 6px 0; } summary { cursor: pointer; color: #0969da; }
code { background: var(--soft); padding: 0 4px; border-radius: 4px; }
footer { margin-top: 24px; color: #59636e; font-size: 12px; }
'''


class _Renderer:
    def __init__(self, run, folder, max_embed):
        self.run = run
        self.folder = folder
        self.max_embed = max_embed
        self.by_name = {s.name: s for s in run.sensors}
        self.problems = []       # things the report could not show (said at the bottom)

    # ---- files ----------------------------------------------------------------------------
    def path(self, name):
        return os.path.join(self.folder, name)

    def read(self, name):
        try:
            with open(self.path(name), 'rb') as f:
                return f.read()
        except OSError:
            return None

    def link(self, name, text=None):
        return '<a href="%s">%s</a>' % (esc(name), esc(text or name))

    def frame(self, name, caption):
        data = self.read(name)
        if data is None:
            return '<p class="warn-text">%s: file %s not found</p>' % (esc(caption), esc(name))
        mime = 'image/png' if name.lower().endswith('.png') else 'image/jpeg'
        return ('<figure><a href="%s"><img class="frame" alt="%s" src="data:%s;base64,%s"></a>'
                '<figcaption>%s</figcaption></figure>'
                % (esc(name), esc(caption), mime, base64.b64encode(data).decode('ascii'), esc(caption)))

    def media(self, tag, name, mime, codec=None):
        """<video>/<audio> with the file inside when small enough, else a relative link."""
        full = self.path(name)
        if not os.path.exists(full):
            return '<p class="warn-text">recording %s not found</p>' % esc(name)
        size = os.path.getsize(full)
        if tag == 'video':
            data = self.read(name) if size <= self.max_embed else None
            if codec is None and data is not None:
                codec = video_codec(data)
            if codec and codec not in BROWSER_CODECS:
                return ('<p>Video %s (%s, %.1f MB): browsers cannot play this codec; open it with a '
                        'media player (VLC, mpv).</p>' % (self.link(name), esc(codec), size / 1e6))
        else:
            data = self.read(name) if size <= self.max_embed else None
        if data is not None:
            src = 'data:%s;base64,%s' % (mime, base64.b64encode(data).decode('ascii'))
            how = 'embedded'
        else:
            src = esc(name)
            how = 'linked: larger than %.0f MB' % (self.max_embed / 1e6)
        extra = ' muted playsinline preload="metadata"' if tag == 'video' else ' preload="metadata"'
        return ('<figure><%s controls%s src="%s"></%s><figcaption>%s (%.2f MB, %s)</figcaption></figure>'
                % (tag, extra, src, tag, self.link(name), size / 1e6, how))

    # ---- page -----------------------------------------------------------------------------
    def page(self):
        run = self.run
        counts = run.counts()
        title = 'sensorTest report: %s, %s mode' % (run.platform, run.mode)
        parts = ['<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">',
                 '<meta name="viewport" content="width=device-width, initial-scale=1">',
                 '<title>%s%s</title>' % (esc(title), (' ' + esc(run.run_id)) if run.run_id else ''),
                 '<style>%s</style></head><body>' % CSS]
        parts.append(self.header(title, counts))
        parts.append(self.summary_table())
        parts.append(self.rates_section())
        for r in run.sensors:
            try:
                parts.append(self.sensor_section(r))
            except Exception as e:   # one odd sensor must not lose the whole report
                self.problems.append('%s: %s: %s' % (r.name, type(e).__name__, e))
                parts.append('<section class="sensor %s-box" id="%s"><h2>%s <span class="badge %s">%s</span></h2>'
                             '<p class="warn-text">this section could not be drawn: %s</p></section>'
                             % (r.verdict, anchor(r.name), esc(r.name), r.verdict, r.verdict, esc(e)))
        parts.append(self.footer())
        parts.append('</body></html>\n')
        return '\n'.join(parts)

    def header(self, title, counts):
        run = self.run
        start = timestamp(run.start).replace('.', ' ')
        end = timestamp(run.end).replace('.', ' ') if run.end else '-'
        duration = '%.1f s' % (run.end - run.start) if run.end else '-'
        source = 'live topics' if run.source == 'live' else 'bag ' + run.source
        out = ['<header><h1>%s</h1>' % esc(title),
               '<div class="meta">run <b>%s</b> &middot; %s &middot; %s to %s (%s) &middot; exit code %d</div>'
               % (esc(run.run_id or '-'), esc(source), esc(start), esc(end), duration, run.exit_code),
               '<div class="meta">%d sensors: <span class="badge PASS">%d passed</span> '
               '<span class="badge FAIL">%d failed</span> <span class="badge SKIPPED">%d skipped</span></div>'
               % (len(run.sensors), counts[PASS], counts[FAIL], counts[SKIPPED])]
        if run.interrupted:
            out.append('<div class="banner warn">Interrupted: %s. Sensors that had not finished are '
                       'judged on what arrived until then.</div>' % esc(run.interrupt_reason or 'run interrupted'))
        if counts[FAIL]:
            failed = ', '.join('<a href="#%s">%s</a>' % (anchor(s.name), esc(s.name))
                               for s in run.sensors if s.verdict == FAIL)
            out.append('<div class="banner bad">%d sensor%s failed: %s</div>'
                       % (counts[FAIL], '' if counts[FAIL] == 1 else 's', failed))
        elif run.sensors and not run.interrupted:
            out.append('<div class="banner good">Every tested sensor passed.</div>')
        out.append('</header>')
        return '\n'.join(out)

    def recordings(self, r):
        links = []
        for kind, name in r.artifacts.items():
            if kind in ('video', 'audio', 'wav') or kind.startswith('audio_'):
                links.append(self.link(name))
        return ' '.join(links) or '-'

    def summary_table(self):
        rows = ['<h2>Summary</h2><table class="summary"><tr><th>sensor</th><th>topic</th><th>verdict</th>'
                '<th>messages</th><th>rate Hz</th><th>expected Hz</th><th>recording</th><th>reasons</th></tr>']
        for r in self.run.sensors:
            band = r.expected_rate_hz
            out = band and r.rate_hz is not None and not (band[0] <= r.rate_hz <= band[1])
            reasons = esc('; '.join(r.reasons))
            if r.warnings:
                reasons += ('<br>' if reasons else '') + '<span class="warn-text">%s</span>' % esc('; '.join(r.warnings))
            rows.append('<tr><td><a href="#%s">%s</a></td><td><code>%s</code></td>'
                        '<td><span class="badge %s">%s</span></td><td class="num">%s</td>'
                        '<td class="num%s">%s</td><td class="num">%s</td><td>%s</td><td class="reasons">%s</td></tr>'
                        % (anchor(r.name), esc(r.name), esc(r.topic or '-'), r.verdict, r.verdict,
                           r.messages if r.verdict != SKIPPED else '-', ' out' if out else '',
                           num(r.rate_hz), band_text(band), self.recordings(r), reasons))
        rows.append('</table>')
        return '\n'.join(rows)

    # ---- rates over the run -----------------------------------------------------------------
    @staticmethod
    def rate_steps(r):
        """The sensor's 1 s rate bins as stairs on the run's time axis: (edges, rates).
        The last bin usually covers only part of a second; its rate is scaled to that part
        (a bin shorter than 0.25 s is dropped rather than shown as a false drop)."""
        pts = [(float(t), float(v)) for t, v in r.series['rate_hz'] if v is not None]
        start = r.started_at or 0.0
        end = r.window_s if r.window_s else (pts[-1][0] + 0.5 if pts else 0.0)
        edges, rates = [], []
        for t, v in pts:
            lo, hi = t - 0.5, min(t + 0.5, end)
            if hi - lo < 0.25:
                break
            if not edges:
                edges.append(start + lo)
            edges.append(start + hi)
            rates.append(v / (hi - lo))
        return edges, rates

    def rates_section(self):
        rows = []
        for r in self.run.sensors:
            sensor = catalog.SENSORS.get(r.name)
            if r.verdict == SKIPPED or not (r.series or {}).get('rate_hz') or (sensor and sensor.family == 'speech'):
                continue
            rows.append(r)
        if not rows:
            return '<h2>Rates</h2><p>No sensor delivered a message stream.</p>'
        n = len(rows)
        fig = _figure(12, 0.75 * n + 0.9)
        axes = fig.subplots(n, 1, sharex=True, squeeze=False)[:, 0]
        for ax, r in zip(axes, rows):
            edges, rates = self.rate_steps(r)
            start = r.started_at or 0.0
            end = r.ended_at if r.ended_at is not None else (edges[-1] if edges else start)
            colour = COLOURS[FAIL] if r.verdict == FAIL else '#0969da'
            top = max(rates + [1.0])
            if r.expected_rate_hz:
                lo, hi = r.expected_rate_hz
                ax.fill_between([start, end], [lo, lo], [hi, hi], color='#2da44e', alpha=0.18, lw=0)
                top = max(top, hi)
            if r.nominal_rate_hz:
                ax.hlines(r.nominal_rate_hz, start, end, colors='#2da44e', linestyles='dashed', lw=0.8)
            if rates:
                ax.stairs(rates, edges, color=colour, lw=1.5, baseline=None)
            if not rates or max(rates) == 0:
                ax.text(0.5, 0.5, 'no messages', transform=ax.transAxes, ha='center', va='center',
                        color=COLOURS[FAIL], fontsize=8)
            ax.set_ylim(0, top * 1.15)
            ax.set_ylabel(r.name, rotation=0, ha='right', va='center', fontsize=8)
            ax.tick_params(labelsize=7)
            ax.grid(True, alpha=0.3)
        axes[-1].set_xlabel('seconds since the start of the run')
        fig.suptitle('messages per second (1 s bins); green band: expected rate, dashed: nominal', fontsize=9)
        return '<h2>Rates</h2>' + png(fig, 'rate of every sensor over the run')

    # ---- one sensor -------------------------------------------------------------------------
    def sensor_section(self, r):
        sensor = catalog.SENSORS.get(r.name)
        family = sensor.family if sensor else None
        out = ['<section class="sensor %s-box" id="%s">' % (r.verdict, anchor(r.name)),
               '<h2>%s <span class="badge %s">%s</span></h2>' % (esc(r.title or r.name), r.verdict, r.verdict),
               '<div class="meta"><code>%s</code> &middot; %s</div>' % (esc(r.topic or '-'), esc(r.msg_type))]
        if r.reasons:
            out.append('<ul class="reasons">%s</ul>' % ''.join('<li>%s</li>' % esc(x) for x in r.reasons))
        if r.warnings:
            out.append('<ul class="warnings">%s</ul>' % ''.join('<li>%s</li>' % esc(x) for x in r.warnings))
        if r.verdict == SKIPPED:
            out.append('</section>')
            return '\n'.join(out)
        out.append('<p>%s</p>' % esc(summary_line(r)))
        body = ''
        renderer = getattr(self, 'family_' + (family or ''), None)
        if renderer is not None:
            body = renderer(r)
        out.append(body)
        out.append(self.stats_block(r))
        if r.notes:
            notes = '<ul class="notes">%s</ul>' % ''.join('<li>%s</li>' % esc(x) for x in r.notes)
            out.append(notes if len(r.notes) <= 6 else
                       '<details><summary>notes (%d)</summary>%s</details>' % (len(r.notes), notes))
        values = []
        for k, v in r.values.items():
            if k == 'joints':
                continue
            _flatten(k, v, values)
        if values:
            out.append('<details><summary>all measured values (%d)</summary>%s</details>'
                       % (len(values), _kv_table([(k, esc(v)) for k, v in values])))
        if r.fields:
            out.append('<details><summary>first message</summary>%s</details>'
                       % _kv_table([(k, esc(v)) for k, v in r.fields]))
        out.append('</section>')
        return '\n'.join(out)

    def stats_block(self, r):
        s = r.stats or {}
        delay = s.get('delay_s') or {}
        band = r.expected_rate_hz
        rate_cls = ''
        if band and r.rate_hz is not None and not (band[0] <= r.rate_hz <= band[1]):
            rate_cls = ' class="fail-text"'
        rows = [('messages', str(r.messages)),
                ('rate (receive times)', '<span%s>%s</span>' % (rate_cls, num(r.rate_hz, 2, 'Hz'))),
                ('rate (header stamps)', num(r.stamp_rate_hz, 2, 'Hz')),
                ('expected / nominal', '%s Hz / %s' % (band_text(band), num(r.nominal_rate_hz, 2, 'Hz'))),
                ('window', '%s, %s' % (num(r.window_s, 1, 's'), esc(r.stopped_because or '-'))),
                ('started at', num(r.started_at, 1, 's into the run'))]
        if s:
            rows += [('first message after', num(s.get('first_message_after_s'), 3, 's')),
                     ('jitter (std of intervals)', num(s.get('jitter_s'), 4, 's')),
                     ('longest interval', num(s.get('max_interval_s'), 3, 's')),
                     ('delay now - stamp', '%s mean, %s max' % (num(delay.get('mean'), 4, 's'),
                                                                 num(delay.get('max'), 4, 's')) if delay else '-'),
                     ('zero / backwards / repeated stamps', '%s / %s / %s' % (
                         s.get('zero_stamps', '-'), s.get('backwards_stamps', '-'), s.get('repeated_stamps', '-')))]
        if r.received_type and r.received_type != r.msg_type:
            rows.append(('received type', '<span class="fail-text">%s</span>' % esc(r.received_type)))
        return '<details><summary>stream statistics</summary>%s</details>' % _kv_table(rows)

    # ---- families ---------------------------------------------------------------------------
    def family_range(self, r):
        xs, ys = _series_xy((r.series or {}).get('range_m'))
        if not xs:
            return ''
        limits = {k: v for k, v in (r.fields or [])}
        fig = _figure(7, 2.2)
        ax = fig.subplots()
        ax.plot(xs, ys, '.-', color='#0969da', ms=3, lw=1)
        for key, label in (('Minimum range value', 'min_range'), ('Maximum range value', 'max_range')):
            try:
                y = float(limits[key])
                ax.axhline(y, color='#9a6700', ls='--', lw=0.8)
                ax.text(xs[0], y, ' ' + label, va='bottom', fontsize=7, color='#9a6700')
            except (KeyError, ValueError):
                pass
        inf = [x for x, y in zip(xs, ys) if y != y]
        if inf:
            ax.plot(inf, [0] * len(inf), 'x', color=COLOURS[FAIL], label='no finite range (inf/NaN)')
            ax.legend(fontsize=7, loc='upper right')
        ax.set_xlabel('s since listening began')
        ax.set_ylabel('range (m)')
        ax.grid(True, alpha=0.3)
        return '<h3>Range over time</h3>' + png(fig, 'range over time of ' + r.name)

    def family_laser(self, r):
        scan = (r.series or {}).get('last_scan')
        if not scan:
            return ''
        import numpy as np
        a0, inc = float(scan['angle_min']), float(scan['angle_increment'])
        ranges = [float('nan') if v is None else float(v) for v in scan['ranges']]
        lo, hi = float(scan['range_min']), float(scan['range_max'])
        blind = scan.get('blind_value')
        angles = a0 + inc * np.arange(len(ranges))
        rng = np.array(ranges, dtype=float)
        is_blind = np.array([blind is not None and v == blind for v in ranges], dtype=bool)
        valid = np.isfinite(rng) & (rng >= lo) & (rng <= hi) & ~is_blind
        invalid = ~valid & ~is_blind
        fig = _figure(7.5, 3.6)
        ax = fig.add_subplot(projection='polar')
        ax.set_theta_zero_location('N')      # forward (x) up, left (+y) to the left, as in ROS
        ax.set_theta_direction(1)
        span = [math.degrees(angles.min()), math.degrees(angles.max())] if len(angles) else [-180, 180]
        if span[1] - span[0] < 359:
            ax.set_thetamin(span[0])
            ax.set_thetamax(span[1])
        ax.plot(angles[valid], rng[valid], '.', color='#0969da', ms=5, label='valid (%d)' % valid.sum())
        if is_blind.any():
            ax.plot(angles[is_blind], np.full(is_blind.sum(), hi), 'x', color='#8c959f', ms=5,
                    label='blind beams = %s (%d)' % (blind, is_blind.sum()))
        if invalid.any():
            ax.plot(angles[invalid], np.full(invalid.sum(), hi), 'x', color=COLOURS[FAIL], ms=6,
                    label='invalid: NaN, inf or outside [%g, %g] m (%d)' % (lo, hi, invalid.sum()))
        ax.set_rmax(hi * 1.05)
        ax.set_rmin(0)
        ax.plot([0], [0], marker='^', color='k', ms=6)
        ax.legend(fontsize=7, loc='center left', bbox_to_anchor=(1.08, 0.5))
        ax.set_title('last scan (m); forward is up', fontsize=9)
        return '<h3>Last scan</h3>' + png(fig, 'polar plot of the last laser scan')

    def _frames(self, r, caption_extra=''):
        cells = []
        for kind, caption in (('first_frame', 'first frame'), ('last_frame', 'last frame')):
            name = r.artifacts.get(kind)
            if name:
                cells.append(self.frame(name, caption + caption_extra))
        return cells

    def _video(self, r):
        name = r.artifacts.get('video')
        if not name:
            return '' if r.values.get('video') is None else '<p>no video file was written</p>'
        codec = (r.values.get('video') or {}).get('codec') if isinstance(r.values.get('video'), dict) else None
        return self.media('video', name, 'video/mp4', codec)

    def _frames_and_video(self, r, cells):
        """The 'Frames and video' row: `cells` (frame thumbnails, ...) plus the video player."""
        video = self._video(r)
        if video:
            cells.append(video)
        return ['<h3>Frames and video</h3><div class="row">%s</div>' % ''.join(cells)] if cells else []

    def family_camera(self, r):
        v = r.values
        cells = self._frames(r)
        out = self._frames_and_video(r, cells)
        if not cells and r.messages:
            out.append('<p>no frames or video recorded (recording off, or no frame could be converted)</p>')
        rows = []
        if 'width' in v:
            rows.append(('image', '%sx%s %s' % (v.get('width'), v.get('height'), esc(v.get('encoding')))))
        for key, label in (('brightness_mean', 'brightness (mean of a frame, 0-255)'),
                           ('brightness_spread', 'spread (std of a frame)')):
            d = v.get(key)
            if isinstance(d, dict):
                rows.append((label, 'min %s, mean %s, max %s' % (num(d.get('min')), num(d.get('mean')),
                                                                   num(d.get('max')))))
        for key, label in (('frames_black', 'black frames'), ('frames_constant', 'constant frames'),
                           ('longest_identical_run', 'longest run of identical frames (frozen)')):
            if key in v:
                rows.append((label, esc(v[key])))
        video = v.get('video')
        if isinstance(video, dict):
            rows.append(('video', '%s frames, %s fps, codec %s' % (video.get('frames_written', '-'),
                                                                   num(video.get('fps')), esc(video.get('codec')))))
        if isinstance(v.get('stereo'), dict):
            st = v['stereo']
            rows.append(('stereo', 'two views of %sx%s, identical views in %s frames'
                         % (st.get('view_width'), st.get('view_height'), st.get('identical_views'))))
        if rows:
            out.append('<h3>Image statistics</h3>' + _kv_table(rows))
        xs, ys = _series_xy((r.series or {}).get('brightness'))
        if xs:
            fig = _figure(7, 1.8)
            ax = fig.subplots()
            ax.plot(xs, ys, '.-', ms=3, lw=1, color='#0969da')
            ax.set_ylim(0, 255)
            ax.set_ylabel('brightness')
            ax.set_xlabel('s since listening began')
            ax.grid(True, alpha=0.3)
            out.append(png(fig, 'brightness over time of ' + r.name))
        return '\n'.join(out)

    def family_depth(self, r):
        v = r.values
        lo_hi = v.get('video_range_m') or [0.0, 5.0]
        cells = self._frames(r, ' (colour-mapped)')
        if cells:
            cells.append(self.colour_scale(lo_hi))
        out = self._frames_and_video(r, cells)
        rows = []
        if 'width' in v:
            rows.append(('image', '%sx%s %s' % (v.get('width'), v.get('height'), esc(v.get('encoding')))))
        d = v.get('depth_m')
        if isinstance(d, dict):
            rows.append(('depth', 'min %s, median %s, max %s m' % (num(d.get('min'), 3), num(d.get('median'), 3),
                                                                     num(d.get('max'), 3))))
        d = v.get('valid_share')
        if isinstance(d, dict):
            rows.append(('valid pixels', 'min %s, mean %s, max %s' % (num(d.get('min'), 3), num(d.get('mean'), 3),
                                                                        num(d.get('max'), 3))))
        if 'frames_all_zero' in v:
            rows.append(('frames without a valid pixel', esc(v['frames_all_zero'])))
        if rows:
            out.append('<h3>Depth statistics</h3>' + _kv_table(rows))
        hist = self.depth_histogram(v.get('depth_histogram'))
        if hist:
            out.append('<h3>Depth histogram</h3>' + hist)
        series = r.series or {}
        xm, ym = _series_xy(series.get('median_depth_m'))
        xv, yv = _series_xy(series.get('valid_share'))
        if xm or xv:
            fig = _figure(7, 2.6)
            a1, a2 = fig.subplots(2, 1, sharex=True)
            a1.plot(xm, ym, '.-', ms=3, lw=1, color='#0969da')
            a1.set_ylabel('median (m)')
            a2.plot(xv, [100 * y for y in yv], '.-', ms=3, lw=1, color='#8250df')
            a2.set_ylabel('valid %')
            a2.set_ylim(0, 105)
            a2.set_xlabel('s since listening began')
            for a in (a1, a2):
                a.grid(True, alpha=0.3)
            out.append('<h3>Over time</h3>' + png(fig, 'median depth and valid pixels over time'))
        return '\n'.join(out)

    def colour_scale(self, lo_hi):
        import matplotlib
        fig = _figure(1.3, 2.6)
        ax = fig.subplots()
        norm = matplotlib.colors.Normalize(vmin=float(lo_hi[0]), vmax=float(lo_hi[1]))
        fig.colorbar(matplotlib.cm.ScalarMappable(norm=norm, cmap='jet'), cax=ax, label='depth (m)')
        return '<figure>%s<figcaption>black: no depth</figcaption></figure>' % png(fig, 'depth colour scale')

    def depth_histogram(self, hist):
        """Accepts {'edges': [...], 'counts': [...]} (edges in m, len(counts)+1 edges, or bin
        centres with 'bins'/'centres'), or a list of [low, high, count] / (centre, count) rows."""
        if not hist:
            return ''
        edges, counts = None, None
        if isinstance(hist, dict):
            counts = hist.get('counts') or hist.get('count')
            edges = hist.get('edges') or hist.get('edges_m') or hist.get('bins_m') or hist.get('bins') \
                or hist.get('centres') or hist.get('centers')
        elif isinstance(hist, (list, tuple)) and hist and isinstance(hist[0], (list, tuple)):
            if len(hist[0]) >= 3:
                edges = [float(h[0]) for h in hist] + [float(hist[-1][1])]
                counts = [float(h[2]) for h in hist]
            else:
                edges = [float(h[0]) for h in hist]
                counts = [float(h[1]) for h in hist]
        elif isinstance(hist, (list, tuple)):
            counts = list(hist)
        if not counts:
            return ''
        counts = [float(c) for c in counts]
        if edges is None or len(edges) not in (len(counts), len(counts) + 1):
            edges = list(range(len(counts) + 1))
            xlabel = 'bin'
        else:
            xlabel = 'depth (m)'
        edges = [float(e) for e in edges]
        fig = _figure(7, 2.0)
        ax = fig.subplots()
        if len(edges) == len(counts) + 1:
            ax.stairs(counts, edges, fill=True, color='#0969da', alpha=0.7)
        else:
            width = (edges[1] - edges[0]) if len(edges) > 1 else 1.0
            ax.bar(edges, counts, width=width * 0.9, color='#0969da', alpha=0.7)
        ax.set_xlabel(xlabel)
        ax.set_ylabel('pixels')
        ax.grid(True, alpha=0.3)
        return png(fig, 'depth histogram')

    def family_audio(self, r):
        v = r.values
        out = []
        channels = v.get('channels') or v.get('levels') or {}
        if isinstance(channels, dict) and channels:
            rows = ['<table><tr><th>channel</th><th>RMS dBFS</th><th>peak dBFS</th><th>clipping</th><th>silent</th></tr>']
            for name, lv in channels.items():
                lv = lv if isinstance(lv, dict) else {}
                clip = lv.get('clipping_share')
                rows.append('<tr><td>%s</td><td class="num">%s</td><td class="num">%s</td><td class="num">%s</td>'
                            '<td>%s</td></tr>' % (esc(name), num(lv.get('rms_dbfs'), 1), num(lv.get('peak_dbfs'), 1),
                                                  '-' if clip is None else '%.3f%%' % (100 * clip),
                                                  'all zero' if lv.get('all_zero') else ''))
            rows.append('</table>')
            out.append('<h3>Levels per channel</h3>' + ''.join(rows))
        if v.get('sample_rate_hz') is not None:
            out.append('<p>sample rate %s Hz measured (%s expected)</p>'
                       % (num(v.get('sample_rate_hz'), 0), esc(v.get('sample_rate_expected_hz', '-'))))
        speech = self.by_name.get('speech')
        if speech is not None and speech.verdict != SKIPPED:
            heard = speech.values.get('heard')
            text = {True: 'yes', False: 'no', None: 'not measured'}.get(heard, esc(heard))
            out.append('<p>Test sentence heard by the microphones: <b>%s</b>%s (see <a href="#%s">speech</a>)</p>'
                       % (text, ', level rose %s dB' % num(speech.values.get('level_rise_db'), 1)
                          if speech.values.get('level_rise_db') is not None else '', anchor('speech')))
        series = r.series or {}
        level_series = [(k[len('level_dbfs_'):], series[k]) for k in series if k.startswith('level_dbfs_') and series[k]]
        if level_series:
            fig = _figure(7, 2.2)
            ax = fig.subplots()
            for i, (name, pts) in enumerate(level_series):
                xs, ys = _series_xy(pts)
                ax.plot(xs, ys, lw=1, color=CHANNEL_COLOURS[i % 4], label=name)
            ax.set_ylabel('RMS per buffer (dBFS)')
            ax.set_xlabel('s since listening began')
            ax.legend(fontsize=7, ncol=4, loc='lower left', bbox_to_anchor=(0.0, 1.0), frameon=False)
            ax.grid(True, alpha=0.3)
            out.append('<h3>Level over time</h3>' + png(fig, 'microphone levels over time'))
        wav = r.artifacts.get('audio') or r.artifacts.get('wav')
        if wav:
            wave = self.waveform(wav)
            if wave:
                out.append('<h3>Waveform</h3>' + wave)
            players = [self.media('audio', wav, 'audio/wav')]
            for kind, name in r.artifacts.items():
                if kind.startswith('audio_'):
                    players.append(self.media('audio', name, 'audio/wav'))
            out.append('<h3>Recording</h3><div class="row">%s</div>' % ''.join(players))
        elif r.messages:
            out.append('<p>no WAV file recorded</p>')
        return '\n'.join(out)

    def waveform(self, name, max_seconds=300.0, bins=900):
        """Min/max envelope of every channel of a WAV file, one row per channel."""
        try:
            import numpy as np
            import soundfile
            with soundfile.SoundFile(self.path(name)) as f:
                rate, nch = f.samplerate, f.channels
                data = f.read(frames=int(max_seconds * rate), dtype='int16', always_2d=True)
        except Exception as e:
            self.problems.append('waveform of %s: %s' % (name, e))
            return ''
        if not len(data):
            return ''
        from .sensors.audio import CHANNELS
        names = list(CHANNELS) if nch == 4 else ['channel %d' % (i + 1) for i in range(nch)]
        n = len(data)
        k = max(1, n // bins)
        m = (n // k) * k
        t = np.arange(m // k) * k / float(rate)
        fig = _figure(7, 0.9 * nch + 0.6)
        axes = fig.subplots(nch, 1, sharex=True, squeeze=False)[:, 0]
        for i, ax in enumerate(axes):
            block = data[:m, i].reshape(-1, k) / 32768.0
            ax.fill_between(t, block.min(axis=1), block.max(axis=1), color=CHANNEL_COLOURS[i % 4], lw=0.3)
            peak = float(np.abs(block).max()) if block.size else 0.0
            ax.set_ylim(-max(peak, 1e-4) * 1.1, max(peak, 1e-4) * 1.1)   # each channel at its own scale
            ax.text(0.995, 0.94, 'peak %s dBFS' % (num(20 * math.log10(peak), 1) if peak > 0 else '-inf'),
                    transform=ax.transAxes, ha='right', va='top', fontsize=7, color='#1f2328',
                    bbox={'facecolor': 'white', 'alpha': 0.8, 'edgecolor': 'none', 'pad': 1})
            ax.set_ylabel(names[i], rotation=0, ha='right', va='center', fontsize=8)
            ax.tick_params(labelsize=7)
            ax.grid(True, alpha=0.3)
        axes[-1].set_xlabel('s (%s, %d Hz, %d channel%s)' % (name, rate, nch, '' if nch == 1 else 's'))
        return png(fig, 'waveform of ' + name)

    def family_joints(self, r):
        joints = r.values.get('joints')
        if not isinstance(joints, dict) or not joints:
            return ''

        def rng(d):
            if not isinstance(d, dict) or d.get('min') is None:
                return '<td class="num">-</td>'
            return '<td class="num">%s / %s / %s</td>' % (num(d.get('min'), 3), num(d.get('mean'), 3),
                                                          num(d.get('max'), 3))
        rows = ['<h3>Joints (%d)</h3><table><tr><th>joint</th><th>position rad (min / mean / max)</th>'
                '<th>velocity rad/s</th><th>effort</th></tr>' % len(joints)]
        for name, d in joints.items():
            d = d if isinstance(d, dict) else {}
            rows.append('<tr><td>%s</td>%s%s%s</tr>' % (esc(name), rng(d.get('position')), rng(d.get('velocity')),
                                                        rng(d.get('effort'))))
        rows.append('</table>')
        return ''.join(rows)

    def family_odometry(self, r):
        series = r.series or {}
        xs, x = _series_xy(series.get('x_m'))
        _, y = _series_xy(series.get('y_m'))
        if not xs:
            return ''
        fig = _figure(8, 2.4)
        a1, a2 = fig.subplots(1, 2, gridspec_kw={'width_ratios': [2.2, 1]})
        a1.plot(xs, x, lw=1.2, label='x')
        if len(y) == len(xs):
            a1.plot(xs, y, lw=1.2, label='y')
            a2.plot(x, y, '.-', ms=2, lw=1, color='#8250df')
            a2.plot(x[:1], y[:1], 'o', color=COLOURS[PASS], ms=4)
            a2.set_xlabel('x (m)')
            a2.set_ylabel('y (m)')
            a2.set_aspect('equal', adjustable='datalim')
            a2.set_title('path', fontsize=8)
            a2.grid(True, alpha=0.3)
        a1.set_xlabel('s since listening began')
        a1.set_ylabel('position (m)')
        a1.legend(fontsize=7)
        a1.grid(True, alpha=0.3)
        return '<h3>Position over time</h3>' + png(fig, 'odometry position over time')

    def family_imu(self, r):
        series = r.series or {}
        xa, ya = _series_xy(series.get('acceleration_m_s2'))
        xg, yg = _series_xy(series.get('angular_velocity_rad_s'))
        if not xa and not xg:
            return ''
        fig = _figure(7, 2.6)
        a1, a2 = fig.subplots(2, 1, sharex=True)
        a1.plot(xa, ya, lw=1.2, color='#0969da')
        a1.set_ylabel('|a| (m/s²)')
        a2.plot(xg, yg, lw=1.2, color='#bf3989')
        a2.set_ylabel('|ω| (rad/s)')
        a2.set_xlabel('s since listening began')
        for a in (a1, a2):
            a.grid(True, alpha=0.3)
        return '<h3>Over time</h3>' + png(fig, 'IMU acceleration and angular velocity over time')

    def family_speech(self, r):
        v = r.values
        heard = v.get('heard')
        rows = [('sentence', esc(v.get('text', '-'))),
                ('delivered to', esc(', '.join(v.get('subscribers') or []) or '-')),
                ('heard by the microphones', {True: '<b>yes</b>', False: '<b class="fail-text">no</b>',
                                              None: 'not measured (microphones not in this run)'}.get(heard, esc(heard)))]
        if v.get('level_rise_db') is not None:
            rows.append(('level rise while speaking', num(v.get('level_rise_db'), 1, 'dB')))
        return '<h3>Speech</h3>' + _kv_table(rows)

    def footer(self):
        run = self.run
        names = [n for n in ('sensorTestResults.json', 'sensorTestResults.xml', 'sensorTestOutput.dat')
                 if os.path.exists(self.path(n))]
        out = ['<footer>']
        if names:
            out.append('<p>Files of this run: %s</p>' % ', '.join(self.link(n) for n in names))
        if run.files:
            out.append('<p>Inputs: %s</p>' % ', '.join('%s <code>%s</code>' % (esc(k), esc(v))
                                                       for k, v in run.files.items()))
        if run.options:
            out.append('<p>Options: %s</p>' % esc(', '.join('%s=%s' % kv for kv in sorted(run.options.items()))))
        if self.problems:
            out.append('<p class="warn-text">Not shown: %s</p>' % esc('; '.join(self.problems)))
        out.append('<p>Written by pepper_interface_tests sensorTest at %s.</p></footer>'
                   % esc(timestamp().replace('.', ' ')))
        return '\n'.join(out)


def render(run, folder=None, max_embed=MAX_EMBED_BYTES):
    """The report of `run` as one HTML string; recordings are read from `folder`."""
    return _Renderer(run, folder or run.output_dir or '.', max_embed).page()
