"""`sensorTest --bag` (bag.py) on awkward real bags, written here with rosbag's Python API:

* a record at a bogus time (t = 1 s in a bag recorded at 1.7e9 s): the window is the bag's dense
  part and a note names the odd record (before: the run listened "for 1.7e+09 s", i.e. forever);
* a bag of ~250 MB of camera images: the replay streams it, so the sensorTest process's peak RSS
  grows by far less than the bag's size (before: the whole bag was read into memory).

sensorTest runs as a real subprocess with no ROS master (ROS_MASTER_URI points nowhere).
"""
import json
import os
import subprocess
import sys
import time

import genpy
import rosbag

import fake_pepper as fake
from pepper_interface_tests.sources.bag import MAX_SILENCE, dense_span
from rosmaster import script

T0 = 1700000000.0
NO_MASTER = dict(os.environ, ROS_MASTER_URI='http://127.0.0.1:1')
# Runs sensorTest and prints its peak RSS (kB): RUSAGE_CHILDREN of this wrapper is exactly the
# sensorTest process (and anything it waited for), whatever else the test process ran before.
PEAK_RSS = ('import resource, subprocess, sys\n'
            'code = subprocess.call(sys.argv[1:], stdout=sys.stderr)\n'
            'print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss, code)\n')


def sonar(t):
    return fake.sonar(t=t, range=1.2)


def run_bag(bag, out, sensors, timeout=60, wrap=False):
    cmd = script('sensorTest') + ['--bag', str(bag), '--sensors', sensors, '--output-dir', str(out),
                                  '--no-history', '--no-report', '--no-record', '--no-show',
                                  '--no-diagnostics']
    if wrap:
        cmd = [sys.executable, '-c', PEAK_RSS] + cmd
    return subprocess.run(cmd, env=NO_MASTER, capture_output=True, text=True, timeout=timeout)


def results(out):
    with open(os.path.join(str(out), 'sensorTestResults.json')) as f:
        return {s['name']: s for s in json.load(f)['sensors']}


def test_dense_span_leaves_out_isolated_records():
    dense = [T0 + 0.1 * i for i in range(30)]
    assert dense_span(dense) == (dense[0], dense[-1], 0, 0)
    assert dense_span([1.0] + dense) == (dense[0], dense[-1], 1, 0)
    assert dense_span(dense + [T0 + 4e8]) == (dense[0], dense[-1], 0, 1)
    # healthy but unusual: a quiet stretch shorter than MAX_SILENCE keeps the bag whole
    quiet = dense + [dense[-1] + MAX_SILENCE - 1]
    assert dense_span(quiet) == (dense[0], quiet[-1], 0, 0)
    assert dense_span([]) == (0.0, 0.0, 0, 0)


def test_a_record_at_a_bogus_time_does_not_stretch_the_window(tmp_path):
    bag_path = str(tmp_path / 'bogus.bag')
    with rosbag.Bag(bag_path, 'w') as bag:
        bag.write('/naoqi_driver/sonar/back', sonar(1.0), genpy.Time.from_sec(1.0))   # the odd one
        for i in range(30):
            t = T0 + 0.1 * i
            bag.write('/naoqi_driver/sonar/back', sonar(t), genpy.Time.from_sec(t))
    start = time.monotonic()
    p = run_bag(bag_path, tmp_path / 'out', 'backSonar')
    took = time.monotonic() - start
    assert p.returncode in (0, 1), p.stdout + p.stderr
    assert 'Traceback' not in p.stderr
    note = next(line for line in p.stdout.splitlines() if 'odd times' in line)
    assert '1 record at odd times left out (t = 1 s)' in note and '30 records checked' in note, note
    back = results(tmp_path / 'out')['backSonar']
    assert back['messages'] == 30
    assert back['window_s'] < 5.0, back['window_s']          # 2.9 s of data (+0.2), not 1.7e9 s
    assert took < 30, took


def write_image_bag(path, megabytes, width=640, height=480, rate=10.0):
    import numpy as np
    rng = np.random.default_rng(1)
    base = rng.integers(0, 256, size=width * height * 3, dtype=np.uint8)
    n = int(megabytes * 1e6 // base.size) + 1
    with rosbag.Bag(path, 'w') as bag:
        for i in range(n):
            t = T0 + i / rate
            m = fake.image(np.roll(base, i * 997).reshape(height, width, 3), 'rgb8', t=t,   # no two alike
                           frame_id='CameraTop_optical_frame')
            bag.write('/naoqi_driver/camera/front/image_raw', m, genpy.Time.from_sec(t))
    return n


def peak_rss_kb(p):
    assert p.returncode == 0, p.stdout + p.stderr
    kb, code = p.stdout.split()
    assert code in ('0', '1'), p.stderr
    return int(kb)


def test_a_large_bag_is_streamed_not_loaded(tmp_path):
    big, small = str(tmp_path / 'big.bag'), str(tmp_path / 'small.bag')
    frames = write_image_bag(big, 250)
    write_image_bag(small, 3)
    size_kb = os.path.getsize(big) / 1024.0
    base = peak_rss_kb(run_bag(small, tmp_path / 'out_small', 'frontCamera', wrap=True))
    start = time.monotonic()
    p = run_bag(big, tmp_path / 'out_big', 'frontCamera', wrap=True, timeout=120)
    took = time.monotonic() - start
    peak = peak_rss_kb(p)
    front = results(tmp_path / 'out_big')['frontCamera']
    assert front['messages'] == frames                       # every frame reached the check
    growth = peak - base
    print('\nbag %.0f MB, %d frames: peak RSS %.0f MB (small bag: %.0f MB, growth %.0f MB), %.1f s'
          % (size_kb / 1024, frames, peak / 1024.0, base / 1024.0, growth / 1024.0, took))
    # loading the bag would add its size; streaming adds about one chunk and the check's state
    assert growth < 0.2 * size_kb, (peak, base, size_kb)


# ------------------------------------------------------------------ bag platform hint
# A bag checked with the wrong platform: every sensor fails as "not in the bag", and a note
# names the platform whose topics the bag does hold. Real bags written with rosbag, the real
# sensorTest script with no master.

def write(path, topics):
    with rosbag.Bag(str(path), 'w') as bag:
        for i in range(30):
            t = T0 + 0.1 * i
            for topic in topics:
                bag.write(topic, sonar(t), genpy.Time.from_sec(t))
    return path


def test_simulator_bag_checked_as_robot_suggests_the_simulator(tmp_path):
    bag = write(tmp_path / 'sim.bag', ['/pepper/sonar_back', '/pepper/sonar_front'])
    p = run_bag(bag, tmp_path / 'out', 'backSonar,frontSonar')
    assert p.returncode == 1 and 'Traceback' not in p.stderr, p.stdout + p.stderr
    r = results(tmp_path / 'out')
    assert r['backSonar']['reasons'] == ['topic /naoqi_driver/sonar/back is not in the bag']
    notes = [ln for ln in p.stdout.splitlines() if 'note:' in ln and '--platform' in ln]
    assert len(notes) == 1, p.stdout
    assert ('0 of the 2 robot topics are in the bag, but 2 of the simulator topics are '
            '(/pepper/sonar_back, /pepper/sonar_front): check it with --platform simulator') in notes[0]


def test_right_platform_or_unrelated_bag_gets_no_hint(tmp_path):
    own = write(tmp_path / 'robot.bag', ['/naoqi_driver/sonar/back'])
    p = run_bag(own, tmp_path / 'o1', 'backSonar,frontSonar')     # frontSonar merely missing
    assert '--platform' not in p.stdout, p.stdout
    other = write(tmp_path / 'other.bag', ['/some/other'])
    p = run_bag(other, tmp_path / 'o2', 'backSonar')
    assert p.returncode == 1 and '--platform' not in p.stdout, p.stdout
