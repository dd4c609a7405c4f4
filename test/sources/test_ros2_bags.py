"""`sensorTest --bag` on ROS 2 recordings (no ROS 2 installed): one synthetic Pepper recording,
good and with one fault per family, written as a ROS 1 bag and as ROS 2 recordings in every
storage form (rosbags' writer: sqlite3 and MCAP folders, per-message and per-file zstd, two split
files, a lone .db3; the mcap-ros2-support writer: a lone .mcap) must get the same verdict, message
count, rate and reasons (topic names aside) for every sensor. Then naoqi_driver2's own choices:
its topic names found without options, the yohatad/naoqi_driver2 fork told by its odometry frame
and judged with its profile, the at-rest note, --driver and --topics overriding the pick, videos
and WAV written from a ROS 2 recording.

sensorTest runs as a real subprocess with no ROS master (ROS_MASTER_URI points nowhere).
"""
import json
import os
import shutil

import numpy as np
import pytest

import fake_pepper as fake
import ros2_recordings as rr
from pepper_interface_tests.plan.textfile import ConfigError
from pepper_interface_tests.sources.ros2bag import check_rosbags
from rosbags_support import OLD_ROSBAGS, reads_ros2
from rosmaster import script

NO_MASTER = dict(os.environ, ROS_MASTER_URI='http://127.0.0.1:1')
QUIET = ['--no-history', '--no-report', '--no-record', '--no-show', '--no-diagnostics']


@pytest.fixture(autouse=True)
def _reading_needs_new_rosbags(request):
    """Every test here reads ROS 2 recordings (skipped on rosbags < 0.10, as on Python 3.8),
    but those of the refusal on such a rosbags."""
    if OLD_ROSBAGS and 'old_rosbags' not in request.node.name:
        pytest.skip(reads_ros2.kwargs['reason'])


def run(bag, out, *extra, sensors=rr.SENSORS, quiet=QUIET):
    cmd = script('sensorTest') + ['--bag', str(bag), '--sensors', sensors, '--output-dir', str(out)]
    p = __import__('subprocess').run(cmd + list(quiet) + list(extra), env=NO_MASTER,
                                     capture_output=True, text=True, timeout=120)
    assert 'Traceback' not in p.stdout + p.stderr, p.stdout + p.stderr
    path = os.path.join(str(out), 'sensorTestResults.json')
    data = {}
    if os.path.exists(path):
        with open(path) as f:
            data = {s['name']: s for s in json.load(f)['sensors']}
    return p, data


def verdicts(data):
    """What must not depend on the recording's format: per sensor, the verdict, the message
    count, the rate and the reasons with naoqi_driver2's topic names written as the ROS 1 ones."""
    out = {}
    for name, s in data.items():
        reasons = []
        for r in s['reasons']:
            for ros1, ros2 in rr.TOPICS.values():
                r = r.replace(' %s ' % ros2, ' %s ' % ros1)
            reasons.append(r)
        out[name] = (s['verdict'], s['messages'], s['rate_hz'], tuple(reasons))
    return out


def _db3_file(path, recs):
    folder = rr.write_rosbags(path, recs, 'sqlite3')
    return os.path.join(folder, os.path.basename(folder) + '.db3')


FORMS = {
    'rosbags-sqlite3': lambda p, recs: rr.write_rosbags(p, recs, 'sqlite3'),
    'rosbags-mcap': lambda p, recs: rr.write_rosbags(p, recs, 'mcap'),
    'mcap-ros2-support-file': lambda p, recs: rr.write_mcap_ros2(str(p) + '.mcap', recs),
    'db3-file': _db3_file,
    'sqlite3-zstd-message': lambda p, recs: rr.write_rosbags(p, recs, 'sqlite3', compression='message'),
    'mcap-zstd-file': lambda p, recs: rr.write_rosbags(p, recs, 'mcap', compression='file'),
    'sqlite3-split': lambda p, recs: rr.write_split(p, recs, 'sqlite3'),
    'mcap-split': lambda p, recs: rr.write_split(p, recs, 'mcap'),
}
# every form once, the four writers' own files (a folder of each storage, the lone .db3, the
# mcap-ros2-support .mcap) with the faults too
CASES = ([('good', form) for form in FORMS if form not in ('db3-file', 'mcap-split')]
         + [('faulty', form) for form in ('db3-file', 'rosbags-mcap', 'mcap-ros2-support-file',
                                          'mcap-split')])


@pytest.fixture(scope='module')
def ros1(tmp_path_factory):
    """The ROS 1 bag's results per variant, each computed once."""
    cache = {}

    def get(variant):
        if variant not in cache:
            d = tmp_path_factory.mktemp('ros1_' + variant)
            bag = rr.write_ros1(d / 'pepper.bag', rr.records(faulty=variant == 'faulty'))
            p, data = run(bag, d / 'out')
            assert p.returncode == (1 if variant == 'faulty' else 0), p.stdout + p.stderr
            cache[variant] = data
        return cache[variant]
    return get


@pytest.mark.parametrize('variant,form', CASES)
def test_same_data_same_verdicts_as_a_ros1_bag(ros1, variant, form, tmp_path):
    expected = ros1(variant)
    recording = FORMS[form](tmp_path / 'pepper', rr.records(faulty=variant == 'faulty'))
    p, data = run(recording, tmp_path / 'out')
    assert p.returncode == (1 if variant == 'faulty' else 0), p.stdout + p.stderr
    # naoqi_driver2's names found with no option, and the profile said
    assert 'topics of naoqi_driver2' in p.stdout and 'driver profile naoqi_driver2:' in p.stdout, p.stdout
    assert verdicts(data) == verdicts(expected)
    # not vacuous: the good data passes, every injected fault fails by its name
    for name, s in data.items():
        if variant == 'faulty' and name in rr.FAULTS:
            assert s['verdict'] == 'FAIL' and any(rr.FAULTS[name] in r for r in s['reasons']), s
        else:
            assert s['verdict'] == 'PASS', s
            assert s['messages'] == int(rr.SECONDS * rr.RATES[name]), s


# Every topic's first record at this very nanosecond. As a float of seconds it reads 68 ns
# later (floor(t * 1e9)) and genpy.Time.from_sec(t) 16 ns later: a start computed from the float
# (as both sources did) leaves every topic's first message out.
FIRST_NS = 1700000000123456700


def test_first_instant_is_read_in_full_from_every_form(tmp_path):
    """Record times are integer nanoseconds end to end: a recording whose topics all start at
    the same nanosecond gives every message, in a ROS 1 bag, in ROS 2 recordings written by
    rosbags (sqlite3, MCAP) and in ROS 2 recordings converted from the bag by rosbags-convert,
    with the bag's verdicts (the camera frames and audio buffers through the one-copy path)."""
    import math
    t = FIRST_NS / 1e9
    assert math.floor(t * 1e9) > FIRST_NS and __import__('genpy').Time.from_sec(t).to_nsec() > FIRST_NS
    recs = rr.records(first_ns=FIRST_NS)
    bag = rr.write_ros1(tmp_path / 'pepper.bag', recs)
    p, ros1 = run(bag, tmp_path / 'out1')
    assert p.returncode == 0, p.stdout + p.stderr
    expected = {name: int(rr.SECONDS * rr.RATES[name]) for name in rr.TOPICS}
    assert {name: s['messages'] for name, s in ros1.items()} == expected
    forms = {
        'rosbags-sqlite3': rr.write_rosbags(tmp_path / 'w_db3', recs, 'sqlite3'),
        'rosbags-mcap': rr.write_rosbags(tmp_path / 'w_mcap', recs, 'mcap'),
        'convert-sqlite3': rr.convert(bag, tmp_path / 'c_db3', 'sqlite3'),
        'convert-mcap': rr.convert(bag, tmp_path / 'c_mcap', 'mcap'),
    }
    for form, recording in forms.items():
        # camera frames and audio buffers take the one-copy conversion (sources/cdr_fast.py)
        from pepper_interface_tests.sources.ros2bag import Ros2BagSource
        source = Ros2BagSource(recording)
        assert set(source.converter.fast) == {'sensor_msgs/msg/Image', 'naoqi_bridge_msgs/msg/AudioBuffer'}, form
        source.close()
        p, data = run(recording, tmp_path / ('out_' + form))
        assert p.returncode == 0, (form, p.stdout + p.stderr)
        assert {name: s['messages'] for name, s in data.items()} == expected, form
        assert verdicts(data) == verdicts(ros1), form


def test_the_fork_is_judged_with_its_profile(tmp_path):
    """yohatad/naoqi_driver2: odometry pepper_odom -> base_footprint, +inf = nothing in range."""
    recs = rr.records(fork=True)
    mcap = rr.write_mcap_ros2(tmp_path / 'fork.mcap', recs)
    p, data = run(mcap, tmp_path / 'out')
    assert p.returncode == 0, p.stdout + p.stderr
    assert 'driver profile yohatad_naoqi_driver2: its odometry is in the frame pepper_odom' in p.stdout
    assert all(s['verdict'] == 'PASS' for s in data.values()), data
    # the same data judged as stock naoqi_driver2 data: the odometry frames are wrong
    p, stock = run(mcap, tmp_path / 'out2', '--driver', 'naoqi_driver2')
    assert p.returncode == 1 and 'driver profile' not in p.stdout, p.stdout
    assert stock['odometry']['verdict'] == 'FAIL'
    assert any('pepper_odom' in r for r in stock['odometry']['reasons']), stock['odometry']
    # and the ROS 1 bag of the same data with --driver gives the ROS 2 recording's verdicts
    bag = rr.write_ros1(tmp_path / 'fork.bag', recs)
    p, ros1 = run(bag, tmp_path / 'out3', '--driver', 'yohatad_naoqi_driver2')
    assert verdicts(ros1) == verdicts(data)


def test_the_forks_dead_board_fails_by_name(tmp_path):
    """A NaN segment from yohatad/naoqi_driver2 is that board dead; the same scans from a ROS 1
    bag judged with the fork's profile give the same verdicts."""
    recs = rr.records(fork=True, faulty=True, leave_out=[s for s in rr.TOPICS if s not in ('laser', 'odometry')])
    folder = rr.write_rosbags(tmp_path / 'dead', recs, 'sqlite3')
    p, data = run(folder, tmp_path / 'out', sensors='laser,odometry')
    assert 'driver profile yohatad_naoqi_driver2' in p.stdout, p.stdout
    laser = data['laser']
    assert laser['verdict'] == 'FAIL', laser
    assert any(r.startswith('right board (slots 0-14) dead') and 'NaN' in r for r in laser['reasons']), laser
    assert not any('front board' in r or 'left board' in r for r in laser['reasons']), laser
    bag = rr.write_ros1(tmp_path / 'dead.bag', recs)
    p, ros1 = run(bag, tmp_path / 'out1', '--driver', 'yohatad_naoqi_driver2', sensors='laser,odometry')
    assert verdicts(ros1) == verdicts(data)


def test_fork_laser_silent_at_rest_says_so(tmp_path):
    recs = rr.records(fork=True, leave_out=('laser',))
    folder = rr.write_rosbags(tmp_path / 'rest', recs, 'mcap')
    p, data = run(folder, tmp_path / 'out', sensors='laser,odometry')
    assert p.returncode == 1, p.stdout + p.stderr
    laser = data['laser']
    assert laser['verdict'] == 'FAIL' and laser['messages'] == 0
    assert any('/laser' in r and 'robot is at rest' in r for r in laser['reasons']), laser
    assert data['odometry']['verdict'] == 'PASS'
    # stock naoqi_driver2 publishes the laser whatever the robot does: no such note
    p, stock = run(folder, tmp_path / 'out2', '--driver', 'naoqi_driver2', sensors='laser')
    assert not any('at rest' in r for r in stock['laser']['reasons']), stock['laser']


def test_topics_option_still_chooses(tmp_path):
    folder = rr.write_rosbags(tmp_path / 'rec', rr.records(), 'sqlite3')
    topics = tmp_path / 'mine.dat'
    topics.write_text('Laser /somewhere/else\n')
    p, data = run(folder, tmp_path / 'out', '--topics', str(topics), sensors='laser')
    assert p.returncode == 1 and 'topics of naoqi_driver2' not in p.stdout, p.stdout
    assert data['laser']['reasons'] == ['topic /somewhere/else is not in the bag']


def test_videos_and_wav_from_a_ros2_recording(tmp_path):
    mcap = rr.write_mcap_ros2(tmp_path / 'media.mcap', rr.records(leave_out=('jointState',)))
    p, data = run(mcap, tmp_path / 'out', sensors='frontCamera,microphone',
                  quiet=['--no-history', '--no-report', '--no-show', '--no-diagnostics'])
    assert p.returncode == 0, p.stdout + p.stderr
    files = os.listdir(str(tmp_path / 'out'))
    assert 'microphoneOutput.wav' in files and 'frontCameraOutput.mp4' in files, files
    import soundfile
    audio, rate = soundfile.read(str(tmp_path / 'out' / 'microphoneOutput.wav'))
    assert rate == 48000 and audio.shape[1] == 4
    assert audio.shape[0] == data['microphone']['messages'] * 8192


def write_image_recording(path, megabytes, storage, width=640, height=480, rate=10.0):
    """A rosbag2 folder of `megabytes` of distinct rgb8 frames on naoqi_driver2's front camera."""
    import numpy as np
    rng = np.random.default_rng(1)
    base = rng.integers(0, 256, size=width * height * 3, dtype=np.uint8)
    n = int(megabytes * 1e6 // base.size) + 1

    def frames():
        for i in range(n):
            t = rr.T0 + i / rate
            m = rr.fake.image(np.roll(base, i * 997).reshape(height, width, 3), 'rgb8',
                              frame_id='CameraTop_optical_frame')
            m.header.stamp = rr.genpy.Time.from_sec(t)
            yield rr.Record('frontCamera', t, m)
    return rr.write_rosbags(path, frames(), storage), n


PEAK_RSS = ('import resource, subprocess, sys\n'
            'code = subprocess.call(sys.argv[1:], stdout=sys.stderr)\n'
            'print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss, code)\n')


def peak_rss_kb(recording, out):
    import subprocess
    import sys
    cmd = [sys.executable, '-c', PEAK_RSS] + script('sensorTest') + [
        '--bag', str(recording), '--sensors', 'frontCamera', '--output-dir', str(out)] + QUIET
    p = subprocess.run(cmd, env=NO_MASTER, capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stdout + p.stderr
    kb, code = p.stdout.split()
    assert code in ('0', '1'), p.stderr
    with open(os.path.join(str(out), 'sensorTestResults.json')) as f:
        return int(kb), json.load(f)['sensors'][0]['messages']


@pytest.mark.slow
@pytest.mark.parametrize('storage', ['sqlite3', 'mcap'])
def test_a_large_ros2_recording_is_streamed_not_loaded(storage, tmp_path):
    big, frames = write_image_recording(tmp_path / 'big', 250, storage)
    small, _ = write_image_recording(tmp_path / 'small', 3, storage)
    size_kb = rr.size(big) / 1024.0
    base, _ = peak_rss_kb(small, tmp_path / 'out_small')
    peak, messages = peak_rss_kb(big, tmp_path / 'out_big')
    assert messages == frames                           # every frame reached the check
    print('\n%s recording %.0f MB, %d frames: peak RSS %.0f MB (small: %.0f MB)'
          % (storage, size_kb / 1024, frames, peak / 1024.0, base / 1024.0))
    # loading the recording would add its size; streaming adds a chunk and the check's state
    assert peak - base < 0.2 * size_kb, (peak, base, size_kb)


def test_a_record_at_a_bogus_time_is_left_out_as_in_a_ros1_bag(tmp_path):
    """The dense-window rule on ROS 2 receive times (nanoseconds): one record at t = 1 s in a
    recording at 1.7e9 s is left out and named, as sources/test_bag.py does for a ROS 1 bag."""
    good = [r for r in rr.records(leave_out=[s for s in rr.TOPICS if s != 'backSonar'])]
    odd = rr.Record('backSonar', 1.0, rr.message('backSonar', 0, 1.0))
    folder = rr.write_rosbags(tmp_path / 'odd', [odd] + good, 'mcap')
    bag = rr.write_ros1(tmp_path / 'odd.bag', [odd] + good)
    results = []
    for recording, out in ((folder, 'o2'), (bag, 'o1')):
        p, data = run(recording, tmp_path / out, sensors='backSonar')
        note = next(ln for ln in p.stdout.splitlines() if 'odd times' in ln)
        assert ('1 record at odd times left out (t = 1 s)' in note
                and '%d records checked' % len(good) in note), note
        assert data['backSonar']['messages'] == len(good) and data['backSonar']['window_s'] < 5.0
        results.append(verdicts(data))
    assert results[0] == results[1]


def test_the_fork_is_told_when_only_its_laser_is_checked(tmp_path):
    recs = rr.records(fork=True, leave_out=('laser',))
    folder = rr.write_rosbags(tmp_path / 'rest', recs, 'sqlite3')
    p, data = run(folder, tmp_path / 'out', sensors='laser')
    assert 'driver profile yohatad_naoqi_driver2' in p.stdout, p.stdout
    assert any('robot is at rest' in r for r in data['laser']['reasons']), data['laser']


# ------------------------------------------------------------------ ros2 bad recordings
# Bad ROS 2 recordings given to `sensorTest --bag`: a clear error naming the file and the fix
# (exit 2) where nothing can be read, a per-sensor reason naming the topic where one topic cannot
# be read, never a traceback. Real files written here (rosbags, mcap-ros2-support), then broken.

def error_of(path, tmp_path, sensors='laser,imu'):
    p, data = run(path, tmp_path / 'out', sensors=sensors)
    assert p.returncode == 2, p.stdout + p.stderr
    assert not data
    text = p.stdout + p.stderr
    lines = [ln for ln in text.splitlines() if ln.startswith('sensorTest: error: ')]
    assert len(lines) == 1 and lines[0].startswith('sensorTest: error: %s: ' % path), text
    assert 'fix: ' in text, text
    return text


def truncated(src, dst):
    with open(src, 'rb') as f:
        data = f.read()
    with open(dst, 'wb') as f:
        f.write(data[:len(data) // 2])
    return str(dst)


def test_folder_without_metadata_yaml(tmp_path):
    folder = rr.write_rosbags(tmp_path / 'rec', rr.records(seconds=1.0), 'sqlite3')
    os.remove(os.path.join(folder, 'metadata.yaml'))
    out = error_of(folder, tmp_path)
    assert 'no metadata.yaml in this folder' in out and 'ros2 bag reindex' in out
    # its storage file alone is still a recording
    p, data = run(os.path.join(folder, 'rec.db3'), tmp_path / 'alone', sensors='laser,imu')
    assert p.returncode == 0 and data['laser']['messages'] == 10, p.stdout


def test_truncated_db3_and_mcap(tmp_path):
    recs = rr.records(seconds=1.0)
    folder = rr.write_rosbags(tmp_path / 'rec', recs, 'sqlite3')
    db3 = truncated(os.path.join(folder, 'rec.db3'), tmp_path / 'cut.db3')
    assert 'cannot open the ROS 2 recording' in error_of(db3, tmp_path / 'a')
    mcap = truncated(rr.write_mcap_ros2(tmp_path / 'whole.mcap', recs), tmp_path / 'cut.mcap')
    out = error_of(mcap, tmp_path / 'b')
    assert 'cannot open the ROS 2 recording' in out and 'mcap recover' in out
    # the same inside a rosbag2 folder
    mfolder = rr.write_rosbags(tmp_path / 'mrec', recs, 'mcap')
    truncated(os.path.join(mfolder, 'mrec.mcap'), tmp_path / 'tmp.mcap')
    shutil.move(str(tmp_path / 'tmp.mcap'), os.path.join(mfolder, 'mrec.mcap'))
    assert 'cannot open the ROS 2 recording' in error_of(mfolder, tmp_path / 'c')


def test_unknown_storage_plugin(tmp_path):
    folder = rr.write_rosbags(tmp_path / 'rec', rr.records(seconds=1.0), 'sqlite3')
    meta = os.path.join(folder, 'metadata.yaml')
    with open(meta) as f:
        text = f.read()
    with open(meta, 'w') as f:
        f.write(text.replace('storage_identifier: sqlite3', 'storage_identifier: rosbag_v3'))
    assert "Storage plugin 'rosbag_v3' not supported" in error_of(folder, tmp_path)


def test_empty_recording_and_renamed_mcap(tmp_path):
    from rosbags.rosbag2 import Writer
    from rosbags.typesys import Stores, get_typestore
    w = Writer(str(tmp_path / 'empty'), version=8)
    with w:
        w.add_connection('/laser', 'sensor_msgs/msg/LaserScan', typestore=get_typestore(Stores.ROS2_HUMBLE))
    assert 'holds no message' in error_of(str(tmp_path / 'empty'), tmp_path / 'a')
    mcap = rr.write_mcap_ros2(tmp_path / 'rec.mcap', rr.records(seconds=1.0))
    renamed = str(tmp_path / 'rec.bin')
    shutil.copy(mcap, renamed)
    assert 'rename it to end in .mcap' in error_of(renamed, tmp_path / 'b')


def test_a_topic_whose_type_has_no_definition(tmp_path):
    """A Humble-style sqlite3 recording (no definitions stored) with a type nobody defines: that
    sensor fails naming its topic and type, the others are judged."""
    from rosbags.rosbag2 import Writer
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore
    ts = get_typestore(Stores.ROS2_HUMBLE)
    ts.register(get_types_from_msg('std_msgs/Header header\nfloat32[] values\n', 'acme_msgs/msg/Scan'))
    scan = ts.types['acme_msgs/msg/Scan']
    header, time = ts.types['std_msgs/msg/Header'], ts.types['builtin_interfaces/msg/Time']
    nodef = {'msgdef': '', 'rihs01': 'RIHS01_' + '0' * 64}
    w = Writer(str(tmp_path / 'rec'), version=8)
    with w:
        laser = w.add_connection('/laser', 'acme_msgs/msg/Scan', **nodef)
        imu = w.add_connection('/imu/base', 'sensor_msgs/msg/Imu', **nodef)
        for r in rr.records(seconds=2.0, leave_out=[s for s in rr.TOPICS if s != 'imu']):
            ns = int(round(r.t * 1e9))
            m = scan(header=header(stamp=time(sec=int(r.t), nanosec=0), frame_id='x'),
                     values=np.array([1.0], dtype=np.float32))
            w.write(laser, ns, ts.serialize_cdr(m, 'acme_msgs/msg/Scan'))
            w.write(imu, ns, bytes(ts.ros1_to_cdr(fake.serialized(r.msg), 'sensor_msgs/msg/Imu')))
    p, data = run(str(tmp_path / 'rec'), tmp_path / 'out', sensors='laser,imu')
    assert p.returncode == 1, p.stdout + p.stderr
    note = [ln for ln in p.stdout.splitlines() if 'cannot be read' in ln]
    assert len(note) == 1 and 'topic /laser' in note[0] and 'acme_msgs/msg/Scan' in note[0], p.stdout
    assert data['laser']['verdict'] == 'FAIL'
    assert data['laser']['reasons'][0].startswith('topic /laser carries acme_msgs/Scan'), data['laser']
    assert data['imu']['verdict'] == 'PASS' and data['imu']['messages'] == 20


# ------------------------------------------------------------------ old rosbags (Python 3.8)
# rosbags 0.9.23, the last release for Python 3.8 (Ubuntu 20.04's), failed inside: "'Typestore'
# object has no attribute 'fielddefs'", and on a ROS 2 Jazzy recording "ReaderError: Rosbag2
# version 9 not supported". sensorTest now refuses ROS 2 recordings there in one sentence.

def test_old_rosbags_is_refused_in_one_sentence_with_the_fix():
    with pytest.raises(ConfigError) as err:
        check_rosbags('/data/run', (0, 9, 23))
    text = str(err.value)
    first, fix = text.split('\n')
    assert first.startswith('/data/run: reading a ROS 2 recording needs rosbags 0.10 or later, '
                            'which needs Python 3.10 or later (here: rosbags 0.9.23 on Python ')
    assert fix.startswith('  fix: ') and 'rosbags-convert --src /data/run' in fix
    check_rosbags('/data/run', (0, 10, 0))
    check_rosbags('/data/run', (0, 11, 9))


@pytest.mark.skipif(not OLD_ROSBAGS, reason='rosbags 0.10 or later reads ROS 2 recordings')
def test_a_ros2_recording_on_old_rosbags_ends_with_one_error_and_exit_2(tmp_path):
    """A real ROS 2 recording (rosbags-convert of 0.9.23 itself, from a ROS 1 bag) and a lone
    MCAP file (mcap-ros2-support) given to sensorTest on old rosbags."""
    import subprocess
    import sys
    bag = rr.write_ros1(tmp_path / 'pepper.bag', rr.records(seconds=1.0))
    exe = os.path.join(os.path.dirname(sys.executable), 'rosbags-convert')
    subprocess.run([exe, str(bag), '--dst', str(tmp_path / 'ros2')], check=True, timeout=120)
    for recording in (str(tmp_path / 'ros2'), str(tmp_path / 'ros2' / 'ros2.db3')):
        text = error_of(recording, tmp_path)
        assert 'reading a ROS 2 recording needs rosbags 0.10 or later' in text, text
