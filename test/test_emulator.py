"""pepperEmulator and recordTestBags against a real roscore, real rospy subscribers, real bags.

The emulator runs as a subprocess (scripts/pepperEmulator); what it publishes is received by
test/emu_listen.py (a real rospy node in its own process) and checked against the sensor facts
of docs (pepper-sensors.md): types, encodings, sizes, frame ids, rates within +-20 %, content
that changes, the 61-beam laser layout, unit quaternions; then every fault, bad fault strings,
/speech reaching the microphones, and the bags written by recordTestBags.
"""
import json
import math
import os
import pathlib
import subprocess
import sys
import time

import psutil
import pytest

from rosmaster import kill_group, script, spawn

HERE = os.path.dirname(os.path.abspath(__file__))
LISTEN = [sys.executable, os.path.join(HERE, 'emu_listen.py')]
NS = '/naoqi_driver'

# topic -> (type, nominal Hz, frame_id, extra expectations): the reference facts, written out
# here independently of the emulator's own table.
ROBOT = {
    NS + '/sonar/back': ('sensor_msgs/Range', 10, 'SonarBack_frame', dict(min=0.25, max=2.55)),
    NS + '/sonar/front': ('sensor_msgs/Range', 10, 'SonarFront_frame', dict(min=0.25, max=2.55)),
    NS + '/camera/front/image_raw': ('sensor_msgs/Image', 10, 'CameraTop_optical_frame',
                                     dict(encoding='rgb8', width=320, height=240)),
    NS + '/camera/bottom/image_raw': ('sensor_msgs/Image', 10, 'CameraBottom_optical_frame',
                                      dict(encoding='rgb8', width=320, height=240)),
    NS + '/camera/depth/image_raw': ('sensor_msgs/Image', 10, 'CameraDepth_optical_frame',
                                     dict(encoding='16UC1', width=320, height=240)),
    NS + '/camera/stereo/image_raw': ('sensor_msgs/Image', 10, 'CameraDepth_optical_frame',
                                      dict(encoding='rgb8', width=640, height=180)),
    NS + '/laser': ('sensor_msgs/LaserScan', 10, 'base_footprint', dict(min=0.1, max=3.0)),
    NS + '/audio': ('pepper_interface_tests/AudioCustomMsg', 48000 / 4096.0, None, {}),
    '/joint_states': ('sensor_msgs/JointState', 50, '', {}),
    NS + '/odom': ('nav_msgs/Odometry', 15, 'odom', dict(child='base_link')),
    NS + '/imu/base': ('sensor_msgs/Imu', 10, 'base_footprint', {}),
    NS + '/imu/torso': ('sensor_msgs/Imu', 10, 'base_link', {}),
    '/camera/color/image_raw': ('sensor_msgs/Image', 15, None,
                                dict(encoding='rgb8', width=640, height=480)),
    '/camera/aligned_depth_to_color/image_raw': ('sensor_msgs/Image', 15, None,
                                                 dict(encoding='16UC1', width=640, height=480)),
}
SIMULATOR = {
    '/pepper/sonar_back': ('sensor_msgs/Range', 20, 'SonarBack_frame', dict(min=0.0, max=5.0)),
    '/pepper/sonar_front': ('sensor_msgs/Range', 20, 'SonarFront_frame', dict(min=0.0, max=5.0)),
    '/pepper/camera/front/image_raw': ('sensor_msgs/Image', 5, 'CameraTop_optical_frame',
                                       dict(encoding='rgb8', width=640, height=480)),
    '/pepper/camera/bottom/image_raw': ('sensor_msgs/Image', 5, 'CameraBottom_optical_frame',
                                        dict(encoding='rgb8', width=640, height=480)),
    '/pepper/camera/depth/image_raw': ('sensor_msgs/Image', 20, 'CameraDepth_optical_frame',
                                       dict(encoding='16UC1', width=320, height=240)),
    '/pepper/laser_2': ('sensor_msgs/LaserScan', 6.25, 'base_footprint', dict(min=0.1, max=7.0)),
    '/joint_states': ('sensor_msgs/JointState', 50, '', {}),
    '/pepper/odom': ('nav_msgs/Odometry', 20, 'odom', {}),
}
JOINTS = ['HeadYaw', 'HeadPitch', 'HipRoll', 'HipPitch', 'KneePitch', 'LShoulderPitch',
          'LShoulderRoll', 'LElbowYaw', 'LElbowRoll', 'LWristYaw', 'LHand', 'RShoulderPitch',
          'RShoulderRoll', 'RElbowYaw', 'RElbowRoll', 'RWristYaw', 'RHand', 'WheelFL', 'WheelFR',
          'WheelB']
BLIND = list(range(15, 23)) + list(range(38, 46))


# ---------------------------------------------------------------- helpers

def unique_name():
    """A node name of its own for each emulator run: `_param:=value` arguments become private
    params on the (shared) master and would otherwise be inherited by the next run."""
    return 'pepperEmulator_%d' % time.time_ns()


class Emulator(object):
    """The emulator script as a subprocess; output captured in a file."""

    def __init__(self, master, tmp_path, *params):
        self.name = unique_name()
        self.log_path = str(tmp_path / (self.name + '.log'))
        self.log = open(self.log_path, 'w')
        self.proc = spawn(script('pepperEmulator') + ['__name:=' + self.name] + list(params),
                          master.env(), stdout=self.log, stderr=subprocess.STDOUT)

    def output(self):
        self.log.flush()
        with open(self.log_path) as f:
            return f.read()

    def stop(self):
        code = kill_group(self.proc)
        self.log.close()
        return code

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.stop()


def listen(master, topics, duration, *extra, wait=30):
    out = subprocess.run(LISTEN + ['--duration', str(duration), '--wait', str(wait)] + list(extra)
                         + list(topics), env=master.env(), stdout=subprocess.PIPE,
                         timeout=duration + wait + 60)
    assert out.returncode == 0, 'listener failed'
    return json.loads(out.stdout)


def check_stream(topic, got, expected, tolerance=0.2):
    """Type, rate (+-tolerance), frame id, header and per-type facts of one topic."""
    type_name, hz, frame, extra = expected
    problems = []
    if got is None:
        return ['%s: nothing received' % topic]
    if got['type'] != type_name:
        problems.append('%s: type %s, expected %s' % (topic, got['type'], type_name))
    rate = got.get('rate', 0.0)
    if not (1 - tolerance) * hz <= rate <= (1 + tolerance) * hz:
        problems.append('%s: rate %.2f Hz, expected %.2f +-%d%%' % (topic, rate, hz, tolerance * 100))
    if frame is not None and got['frames'] != [frame]:
        problems.append('%s: frame ids %s, expected %s' % (topic, got['frames'], frame))
    if 'stamp_delay' in got and got['stamp_delay'] > 1.0:
        problems.append('%s: header stamps %.2f s away from receive time' % (topic, got['stamp_delay']))
    if not got['seq_increasing']:
        problems.append('%s: header.seq not increasing' % topic)
    for key in ('encoding', 'width', 'height'):
        if key in extra and got.get(key) != extra[key]:
            problems.append('%s: %s %s, expected %s' % (topic, key, got.get(key), extra[key]))
    if type_name == 'sensor_msgs/Image':
        bpp = 2 if extra['encoding'] == '16UC1' else 3
        if got['step'] != got['width'] * bpp or got['data_len'] != got['step'] * got['height']:
            problems.append('%s: step %s / data %s inconsistent' % (topic, got['step'], got['data_len']))
        if len(set(got['digest'])) < 0.9 * len(got['digest']):
            problems.append('%s: only %d distinct frames of %d' % (
                topic, len(set(got['digest'])), len(got['digest'])))
        if extra['encoding'] == '16UC1':
            zero = sum(got['zero_share']) / len(got['zero_share'])
            if not 0.0 < zero < 0.2:
                problems.append('%s: share of invalid (0) depth pixels %.3f' % (topic, zero))
    if type_name == 'sensor_msgs/LaserScan':
        if got['n'] != 61 or any(idx != BLIND for idx in got['blind_idx']):
            problems.append('%s: %s ranges, blind beams %s' % (topic, got['n'], got['blind_idx'][0]))
        if abs(got['angle_min'] + 2.0944) > 1e-3 or abs(got['angle_max'] - 2.0944) > 1e-3 or \
                abs(got['angle_min'] + 60 * got['angle_increment'] - got['angle_max']) > 1e-3:
            problems.append('%s: angles %s..%s step %s do not give 61 beams' % (
                topic, got['angle_min'], got['angle_max'], got['angle_increment']))
        if abs(got['range_min'] - extra['min']) > 1e-6 or abs(got['range_max'] - extra['max']) > 1e-6:
            problems.append('%s: range limits %s..%s' % (topic, got['range_min'], got['range_max']))
        if max(got['nan']) or max(got['beyond']):
            problems.append('%s: NaN or out-of-range beams' % topic)
        if len(set(got['digest'])) < 0.9 * len(got['digest']):
            problems.append('%s: scans do not change' % topic)
    if type_name == 'sensor_msgs/Range':
        values = got['range']
        if got['radiation_type'] != 0 or abs(got['field_of_view'] - 0.5236) > 1e-3 or \
                abs(got['min_range'] - extra['min']) > 1e-6 or abs(got['max_range'] - extra['max']) > 1e-6:
            problems.append('%s: Range fields %s' % (topic, {k: got[k] for k in (
                'radiation_type', 'field_of_view', 'min_range', 'max_range')}))
        if None in values or min(values) < extra['min'] or max(values) > extra['max']:
            problems.append('%s: ranges outside %s..%s' % (topic, extra['min'], extra['max']))
        elif len(set(values)) < 3:
            problems.append('%s: range does not vary' % topic)
    if type_name in ('sensor_msgs/Imu', 'nav_msgs/Odometry'):
        if any(abs(q - 1.0) > 1e-6 for q in got['qnorm']):
            problems.append('%s: quaternion not unit (%s..%s)' % (topic, min(got['qnorm']), max(got['qnorm'])))
    if type_name == 'sensor_msgs/Imu':
        if any(a is None or abs(a - 9.81) > 0.3 for a in got['acc_z']):
            problems.append('%s: linear_acceleration.z is not gravity' % topic)
    if type_name == 'nav_msgs/Odometry':
        if 'child' in extra and got['child_frame_id'] != extra['child']:
            problems.append('%s: child_frame_id %s' % (topic, got['child_frame_id']))
        xs, ys = got['x'], got['y']
        if None in xs or max(xs) - min(xs) < 0.01:
            problems.append('%s: the robot does not move' % topic)
        # twist consistent with the pose: distance travelled ~ vx * time
        dt = (len(xs) - 1) / hz
        travelled = sum(math.hypot(x1 - x0, y1 - y0) for x0, y0, x1, y1 in
                        zip(xs, ys, xs[1:], ys[1:]))
        if abs(travelled - got['vx'][0] * dt) > 0.3 * got['vx'][0] * dt:
            problems.append('%s: travelled %.3f m in %.1f s at vx %.3f' % (topic, travelled, dt, got['vx'][0]))
    if type_name == 'sensor_msgs/JointState':
        if got['names'] != JOINTS or not got['n_pos'] == got['n_vel'] == got['n_eff'] == 20:
            problems.append('%s: joints %s / %d %d %d' % (topic, got['names'], got['n_pos'],
                                                          got['n_vel'], got['n_eff']))
        if max(got['nan']) or len(set(got['digest'])) < 0.9 * len(got['digest']):
            problems.append('%s: NaN or unchanging positions' % topic)
    if type_name.endswith('AudioCustomMsg'):
        lengths = [got['len_' + c] for c in ('rearLeft', 'rearRight', 'frontLeft', 'frontRight')]
        if lengths != [4096] * 4:
            problems.append('%s: samples per channel %s' % (topic, lengths))
        if min(min(r[1:]) for r in got['rms']) < 10:
            problems.append('%s: a silent channel' % topic)
    return problems


# ---------------------------------------------------------------- profiles

def test_robot_profile_all_topics(module_master, tmp_path):
    """Every robot topic (audio direct, RealSense on): types, sizes, frames, rates, content; CPU."""
    with Emulator(module_master, tmp_path, '_audio:=direct', '_realsense:=true') as emu:
        proc = psutil.Process(emu.proc.pid)
        cpu0, t0 = proc.cpu_times(), time.time()
        got = listen(module_master, list(ROBOT), 8.0)
        cpu1, t1 = proc.cpu_times(), time.time()
        log = emu.output()
    cpu = (cpu1.user + cpu1.system - cpu0.user - cpu0.system) / (t1 - t0)
    print('emulator CPU with every robot topic subscribed: %.0f%% of one core' % (100 * cpu))
    assert 'all 13 publishers up (14 topics, robot profile' in log
    problems = [p for topic, exp in ROBOT.items() for p in check_stream(topic, got.get(topic), exp)]
    assert not problems, '\n'.join(problems)
    assert got[NS + '/odom']['publishers'] == ['/' + emu.name]
    assert cpu < 1.0, 'the emulator needs %.0f%% of a core' % (100 * cpu)


def test_simulator_profile(module_master, tmp_path):
    """The simulator's topics and characteristics; none of the robot-only topics."""
    robot_only = [NS + '/camera/front/image_raw', NS + '/imu/base', NS + '/audio',
                  NS + '/camera/stereo/image_raw', '/camera/color/image_raw', '/speech']
    with Emulator(module_master, tmp_path, '_profile:=simulator', '_audio:=direct',
                  '_realsense:=true'):
        got = listen(module_master, list(SIMULATOR), 6.0,
                     *[a for t in robot_only for a in ('--absent', t)])
    problems = [p for topic, exp in SIMULATOR.items() for p in check_stream(topic, got.get(topic), exp)]
    assert not problems, '\n'.join(problems)
    for topic in robot_only:        # the master may remember types of earlier runs' topics
        assert got[topic].get('count', 0) == 0 and got[topic]['publishers'] == [], topic
    assert not [n for n in got['/speech']['subscribers'] if 'pepperEmulator' in n]


def test_rate_factor_and_resolution(module_master, tmp_path):
    with Emulator(module_master, tmp_path, '_rate_factor:=0.5', '_camera_resolution:=QQVGA'):
        topics = [NS + '/camera/front/image_raw', NS + '/camera/depth/image_raw', '/joint_states']
        got = listen(module_master, topics, 5.0)
    front = got[NS + '/camera/front/image_raw']
    depth = got[NS + '/camera/depth/image_raw']
    assert (front['width'], front['height'], depth['width'], depth['height']) == (160, 120, 160, 120)
    assert 4.0 <= front['rate'] <= 6.0 and 20.0 <= got['/joint_states']['rate'] <= 30.0


# ---------------------------------------------------------------- faults

BATCH_1 = ('frontCamera:frozen;bottomCamera:black;depthCamera:wrong_encoding;'
           'stereoCamera:wrong_step;laser:nan;frontSonar:out_of_range;backSonar:silent;'
           'imu:broken_quaternion;odometry:rate=0.3;jointState:die_after=3;'
           'microphone:silent_channel=rearRight;realsenseRGBCamera:wrong_type;'
           'realsenseDepthCamera:wrong_encoding')
BATCH_2 = ('LASER:out_of_range;frontsonar:nan;backSonar:rate=2;imu:nan;odometry:nan,broken_quaternion;'
           'jointState:nan,out_of_range;microphone:silent;frontCamera:wrong_encoding;'
           'bottomCamera:wrong_step;depthCamera:black;stereoCamera:die_after=2;'
           'realsenseDepthCamera:frozen;realsenseRGBCamera:black')


def _faults_batch_1(got, start):
    front = got[NS + '/camera/front/image_raw']
    assert len(set(front['digest'])) == 1 and front['count'] > 20, 'frozen: same bytes every frame'
    assert 8 <= front['rate'] <= 12, 'frozen camera keeps its rate'
    bottom = got[NS + '/camera/bottom/image_raw']
    assert max(bottom['max']) == 0 and bottom['count'] > 20, 'black: all-zero image'
    depth = got[NS + '/camera/depth/image_raw']
    assert depth['encoding'] == '32FC1' and depth['step'] == 320 * 2, 'wrong_encoding on depth'
    stereo = got[NS + '/camera/stereo/image_raw']
    assert stereo['step'] < 640 * 3 and stereo['data_len'] == 640 * 3 * 180, 'wrong_step'
    laser = got[NS + '/laser']
    assert min(laser['nan']) > 0 and laser['n'] == 61, 'laser nan'
    sonar = got[NS + '/sonar/front']['range']
    assert all(r is not None and not 0.25 <= r <= 2.55 for r in sonar), 'sonar out_of_range'
    back = got[NS + '/sonar/back']
    assert back['count'] == 0 and len(back['publishers']) == 1, 'silent: advertised only'
    imu = got[NS + '/imu/base']
    assert all(abs(q - 1.0) > 0.1 for q in imu['qnorm']) and imu['count'] > 20, 'broken_quaternion'
    odom = got[NS + '/odom']
    assert 0.8 * 4.5 <= odom['rate'] <= 1.2 * 4.5, 'rate=0.3 of 15 Hz'
    joints = got['/joint_states']
    assert joints['count'] > 20 and joints['last_time'] - start < 3.5, 'die_after=3 stops it'
    assert joints['publishers'] == [], 'die_after unregisters the topic'
    audio = got[NS + '/audio']
    levels = [r[1:] for r in audio['rms']]
    assert all(lv[1] == 0 for lv in levels) and all(min(lv[0], lv[2], lv[3]) > 10 for lv in levels), \
        'silent_channel=rearRight silences only rearRight'
    rs_rgb = got['/camera/color/image_raw']
    assert rs_rgb['type'] == 'std_msgs/String' and rs_rgb['count'] > 20, 'wrong_type'
    rs_depth = got['/camera/aligned_depth_to_color/image_raw']
    assert rs_depth['encoding'] == '32FC1', 'wrong_encoding on RealSense depth'


def _faults_batch_2(got, start):
    laser = got[NS + '/laser']
    assert min(laser['beyond']) > 30 and max(laser['nan']) == 0, 'laser out_of_range'
    assert all(r is None for r in got[NS + '/sonar/front']['range']), 'sonar nan'
    assert 0.8 * 20 <= got[NS + '/sonar/back']['rate'] <= 1.2 * 20, 'rate=2 doubles the rate'
    imu = got[NS + '/imu/base']
    assert all(a is None for a in imu['acc_z']) and all(abs(q - 1) < 1e-6 for q in imu['qnorm'])
    odom = got[NS + '/odom']
    assert all(x is None for x in odom['x']) and all(abs(q - 1.0) > 0.1 for q in odom['qnorm'])
    joints = got['/joint_states']
    assert min(joints['nan']) == 2 and min(joints['max_abs']) >= 3.0, 'joint nan + out_of_range'
    audio = got[NS + '/audio']
    assert audio['count'] == 0 and len(audio['publishers']) == 1, 'microphone silent'
    assert got[NS + '/camera/front/image_raw']['encoding'] == 'bgr8'
    bottom = got[NS + '/camera/bottom/image_raw']
    assert bottom['step'] < 320 * 3 and bottom['encoding'] == 'rgb8'
    depth = got[NS + '/camera/depth/image_raw']
    assert max(depth['max']) == 0 and depth['encoding'] == '16UC1', 'black depth'
    stereo = got[NS + '/camera/stereo/image_raw']
    assert stereo['count'] > 5 and stereo['last_time'] - start < 2.5 and stereo['publishers'] == []
    rs_depth = got['/camera/aligned_depth_to_color/image_raw']
    assert len(set(rs_depth['digest'])) == 1 and rs_depth['count'] > 20
    assert max(got['/camera/color/image_raw']['max']) == 0


@pytest.mark.parametrize('faults,check', [(BATCH_1, _faults_batch_1), (BATCH_2, _faults_batch_2)],
                         ids=['batch1', 'batch2'])
def test_faults(module_master, tmp_path, faults, check):
    """Every fault type, on every sensor family it applies to, shows in what is received."""
    topics = [t for t in ROBOT]
    with Emulator(module_master, tmp_path, '_audio:=direct', '_realsense:=true',
                  '_faults:=' + faults) as emu:
        # listen from the moment the emulator is up, so die_after can be timed
        deadline = time.time() + 30
        while 'publishers up' not in emu.output() and time.time() < deadline:
            time.sleep(0.05)
        start = time.time()
        got = listen(module_master, topics, 6.0)
        log = emu.output()
    assert 'faults: ' in log and 'die_after' in log
    check(got, start)


@pytest.mark.parametrize('params,words', [
    (['_faults:=laser:melted'], ['unknown fault "melted"', 'nan', 'out_of_range', 'silent']),
    (['_faults:=tailCamera:frozen'], ['unknown sensor "tailCamera"', 'frontCamera', 'laser', 'imu']),
    (['_faults:=laser:broken_quaternion'], ['does not apply to laser', 'nan']),
    (['_faults:=microphone:silent_channel=rearRight'], ['~audio direct', 'silent-channel']),
    (['_profile:=simulator', '_faults:=imu:nan'], ['"imu" is not published', 'simulator']),
    (['_profile:=android'], ['android', 'robot, simulator']),
])
def test_bad_configuration_exits_2(module_master, tmp_path, params, words):
    out = subprocess.run(script('pepperEmulator') + ['__name:=' + unique_name()] + params,
                         env=module_master.env(),
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=60)
    assert out.returncode == 2, out.stdout
    for word in words:
        assert word in out.stdout, out.stdout


def test_no_master_exits_2(tmp_path):
    from rosmaster import Master, free_port
    env = Master().env(ROS_MASTER_URI='http://127.0.0.1:%d' % free_port())
    out = subprocess.run(script('pepperEmulator'), env=env, stdout=subprocess.PIPE,
                         stderr=subprocess.STDOUT, text=True, timeout=60)
    assert out.returncode == 2 and 'no ROS master' in out.stdout


# ---------------------------------------------------------------- speech

def test_speech_raises_direct_audio_level(module_master, tmp_path):
    """/speech is mixed into the microphones (audio direct): the level rises well above the tones."""
    with Emulator(module_master, tmp_path, '_audio:=direct') as emu:
        got = listen(module_master, [NS + '/audio'], 7.0, '--speech',
                     'This is the CSSR4Africa speaker test.', '--speech-at', '2.0')
        log = emu.output()
    spoke_at = got['_meta']['spoke_at']
    rms = got[NS + '/audio']['rms']
    before = [max(r[1:]) for r in rms if r[0] < spoke_at]
    after = [max(r[1:]) for r in rms if r[0] > spoke_at]
    assert len(before) > 10 and len(after) > 20
    assert max(after) > 2.5 * max(before), 'speech did not reach the microphones: %s -> %s' % (
        max(before), max(after))
    assert 'CSSR4Africa speaker test' in log


def test_speech_reaches_naoqi_endpoint(module_master, tmp_path):
    """Audio bridge mode: /speech -> ALTextToSpeech.say on a real libqi endpoint (naoqiEndpoint),
    heard in the microphones that naoqiAudio + naoqiAudioPublisher bring back to ROS."""
    from rosmaster import free_port
    env = module_master.env()
    naoqi, ws = free_port(), free_port()
    log = open(str(tmp_path / 'chain.log'), 'w')
    procs = [spawn(script('naoqiEndpoint') + ['--port', str(naoqi)], env, stdout=log,
                   stderr=subprocess.STDOUT),
             spawn(script('naoqiAudioPublisher') + ['__name:=' + unique_name() + '_pub',
                                                    '_port:=%d' % ws], env, stdout=log,
                   stderr=subprocess.STDOUT)]
    try:
        with Emulator(module_master, tmp_path, '_naoqi_url:=tcp://127.0.0.1:%d' % naoqi) as emu:
            procs.append(spawn(script('naoqiAudio') + ['--ip', '127.0.0.1', '--port', str(naoqi),
                                                       '--ws', 'ws://127.0.0.1:%d' % ws],
                               env, stdout=log, stderr=subprocess.STDOUT))
            got = listen(module_master, [NS + '/audio'], 8.0, '--speech',
                         'This is the CSSR4Africa speaker test.', '--speech-at', '3.0')
            emu_log = emu.output()
    finally:
        for p in reversed(procs):
            kill_group(p)
        log.close()
    chain = (tmp_path / 'chain.log').read_text()
    spoke_at = got['_meta']['spoke_at']
    rms = got[NS + '/audio']['rms']
    before = [max(r[1:]) for r in rms if r[0] < spoke_at]
    after = [max(r[1:]) for r in rms if r[0] > spoke_at]
    assert before and after, 'no audio through the bridge\n' + chain
    assert max(after) > 1.5 * max(before), 'speech not heard: %s -> %s\n%s\n%s' % (
        max(before), max(after), emu_log, chain)
    assert 'not reachable' not in emu_log


def test_speech_without_naoqi_endpoint_warns_once(module_master, tmp_path):
    """Audio bridge mode with no NAOqi endpoint: one warning, and the sensors keep publishing."""
    from rosmaster import free_port
    url = 'tcp://127.0.0.1:%d' % free_port()
    with Emulator(module_master, tmp_path, '_naoqi_url:=' + url) as emu:
        got = listen(module_master, [NS + '/laser'], 3.0, '--speech', 'one', '--speech-at', '0.5')
        got2 = listen(module_master, [NS + '/laser'], 3.0, '--speech', 'two', '--speech-at', '0.5')
        time.sleep(1.0)
        log = emu.output()
    assert log.count('not reachable') == 1, log
    assert url in log
    assert got[NS + '/laser']['count'] > 15 and got2[NS + '/laser']['count'] > 15


# ---------------------------------------------------------------- recordTestBags

def test_record_test_bags(recorded_bags):
    """recordTestBags writes small, complete bags (own roscore) that rosbag opens."""
    import rosbag
    out_dir = pathlib.Path(os.path.dirname(recorded_bags['robot_good']))
    names = sorted(os.listdir(out_dir))
    assert not [n for n in names if n.endswith('.active')], names
    for name in ('robot_good.bag', 'simulator_good.bag', 'robot_faulty.bag'):
        assert name in names, names
    expected = {
        'robot_good.bag': set(ROBOT),
        'robot_faulty.bag': set(ROBOT) - {NS + '/sonar/back'},   # silent: never published
        'simulator_good.bag': set(SIMULATOR),
    }
    for name, topics in expected.items():
        path = out_dir / name
        size = path.stat().st_size
        assert size < 8e6, '%s is %.1f MB' % (name, size / 1e6)
        with rosbag.Bag(str(path)) as bag:
            info = bag.get_type_and_topic_info().topics
            assert set(info) == topics, '%s: %s' % (name, sorted(set(info) ^ topics))
            for topic in topics:
                exp = (ROBOT if name.startswith('robot') else SIMULATOR)[topic]
                assert info[topic].msg_type == exp[0]
                assert info[topic].message_count >= 2 * exp[1], (name, topic, info[topic].message_count)
            assert '/speech' not in info and '/rosout' not in info
            if name == 'robot_faulty.bag':
                frames = {bytes(m.data) for _, m, _ in bag.read_messages([NS + '/camera/front/image_raw'])}
                assert len(frames) == 1, 'frontCamera:frozen recorded'
                scan = next(bag.read_messages([NS + '/laser']))[1]
                assert any(math.isnan(r) for r in scan.ranges)
            if name == 'robot_good.bag':
                frames = {bytes(m.data) for _, m, _ in bag.read_messages([NS + '/camera/front/image_raw'])}
                assert len(frames) > 10
                img = next(bag.read_messages([NS + '/camera/front/image_raw']))[1]
                assert (img.width, img.height) == (160, 120)
