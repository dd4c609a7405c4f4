"""Options that mean what they say, as a user runs sensorTest against a real master (test/rosmaster.py)
with the package's own files: --cameras with the shipped input file, --require-heard without the
microphone, and the microphone's window in --mic-mode sequential as the header tells it."""
import json
import os
import subprocess
import sys

from pepper_interface_tests.plan import declaration
from report_helpers import sensor_test
from rosmaster import NODES, kill_group, spawn, wait_for_publishers

HERE = NODES   # the node scripts' folder (test/nodes/)
MEDIA = os.path.join(HERE, 'media_publisher.py')
# the shipped data/pepperTopics.dat names these topics
REALSENSE_RGB, REALSENSE_DEPTH = '/camera/color/image_raw', '/camera/aligned_depth_to_color/image_raw'
PEPPER_CAMS = list(declaration.sensors_of(camera='pepper'))


def media(master, *args):
    return spawn([sys.executable, MEDIA] + list(args), master.env(), stdout=subprocess.DEVNULL,
                 stderr=subprocess.DEVNULL)


def results_of(out):
    with open(os.path.join(str(out), 'sensorTestResults.json'), encoding='utf-8') as f:
        data = json.load(f)
    return {s['name']: s for s in data['sensors']}


def notes(stdout):
    """The header's notes, each joined back from its wrapped lines ('  note: ...' then 8 spaces)."""
    out = []
    for line in stdout.splitlines():
        if line.startswith('  note: '):
            out.append(line[len('  note: '):])
        elif out and line.startswith(' ' * 8) and not line.strip().startswith('start '):
            out[-1] += ' ' + line.strip()
        elif out and line.startswith('  start'):
            break
    return out


def test_cameras_realsense_tests_the_realsense_with_the_shipped_input_file(module_master, tmp_path, monkeypatch):
    """Before: 4 SKIPPED, no camera tested, and exit 0 as far as the cameras went."""
    monkeypatch.setenv('COLUMNS', '80')      # the header below is judged at 80 columns, whatever runs the tests
    pubs = [media(module_master, 'camera', REALSENSE_RGB, '--rate', '15', '--node', 'rs_rgb'),
            media(module_master, 'depth', REALSENSE_DEPTH, '--rate', '15', '--node', 'rs_depth')]
    try:
        wait_for_publishers(module_master, [REALSENSE_RGB, REALSENSE_DEPTH])   # before sensorTest looks
        proc = sensor_test(module_master, ['--cameras', 'realsense', '--mode', 'parallel', '--duration', '2',
                                           '--wait', '1.5', '--no-record', '--no-report', '--no-history',
                                           '--no-diagnostics', '--output-dir', str(tmp_path)])
    finally:
        for p in pubs:
            kill_group(p)
    assert proc.returncode in (0, 1) and 'Traceback' not in proc.stderr, proc.stdout + proc.stderr
    r = results_of(tmp_path)
    assert r['realsenseRGBCamera']['verdict'] == 'PASS', r['realsenseRGBCamera']['reasons']
    assert r['realsenseDepthCamera']['verdict'] == 'PASS', r['realsenseDepthCamera']['reasons']
    assert r['realsenseRGBCamera']['messages'] >= 15
    for name in PEPPER_CAMS:           # the input file enables them; the option leaves them out
        assert r[name]['verdict'] == 'SKIPPED' and r[name]['reasons'] == ['left out by --cameras realsense']
    said = notes(proc.stdout)
    assert any(n.startswith('cameras: realsenseRGBCamera, realsenseDepthCamera (--cameras realsense, '
                            'whatever sensorTestInput.ini says)') for n in said), proc.stdout
    assert any(n.startswith('skipped: ' + ', '.join(PEPPER_CAMS)) for n in said)
    # the notes come right under the run header, before any sensor starts, wrapped to 80 columns
    lines = proc.stdout.splitlines()
    first_start = next(i for i, line in enumerate(lines) if line.strip().startswith('start '))
    header = lines[:first_start]
    # the input file's sensors and, by --cameras realsense, the RealSense's: every declared one
    assert header[0].startswith('sensorTest: %d sensors' % len(declaration.on_head())) and len(said) >= 2
    # each line fits, or is one unbreakable word (the results folder's path on its own line)
    assert all(len(line) <= 80 or len(line.split()) == 1 for line in header[1:]), header


def test_default_run_header_says_the_realsense_is_left_out(module_master, tmp_path):
    proc = sensor_test(module_master, ['--sensors', 'laser', '--duration', '0.5', '--wait', '0.5',
                                       '--no-report', '--no-history', '--no-diagnostics',
                                       '--output-dir', str(tmp_path)])
    assert proc.returncode == 1, proc.stdout + proc.stderr            # nobody publishes the laser
    assert not any('RealSense' in n for n in notes(proc.stdout))     # --sensors: the user named them
    proc = sensor_test(module_master, ['--duration', '0.5', '--wait', '0.5', '--mode', 'parallel',
                                       '--no-record', '--no-report', '--no-history', '--no-diagnostics',
                                       '--output-dir', str(tmp_path)], timeout=60)
    said = notes(proc.stdout)
    assert 'not tested: realsenseRGBCamera, realsenseDepthCamera (false in sensorTestInput.ini)' in said, proc.stdout
    assert any('--cameras realsense' in n and '--cameras both' in n for n in said)


def test_require_heard_without_the_microphone_is_refused(module_master, tmp_path):
    """Before: speech passed with no note, though nothing could hear it."""
    for extra in (['--require-heard'], ['_require_heard:=true']):
        proc = sensor_test(module_master, ['--sensors', 'speech,laser', '--output-dir', str(tmp_path)] + extra)
        assert proc.returncode == 2, proc.stdout + proc.stderr
        assert 'microphone is not in this run' in proc.stderr and '--sensors speech,microphone' in proc.stderr
        assert 'Traceback' not in proc.stderr
        assert not os.path.exists(tmp_path / 'runs') and not os.path.exists(tmp_path / 'sensorTestResults.json')


def test_header_tells_the_microphone_window_in_sequential_mic_mode(module_master, tmp_path):
    """Before: the header said "1 s each" while the microphone listened 4 s."""
    pub = media(module_master, 'audio', '/naoqi_driver/audio', '--node', 'mics')
    try:
        wait_for_publishers(module_master, ['/naoqi_driver/audio'])
        proc = sensor_test(module_master, ['--sensors', 'microphone', '--mic-mode', 'sequential',
                                           '--duration', '1', '--wait', '2', '--no-record', '--no-report',
                                           '--no-history', '--no-diagnostics', '--output-dir', str(tmp_path)])
    finally:
        kill_group(pub)
    assert proc.returncode in (0, 1), proc.stdout + proc.stderr
    said = notes(proc.stdout)
    assert 'microphone listens 4 s: --mic-mode sequential, each of the 4 microphones for 1 s' in said, proc.stdout
    window = results_of(tmp_path)['microphone']['window_s']
    assert 3.8 <= window <= 4.6, window                    # what the header says is what happened


def test_emulator_launch_with_realsense_tests_the_realsense(master, tmp_path):
    """Before: `pepperEmulator.launch realsense:=true run_test:=true` published the RealSense
    topics but sensorTest never listened to them (cameras=both kept the input file's false)."""
    from rosmaster import ROOT
    out_dir = tmp_path / 'results'
    log_path = tmp_path / 'roslaunch.log'
    with open(str(log_path), 'w') as log:
        launch = spawn(['roslaunch', os.path.join(ROOT, 'launch', 'pepperEmulator.launch'), 'realsense:=true',
                        'run_test:=true', 'audio:=direct', 'duration:=3', 'output_dir:=%s' % out_dir],
                       master.env(), stdout=log, stderr=subprocess.STDOUT)
        try:
            launch.wait(timeout=150)      # run_test:=true: the launch ends with sensorTest
        except subprocess.TimeoutExpired:
            pass                          # the results below say what did not happen
        finally:
            kill_group(launch)
    text = log_path.read_text()
    r = results_of(out_dir)
    for name in ('realsenseRGBCamera', 'realsenseDepthCamera'):
        assert r[name]['verdict'] != 'SKIPPED' and r[name]['messages'] > 0, (name, r[name], text[-3000:])
    # both = Pepper's cameras too: those of the emulator's head (stereo)
    assert all(r[n]['verdict'] != 'SKIPPED' for n in PEPPER_CAMS if 'stereo' in declaration.SENSORS[n].heads)
    assert any(n.startswith('cameras: bottomCamera, frontCamera, realsenseRGBCamera, realsenseDepthCamera')
               for n in notes(text)), text
