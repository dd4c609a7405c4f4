"""sensorTestBenchmark: how much of a heavy media load sensorTest receives and records.

It starts its own roscore on a free port, a publisher process (rospy) with
  frontCamera, bottomCamera  640x480 rgb8 at 30 Hz
  depthCamera                320x240 16UC1 at 20 Hz
  stereoCamera               1280x360 rgb8 at 15 Hz
  realsenseRGBCamera         640x480 rgb8 at 30 Hz
  realsenseDepthCamera       640x480 16UC1 at 30 Hz
  microphone                 AudioCustomMsg 4 x 4096 samples at 48 kHz (11.7 buffers/s)
and runs `sensorTest --platform robot --mode parallel --duration D` over those topics as a
subprocess, with a temporary topics file, input file, expectations file and output folder.
The publisher waits until sensorTest has subscribed to every topic, then publishes for
`--publish` seconds (default D - 2) and stops, so the number published is exact and falls
inside the listening window (the temporary expectations accept the quiet tail).

Printed per topic: published, received (sensorTest's count), recorded (frames decoded from the
mp4 by ffprobe; buffers' worth of samples in the WAV), rate, verdict, video codec; then the
sensorTest process's CPU seconds (user + system, including its ffmpeg children) and peak RSS
(from wait4), and the machine. Exit code 0 when every stream reached the target share
(default 99 %) received and recorded, 1 otherwise.
"""
import argparse
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time

import numpy as np

from .rosmaster import MasterError, PrivateMaster, stop_group

STREAMS = [
    # sensor, topic, kind, width, height, rate
    ('frontCamera', '/bench/front/image_raw', 'rgb8', 640, 480, 30.0),
    ('bottomCamera', '/bench/bottom/image_raw', 'rgb8', 640, 480, 30.0),
    ('depthCamera', '/bench/depth/image_raw', '16UC1', 320, 240, 20.0),
    ('stereoCamera', '/bench/stereo/image_raw', 'rgb8', 1280, 360, 15.0),
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


def publish(seconds, wait):
    """Publisher process: wait for sensorTest's subscriptions, publish for `seconds`, report counts."""
    import rospy
    from sensor_msgs.msg import Image
    from pepper_interface_tests.msg import AudioCustomMsg
    rospy.init_node('sensor_test_benchmark_publisher', disable_signals=True)
    pubs, payloads = {}, {}
    for name, topic, enc, w, h, rate in STREAMS:
        cls = AudioCustomMsg if enc == 'audio' else Image
        pubs[name] = rospy.Publisher(topic, cls, queue_size=60)
        if enc == 'audio':
            t = np.arange(w * RING) / 48000.0
            chans = [(3000 * np.sin(2 * np.pi * f * t)).astype(np.int16) for f in (500, 1000, 1500, 2500)]
            payloads[name] = [[c[i * w:(i + 1) * w].tolist() for c in chans] for i in range(RING)]
        else:
            payloads[name] = _frames(enc, w, h)
    deadline = time.monotonic() + wait
    while any(p.get_num_connections() == 0 for p in pubs.values()):
        if time.monotonic() > deadline:
            missing = [n for n, p in pubs.items() if p.get_num_connections() == 0]
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
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    late = time.monotonic() - end
    print(json.dumps({'published': counts, 'seconds': seconds, 'finished_late_s': round(late, 3)}), flush=True)
    # stay up (and connected) until told to stop, so nothing is cut off in flight
    stop = threading.Event()
    signal.signal(signal.SIGTERM, lambda *_: stop.set())
    signal.signal(signal.SIGINT, lambda *_: stop.set())
    stop.wait(120)
    return 0


# ---------------------------------------------------------------- driver

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


def _sample_rss(pid, peak, stop):
    try:
        import psutil
        proc = psutil.Process(pid)
        while not stop.is_set():
            try:
                peak[0] = max(peak[0], proc.memory_info().rss)
            except psutil.Error:
                return
            stop.wait(0.2)
    except ImportError:
        return


def _recorded(out_dir, sensor):
    from . import catalog
    from .recording import ffprobe_frames
    if sensor == 'microphone':
        path = os.path.join(out_dir, 'microphoneOutput.wav')
        if not os.path.exists(path):
            return None, None
        import soundfile
        info = soundfile.info(path)
        return info.frames, '%d ch %d Hz %s' % (info.channels, info.samplerate, info.subtype)
    path = os.path.join(out_dir, catalog.SENSORS[sensor].video)
    if not os.path.exists(path):
        return None, None
    return ffprobe_frames(path), None


def run(args):
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    sensor_test = os.path.join(root, 'scripts', 'sensorTest')
    if not os.path.exists(sensor_test):
        import rospkg
        sensor_test = os.path.join(rospkg.RosPack().get_path('pepper_interface_tests'), 'scripts', 'sensorTest')
    tmp = tempfile.mkdtemp(prefix='sensorTestBenchmark-')
    out_dir = os.path.join(tmp, 'out')
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
    env = master.env()
    if args.codec:
        env['SENSORTEST_VIDEO_CODEC'] = args.codec
    publish_s = args.publish if args.publish else max(1.0, args.duration - 2.0)
    cmd = [sys.executable, sensor_test, '--topics', topics, '--input', inputs, '--expectations', expect,
           '--platform', 'robot', '--mode', 'parallel', '--duration', '%g' % args.duration,
           '--wait', '10', '--output-dir', out_dir, '--no-show', '--no-history', '--no-diagnostics',
           '--no-report'] + ([] if args.record else ['--no-record'])
    print('sensorTestBenchmark: %d CPUs, load average %s; output in %s'
          % (os.cpu_count(), ' '.join('%.2f' % x for x in os.getloadavg()), tmp))
    print('command: ' + ' '.join(cmd[1:]).replace(root + '/', ''))
    procs = []
    try:
        try:
            master.start(timeout=20.0)
        except MasterError as exc:
            print(str(exc))
            return 2
        env['ROS_MASTER_URI'] = master.uri  # start() moves to another port if its was taken
        pub = subprocess.Popen([sys.executable, os.path.abspath(sys.argv[0]), '--publisher',
                                '--publish', '%g' % publish_s], env=env, stdout=subprocess.PIPE,
                               text=True, start_new_session=True)
        procs.append(pub)
        time.sleep(1.0)
        log = open(os.path.join(tmp, 'sensorTest.log'), 'w')
        t0 = time.monotonic()
        st = subprocess.Popen(cmd, env=env, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
        procs.append(st)
        peak, stop = [0], threading.Event()
        sampler = threading.Thread(target=_sample_rss, args=(st.pid, peak, stop), daemon=True)
        sampler.start()
        _, status, usage = os.wait4(st.pid, 0)
        st.returncode = os.waitstatus_to_exitcode(status)
        wall = time.monotonic() - t0
        stop.set()
        log.close()
        pub.send_signal(signal.SIGTERM)
        line = pub.stdout.readline()
        pub.wait(15)
        published = json.loads(line) if line.strip() else {'error': 'publisher printed nothing'}
        if 'error' in published:
            print('publisher: ' + published['error'])
            return 2
        results_path = os.path.join(out_dir, 'sensorTestResults.json')
        if not os.path.exists(results_path):
            print('sensorTest wrote no results (exit %d); log: %s' % (st.returncode, log.name))
            return 2
        with open(results_path) as f:
            results = {s['name']: s for s in json.load(f)['sensors']}
        ok = _table(results, published, out_dir, args.target, args.record)
        cpu = usage.ru_utime + usage.ru_stime
        rss = max(peak[0], usage.ru_maxrss * 1024)
        print('\nsensorTest: exit %d, wall %.1f s, CPU %.1f s (user %.1f + system %.1f) = %.0f%% of one core '
              'over the run, peak RSS %.0f MB'
              % (st.returncode, wall, cpu, usage.ru_utime, usage.ru_stime, 100 * cpu / wall, rss / 1e6))
        print('publisher: %g s of publishing, finished %.3f s late' % (published['seconds'],
                                                                      published['finished_late_s']))
        print('target: >= %.0f%% of published messages received and recorded: %s'
              % (100 * args.target, 'met' if ok else 'NOT met'))
        if args.keep:
            print('kept: %s' % tmp)
        return 0 if ok else 1
    finally:
        for p in reversed(procs):
            stop_group(p, timeout=10.0)
        master.stop()
        if not args.keep:
            shutil.rmtree(tmp, ignore_errors=True)


def _table(results, published, out_dir, target, record=True):
    head = '%-21s %-38s %9s %9s %9s %8s %7s  %-7s %s' % (
        'sensor', 'stream', 'published', 'received', 'recorded', 'recv %', 'Hz', 'verdict', 'video')
    print('\n' + head)
    print('-' * len(head))
    ok = True
    for name, topic, enc, w, h, rate in STREAMS:
        r = results.get(name, {})
        sent = published['published'].get(name, 0)
        got = r.get('messages', 0)
        frames, extra = _recorded(out_dir, name)
        if name == 'microphone':
            stream = '4 x %d int16 @ 48 kHz, %.1f/s' % (w, rate)
            recorded = frames / float(w) if frames is not None else None
            video = extra or 'no WAV'
        else:
            stream = '%dx%d %s @ %g Hz' % (w, h, enc, rate)
            recorded = frames
            v = (r.get('values') or {}).get('video') or {}
            video = '%s %s fps' % (v.get('codec'), v.get('fps')) if v.get('codec') else 'no video'
            if v.get('frames_dropped'):
                video += ', %d dropped' % v['frames_dropped']
        share_recv = got / float(sent) if sent else 0.0
        share_rec = (recorded or 0) / float(sent) if sent else 0.0
        ok = ok and share_recv >= target and (share_rec >= target or not record)
        print('%-21s %-38s %9d %9d %9s %7.1f%% %7s  %-7s %s' % (
            name, stream, sent, got, ('%.0f' % recorded) if recorded is not None else '-',
            100 * share_recv, '%.2f' % r['rate_hz'] if r.get('rate_hz') else '-', r.get('verdict', '?'), video))
        for reason in r.get('reasons', []):
            print('%21s   reason: %s' % ('', reason))
    return ok


def main(argv=None):
    p = argparse.ArgumentParser(prog='sensorTestBenchmark', description=__doc__.split('\n\n')[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog=__doc__.split('\n\n', 1)[1])
    p.add_argument('--duration', type=float, default=10.0, help='sensorTest --duration (default 10)')
    p.add_argument('--publish', type=float, default=None, help='seconds of publishing (default duration - 2)')
    p.add_argument('--codec', choices=('auto', 'avc1', 'mp4v'), default=None,
                   help='force the video codec (SENSORTEST_VIDEO_CODEC); default auto')
    p.add_argument('--no-record', dest='record', action='store_false',
                   help='pass --no-record to sensorTest (cost of checking alone)')
    p.add_argument('--target', type=float, default=0.99, help='share that must be received and recorded')
    p.add_argument('--keep', action='store_true', help='keep the temporary folder (videos, logs)')
    p.add_argument('--publisher', action='store_true', help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.publisher:
        return publish(args.publish, wait=30.0)
    return run(args)
