"""sensorTestBenchmark: what sensorTest costs next to `rostopic hz` on the same heavy streams.

It starts its own roscore on a free port and a publisher process (rospy) with the streams of
issue 12 (about 1 GB in 10 s):
  frontCamera, bottomCamera  640x480 rgb8 at 30 Hz
  depthCamera                320x240 16UC1 at 20 Hz
  realsenseRGBCamera         640x480 rgb8 at 30 Hz
  realsenseDepthCamera       640x480 16UC1 at 30 Hz
  microphone                 AudioCustomMsg 4 x 4096 samples at 48 kHz (11.7 buffers/s)
Each round runs, side by side on those topics, `rostopic hz` (the floor for a rospy listener:
AnyMsg, no deserialisation) and `sensorTest --platform robot --mode parallel --duration D` (default 15)
with a temporary topics, input and expectations file and output folder. The publisher waits
until both have subscribed to every topic, publishes for `--publish` seconds (default 10)
and stops, so the number published is exact and falls inside the listening window (the
temporary expectations accept the quiet tail); `rostopic hz` is stopped (SIGINT) once the
publisher is done, sensorTest ends on its own.

A round is `off` (sensorTest --no-record: every check, no recording) or `on` (checks and
recording); by default both, `--runs` times. Printed per round: published, received
(sensorTest's count) and recorded (frames decoded from the mp4 by ffprobe; buffers' worth of
samples in the WAV) per stream; the CPU seconds (user + system, from wait4: the process and
its reaped children, so sensorTest's ffmpeg encoders and any encoding after the window count)
of sensorTest and of `rostopic hz` and their ratio; the time from the end of the window to
the last recording written (mtime); the peak memory of sensorTest and its ffmpeg children
together (psutil, sampled every 0.1 s) as PSS (each shared page divided among the processes
that map it) and as RSS (the sum counts the libraries every ffmpeg maps once per process),
and sensorTest's own RSS. Then one summary line per round with the targets of issue 12: ratio
<= 1.5 with recording off, <= 5 with recording on, last file <= 2 s after the window, peak
memory (PSS of the whole tree) <= 300 MB, every message received (>= --target) and recorded.
Exit code 0 when every round met every target, 1 otherwise, 2 when a round could not run.
`--profile DIR` runs sensorTest under py-spy (if installed) and prints the top entries
(CPU ratios of such a round include the profiler and are not comparable).
"""
import argparse
import glob
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from typing import Any, Dict, List, Optional, Sequence

import numpy as np

from .outputs.terminal import HelpFormatter
from .plan.settings import package_dir
from .results import JSON_FILE
from .rosmaster import MasterError, PrivateMaster, stop_group

STREAMS = [
    # sensor, topic, kind, width, height, rate
    ('frontCamera', '/bench/front/image_raw', 'rgb8', 640, 480, 30.0),
    ('bottomCamera', '/bench/bottom/image_raw', 'rgb8', 640, 480, 30.0),
    ('depthCamera', '/bench/depth/image_raw', '16UC1', 320, 240, 20.0),
    ('realsenseRGBCamera', '/bench/color/image_raw', 'rgb8', 640, 480, 30.0),
    ('realsenseDepthCamera', '/bench/aligned_depth_to_color/image_raw', '16UC1', 640, 480, 30.0),
    ('microphone', '/bench/audio', 'audio', 4096, 4, 48000.0 / 4096),
]
RING = 24   # distinct frames per stream, cycled (no two consecutive frames identical)


# ---------------------------------------------------------------- publisher process

def _frames(encoding, w, h):
    rng = np.random.default_rng(7)
    yy, xx = np.mgrid[0:h, 0:w]
    out = []
    for i in range(RING):
        if encoding == 'rgb8':
            noise = rng.integers(0, 24, (h, w, 3), dtype=np.uint8)
            px = np.dstack([(xx + 6 * i) % 256, (yy + 3 * i) % 256, ((xx + yy) // 2 + 5 * i) % 256]).astype(np.uint8)
            out.append((px + noise).tobytes())
        else:
            mm = (800 + (xx * 3000) // w + 40 * i + rng.integers(0, 30, (h, w))).astype(np.uint16)
            mm[: h // 12] = 0
            out.append(mm.tobytes())
    return out


def publish(seconds: float, wait: float, subscribers: int = 1) -> int:
    """Publisher process: wait for `subscribers` subscriptions per topic, publish for `seconds`,
    report counts."""
    import rospy
    from sensor_msgs.msg import Image

    from pepper_interface_tests.msg import AudioCustomMsg
    rospy.init_node('sensor_test_benchmark_publisher', disable_signals=True)
    pubs, payloads = {}, {}
    for name, topic, enc, w, h, _rate in STREAMS:
        cls = AudioCustomMsg if enc == 'audio' else Image
        pubs[name] = rospy.Publisher(topic, cls, queue_size=60)
        if enc == 'audio':
            t = np.arange(w * RING) / 48000.0
            chans = [(3000 * np.sin(2 * np.pi * f * t)).astype(np.int16) for f in (500, 1000, 1500, 2500)]
            payloads[name] = [[c[i * w:(i + 1) * w].tolist() for c in chans] for i in range(RING)]
        else:
            payloads[name] = _frames(enc, w, h)
    deadline = time.monotonic() + wait
    while any(p.get_num_connections() < subscribers for p in pubs.values()):
        if time.monotonic() > deadline:
            missing = [n for n, p in pubs.items() if p.get_num_connections() < subscribers]
            print(json.dumps({'error': 'no subscriber on: ' + ', '.join(missing)}), flush=True)
            return 1
        time.sleep(0.05)
    time.sleep(0.3)
    counts = {name: 0 for name in pubs}
    start = time.monotonic() + 0.05
    end = start + seconds

    def run(name, enc, w, h, rate):
        pub, ring = pubs[name], payloads[name]
        period = 1.0 / rate
        k = 0
        while True:
            due = start + k * period
            if due >= end:
                break
            delay = due - time.monotonic()
            if delay > 0:
                time.sleep(delay)
            if enc == 'audio':
                msg = AudioCustomMsg(*ring[k % RING])
            else:
                msg = Image(width=w, height=h, encoding=enc, is_bigendian=0,
                            step=w * (3 if enc == 'rgb8' else 2), data=ring[k % RING])
                msg.header.stamp = rospy.Time.now()
                msg.header.frame_id = name
            pub.publish(msg)
            counts[name] += 1
            k += 1

    threads = [threading.Thread(target=run, args=(n, e, w, h, r)) for n, _, e, w, h, r in STREAMS]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    late = time.monotonic() - end
    print(json.dumps({'published': counts, 'seconds': seconds, 'finished_late_s': round(late, 3)}), flush=True)
    # stay up (and connected) until told to stop, so nothing is cut off in flight
    stop = threading.Event()
    signal.signal(signal.SIGTERM, lambda *_: stop.set())
    signal.signal(signal.SIGINT, lambda *_: stop.set())
    stop.wait(120)
    return 0


# ---------------------------------------------------------------- driver

TARGETS = {'off': 1.5, 'on': 5.0}     # issue 12: CPU of sensorTest / CPU of rostopic hz
TARGET_LAST_FILE_S = 2.0
TARGET_RSS_MB = 300.0


def _expectations(duration):
    lines = ['# written by sensorTestBenchmark: the benchmark streams\' rates; the publisher stops',
             '# before the window ends, so a quiet tail of up to 5 s is accepted (max_gap_factor).',
             'defaults:', '  min_messages: 3', '  max_delay: 5.0', '  max_future: 1.0', 'robot:']
    for name, _, enc, w, h, rate in STREAMS:
        lines.append('  %s:' % name)
        lines.append('    rate: [%.2f, %.2f]' % (rate * 0.8, rate * 1.25))
        lines.append('    nominal: %.2f' % rate)
        lines.append('    max_gap_factor: %.1f' % (5.0 * rate * 0.8))
        if enc == 'audio':
            lines += ['    sample_rate: 48000', '    sample_rate_tolerance: 0.05', '    silence_dbfs: -70.0']
        else:
            lines.append('    encoding: %s' % enc)
            lines.append('    width: %d' % w)
            lines.append('    height: %d' % h)
            if enc == '16UC1':
                lines.append('    video_range: [0.0, 5.0]')
    return '\n'.join(lines) + '\n'


def _sample_rss(pid, peak, stop, threads=None):
    """Peaks over the run, sampled every 0.1 s (psutil): peak['rss'] sensorTest alone,
    peak['rss_children'] its children (the ffmpeg encoders), peak['rss_tree'] both at the same
    moment, peak['pss_tree'] the proportional set size of the whole tree (each shared page
    divided among the processes that map it: the shared libraries of five ffmpeg processes
    count once, not five times), peak['uss_tree'] its private memory. Linux's smaps_rollup
    makes a PSS sample cheap (about 0.1 ms a process)."""
    try:
        import psutil
    except ImportError:
        return
    proc = psutil.Process(pid)
    while not stop.is_set():
        try:
            tree = [proc] + proc.children(recursive=True)
            own = proc.memory_full_info()
        except psutil.Error:
            return
        rss_kids = pss = uss = 0
        for p in tree[1:]:
            try:
                info = p.memory_full_info()
            except psutil.Error:
                continue
            rss_kids += info.rss
            pss += info.pss
            uss += info.uss
        for key, value in (('rss', own.rss), ('rss_children', rss_kids), ('rss_tree', own.rss + rss_kids),
                           ('pss_tree', own.pss + pss), ('uss_tree', own.uss + uss)):
            peak[key] = max(peak.get(key, 0), value)
        if threads is not None:
            try:
                for th in proc.threads():
                    threads[th.id] = th.user_time + th.system_time
            except psutil.Error:
                pass
        stop.wait(0.1)


def _wait4(pid, timeout):
    """(exit code, rusage) of a child, waiting at most `timeout` s (None, None when it did not end)."""
    deadline = time.monotonic() + timeout
    while True:
        done, status, usage = os.wait4(pid, os.WNOHANG)
        if done:
            return os.waitstatus_to_exitcode(status), usage
        if time.monotonic() > deadline:
            return None, None
        time.sleep(0.02)


def _recorded(out_dir, sensor):
    from .media.recording import ffprobe_frames
    from .plan import catalog
    if sensor == 'microphone':
        path = os.path.join(out_dir, 'microphoneOutput.wav')
        if not os.path.exists(path):
            return None, None
        import soundfile
        info = soundfile.info(path)
        return info.frames, '%d ch %d Hz %s' % (info.channels, info.samplerate, info.subtype)
    video = catalog.SENSORS[sensor].video
    if video is None:       # a sensor that records no video
        return None, None
    path = os.path.join(out_dir, video)
    if not os.path.exists(path):
        return None, None
    return ffprobe_frames(path), None


def _wait_subscribed(uri, prefix, topics, timeout):
    """Wait until a node whose name starts with `prefix` subscribes to every topic (on a
    loaded machine `rostopic hz` may take seconds to start: sensorTest's window must not
    begin before the publisher can)."""
    import xmlrpc.client
    master: Any = xmlrpc.client.ServerProxy(uri)   # typeshed's return types hide the tuple
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        try:
            _, _, (_, subscribers, _) = master.getSystemState('/bench')
            subs = {t: nodes for t, nodes in subscribers}
            if all(any(n.startswith(prefix) for n in subs.get(t, ())) for t in topics):
                return True
        except OSError:
            pass
        time.sleep(0.1)
    return False


def _sensor_test_script():
    root = package_dir()
    return root, os.path.join(root, 'scripts', 'sensorTest')


def _round(args, tmp, master, files, mode, label):
    """One side-by-side round; a dict of measurements (or {'error': text})."""
    root, sensor_test = _sensor_test_script()
    topics, inputs, expect = files
    out_dir = os.path.join(tmp, 'out-' + label)
    env = master.env()
    # 10 s of streams as in issue 12; the window is longer so that a publisher that starts late
    # (on a loaded machine) still ends inside it
    publish_s = args.publish if args.publish else min(10.0, max(1.0, args.duration - 2.0))
    cmd = [sys.executable, sensor_test, '--topics', topics, '--input', inputs, '--expectations', expect,
           '--platform', 'robot', '--mode', 'parallel', '--duration', '%g' % args.duration,
           '--wait', '10', '--output-dir', out_dir, '--no-show', '--no-history', '--no-diagnostics',
           '--no-report'] + ([] if mode == 'on' else ['--no-record'])
    profile = None
    if args.profile:
        spy = shutil.which('py-spy')
        if spy:
            os.makedirs(args.profile, exist_ok=True)
            profile = os.path.join(os.path.abspath(args.profile), 'sensorTest-%s.txt' % label)
            cmd = [spy, 'record', '--format', 'raw', '--rate', '200', '--nonblocking', '-o', profile, '--'] + cmd
        else:
            print('py-spy not found: no profile')
    hz_cmd = [shutil.which('rostopic') or 'rostopic', 'hz'] + [s[1] for s in STREAMS]
    print('\n== round %s: recording %s ==' % (label, mode))
    print('sensorTest: ' + ' '.join(cmd[cmd.index(sensor_test) + 1:]).replace(root + '/', ''))
    print('alongside:  ' + ' '.join(['rostopic'] + hz_cmd[1:]))
    procs: List[subprocess.Popen] = []
    try:
        pub = subprocess.Popen([sys.executable, os.path.abspath(sys.argv[0]), '--publisher', '--subscribers', '2',
                                '--publish', '%g' % publish_s], env=env, stdout=subprocess.PIPE,
                               text=True, start_new_session=True)
        procs.append(pub)
        time.sleep(1.0)
        hz_log = open(os.path.join(tmp, 'rostopic-hz-%s.log' % label), 'w')
        hz = subprocess.Popen(hz_cmd, env=env, stdout=hz_log, stderr=subprocess.STDOUT, start_new_session=True)
        procs.append(hz)
        if not _wait_subscribed(master.uri, '/rostopic_', [s[1] for s in STREAMS], 60.0):
            return {'error': 'rostopic hz did not subscribe within 60 s; log: %s' % hz_log.name}
        log = open(os.path.join(tmp, 'sensorTest-%s.log' % label), 'w')
        t0 = time.monotonic()
        st = subprocess.Popen(cmd, env=env, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
        procs.append(st)
        peak: Dict[str, int] = {}
        stop = threading.Event()
        threads: Optional[Dict[int, float]] = {} if args.threads else None
        sampler = threading.Thread(target=_sample_rss, args=(st.pid, peak, stop, threads), daemon=True)
        sampler.start()
        line = pub.stdout.readline() if pub.stdout else ''   # the publisher reports once it has published everything
        published = json.loads(line) if line.strip() else {'error': 'publisher printed nothing'}
        time.sleep(0.5)                      # let the last messages arrive at rostopic hz
        if hz.poll() is None:
            os.killpg(hz.pid, signal.SIGINT)
        hz_code, hz_usage = _wait4(hz.pid, 20.0)
        hz.returncode = hz_code
        hz_log.close()
        code, usage = _wait4(st.pid, args.duration + 120.0)
        st.returncode = code
        wall = time.monotonic() - t0
        stop.set()
        log.close()
        if 'error' in published:
            return {'error': 'publisher: ' + published['error']}
        if usage is None or hz_usage is None:
            return {'error': 'sensorTest or rostopic hz did not end; logs in %s' % tmp}
        results_path = os.path.join(out_dir, JSON_FILE)
        if not os.path.exists(results_path):
            return {'error': 'sensorTest wrote no results (exit %s); log: %s' % (code, log.name)}
        with open(results_path) as f:
            run = json.load(f)
        results = {s['name']: s for s in run['sensors']}
        streams, ok_counts = _table(results, published, out_dir, args.target, mode == 'on')
        window_end = run['start_unix'] + max(s['ended_at'] for s in run['sensors'])
        media = [p for ext in ('mp4', 'wav') for p in glob.glob(os.path.join(out_dir, '*.' + ext))]
        last_file = (max(os.path.getmtime(p) for p in media) - window_end) if media else None
        cpu = usage.ru_utime + usage.ru_stime
        videos = [(r.get('values') or {}).get('video') or {} for r in results.values()]
        encoders = sum(v.get('encoder_cpu_s') or 0.0 for v in videos if isinstance(v, dict))
        writers = sum(v.get('writer_cpu_s') or 0.0 for v in videos if isinstance(v, dict))
        hz_cpu = hz_usage.ru_utime + hz_usage.ru_stime
        m = {'label': label, 'mode': mode, 'exit': code, 'wall': wall, 'cpu': cpu, 'user': usage.ru_utime,
             'system': usage.ru_stime, 'hz_cpu': hz_cpu, 'ratio': cpu / hz_cpu if hz_cpu else float('inf'),
             'rss': max(peak.get('rss', 0), usage.ru_maxrss * 1024) / 1e6,
             'rss_children': peak.get('rss_children', 0) / 1e6, 'rss_tree': peak.get('rss_tree', 0) / 1e6,
             'pss_tree': peak.get('pss_tree', 0) / 1e6, 'uss_tree': peak.get('uss_tree', 0) / 1e6,
             'last_file': last_file if mode == 'on' else None,
             'counts_ok': ok_counts, 'streams': streams, 'late': published['finished_late_s'],
             'profile': profile, 'encoders': encoders}
        print('\nsensorTest:  exit %s, wall %.1f s, CPU %.2f s (user %.2f + system %.2f, with its ffmpeg '
              'children%s)'
              % (code, wall, cpu, usage.ru_utime, usage.ru_stime,
                 ': %.2f s in the encoders, %.2f s in the writer threads' % (encoders, writers)
                 if mode == 'on' else ''))
        print('memory (peaks, sampled every 0.1 s): sensorTest and its children together PSS %.0f MB '
              '(USS %.0f MB), RSS %.0f MB; sensorTest alone RSS %.0f MB, the children RSS %.0f MB'
              % (m['pss_tree'], m['uss_tree'], m['rss_tree'], m['rss'], m['rss_children']))
        print('rostopic hz: CPU %.2f s (user %.2f + system %.2f)' % (hz_cpu, hz_usage.ru_utime, hz_usage.ru_stime))
        print('ratio: %.2fx (target <= %.1fx)%s' % (m['ratio'], TARGETS[mode],
                                                   '  [profiled: not comparable]' if profile else ''))
        if mode == 'on':
            print('end of window -> last file written: %s' % ('%.2f s' % last_file if last_file is not None
                                                              else 'no file'))
        print('publisher: %s s of publishing, finished %s s late' % (published['seconds'],
                                                                      published['finished_late_s']))
        if threads:
            print('CPU per thread (sampled every 0.1 s; the main thread first): %s'
                  % ', '.join('%.2f' % threads[t] for t in sorted(threads, key=lambda t: (t != st.pid, -threads[t]))))
        if profile and os.path.exists(profile):
            _print_profile(profile)
        return m
    finally:
        for p in reversed(procs):
            stop_group(p, timeout=10.0)


def _print_profile(path, top=15):
    """Top entries of a py-spy raw (collapsed stacks) profile: self and inclusive samples."""
    own: Dict[str, int] = {}
    incl: Dict[str, int] = {}
    total = 0
    with open(path) as f:
        for line in f:
            stack, _, count = line.rstrip().rpartition(' ')
            if not stack:
                continue
            n = int(count)
            total += n
            frames = [fr.split(' (')[0] + ' (' + fr.split(' (')[1].split(':')[0].split('/')[-1] + ')'
                      if ' (' in fr else fr for fr in stack.split(';')]
            own[frames[-1]] = own.get(frames[-1], 0) + n
            for fr in set(frames):
                incl[fr] = incl.get(fr, 0) + n
    print('profile %s: %d samples' % (path, total))
    print('  top self:')
    for fr, n in sorted(own.items(), key=lambda kv: -kv[1])[:top]:
        print('    %5.1f%%  %s' % (100.0 * n / total, fr))
    print('  top inclusive:')
    for fr, n in sorted(incl.items(), key=lambda kv: -kv[1])[:top]:
        print('    %5.1f%%  %s' % (100.0 * n / total, fr))


def run(args: argparse.Namespace) -> int:
    tmp = tempfile.mkdtemp(prefix='sensorTestBenchmark-')
    topics = os.path.join(tmp, 'benchTopics.dat')
    inputs = os.path.join(tmp, 'benchInput.ini')
    expect = os.path.join(tmp, 'benchExpectations.yaml')
    with open(topics, 'w') as f:
        f.writelines('%s %s\n' % (s[0], s[1]) for s in STREAMS)
    with open(inputs, 'w') as f:
        f.writelines('%s true\n' % s[0] for s in STREAMS)
    with open(expect, 'w') as f:
        f.write(_expectations(args.duration))
    master = PrivateMaster('/bench', ros_home=os.path.join(tmp, 'ros_home'))
    print('sensorTestBenchmark: %d CPUs, load average %s; output in %s'
          % (os.cpu_count() or 0, ' '.join('%.2f' % x for x in os.getloadavg()), tmp))
    rounds = []
    try:
        try:
            master.start(timeout=20.0)
        except MasterError as exc:
            print(str(exc))
            return 2
        for i in range(args.runs):
            for mode in args.modes:
                m = _round(args, tmp, master, (topics, inputs, expect), mode, '%s-%d' % (mode, i + 1))
                if 'error' in m:
                    print(m['error'])
                    return 2
                rounds.append(m)
        ok = _summary(rounds, args)
        if args.keep:
            print('kept: %s' % tmp)
        return 0 if ok else 1
    finally:
        master.stop()
        if not args.keep:
            shutil.rmtree(tmp, ignore_errors=True)


def _summary(rounds, args):
    head = '%-8s %10s %10s %7s %7s %11s %9s %9s %9s %s' % (
        'round', 'sensorTest', 'hz', 'ratio', 'target', 'last file', 'tree PSS', 'tree RSS', 'counts', 'met')
    print('\nsummary (CPU seconds of the whole process incl. children; side by side in one round)')
    print(head)
    print('-' * len(head))
    ok = True
    for m in rounds:
        met = [m['ratio'] <= TARGETS[m['mode']], m['pss_tree'] <= TARGET_RSS_MB, m['counts_ok']]
        if m['mode'] == 'on':
            met.append(m['last_file'] is not None and m['last_file'] <= TARGET_LAST_FILE_S)
        ok = ok and all(met)
        print('%-8s %9.2fs %9.2fs %6.2fx %6.1fx %11s %6.0f MB %6.0f MB %9s %s' % (
            m['label'], m['cpu'], m['hz_cpu'], m['ratio'], TARGETS[m['mode']],
            '%.2f s' % m['last_file'] if m['last_file'] is not None else '-', m['pss_tree'], m['rss_tree'],
            'all' if m['counts_ok'] else 'MISSING', 'yes' if all(met) else 'NO'))
    print('targets (issue 12): ratio <= 1.5x recording off, <= 5x recording on; last file <= %.0f s after the '
          'window; peak memory <= %.0f MB (PSS of sensorTest and its ffmpeg children together: shared '
          'libraries counted once; the RSS sum counts them once per process); >= %.0f%% received and '
          'recorded: %s' % (TARGET_LAST_FILE_S, TARGET_RSS_MB, 100 * args.target, 'all met' if ok else 'NOT all met'))
    return ok


def _table(results, published, out_dir, target, record=True):
    head = '%-21s %-38s %9s %9s %9s %8s %7s  %-7s %s' % (
        'sensor', 'stream', 'published', 'received', 'recorded', 'recv %', 'Hz', 'verdict', 'video')
    print('\n' + head)
    print('-' * len(head))
    ok = True
    rows = {}
    for name, _topic, enc, w, h, rate in STREAMS:
        r = results.get(name, {})
        sent = published['published'].get(name, 0)
        got = r.get('messages', 0)
        frames, extra = _recorded(out_dir, name) if record else (None, None)
        if name == 'microphone':
            stream = '4 x %d int16 @ 48 kHz, %.1f/s' % (w, rate)
            recorded = frames / float(w) if frames is not None else None
            video = extra or ('no WAV' if record else 'recording off')
        else:
            stream = '%dx%d %s @ %g Hz' % (w, h, enc, rate)
            recorded = frames
            v = (r.get('values') or {}).get('video') or {}
            video = '%s %s fps' % (v.get('codec'), v.get('fps')) if v.get('codec') else \
                ('no video' if record else 'recording off')
            if v.get('frames_dropped'):
                video += ', %d dropped' % v['frames_dropped']
        share_recv = got / float(sent) if sent else 0.0
        share_rec = (recorded or 0) / float(sent) if sent else 0.0
        ok = ok and share_recv >= target and (share_rec >= target or not record)
        rows[name] = {'published': sent, 'received': got, 'recorded': recorded}
        print('%-21s %-38s %9d %9d %9s %7.1f%% %7s  %-7s %s' % (
            name, stream, sent, got, ('%.0f' % recorded) if recorded is not None else '-',
            100 * share_recv, '%.2f' % r['rate_hz'] if r.get('rate_hz') else '-', r.get('verdict', '?'), video))
        for reason in r.get('reasons', []):
            print('%21s   reason: %s' % ('', reason))
    return rows, ok


def main(argv: Optional[Sequence[str]] = None) -> int:
    p = argparse.ArgumentParser(prog='sensorTestBenchmark', description=__doc__.split('\n\n')[0],
                                formatter_class=HelpFormatter,
                                epilog=__doc__.split('\n\n', 1)[1])
    p.add_argument('--duration', type=float, default=15.0, help='sensorTest --duration (default 15)')
    p.add_argument('--publish', type=float, default=None, help='seconds of publishing (default 10)')
    p.add_argument('--modes', default='off,on',
                   help='rounds per run: off (--no-record), on (recording), or off,on (default)')
    p.add_argument('--runs', type=int, default=1, help='repeat the rounds this many times (default 1)')
    p.add_argument('--no-record', dest='modes', action='store_const', const='off',
                   help='only the round with recording off (same as --modes off)')
    p.add_argument('--target', type=float, default=0.99, help='share that must be received and recorded')
    p.add_argument('--profile', metavar='DIR', help='run sensorTest under py-spy, profiles into DIR')
    p.add_argument('--threads', action='store_true', help='print the CPU of each sensorTest thread')
    p.add_argument('--keep', action='store_true', help='keep the temporary folder (videos, logs)')
    p.add_argument('--publisher', action='store_true', help=argparse.SUPPRESS)
    p.add_argument('--subscribers', type=int, default=1, help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.publisher:
        return publish(args.publish, wait=30.0, subscribers=args.subscribers)
    args.modes = [m.strip() for m in args.modes.split(',') if m.strip()]
    if not args.modes or any(m not in TARGETS for m in args.modes):
        p.error('--modes takes off, on or off,on')
    return run(args)
