"""pepperEmulator and recordTestBags against a real roscore, real rospy subscribers, real bags.

The emulator runs as a subprocess (scripts/pepperEmulator); what it publishes is received by
test/nodes/emu_listen.py (a real rospy node in its own process) and checked against the sensor facts
of docs (pepper-sensors.md): types, encodings, sizes, frame ids, rates within +-20 %, content
that changes, the 61-beam laser layout (built as laser.cpp builds it), unit quaternions; then
every fault, bad fault strings, /speech reaching the microphones, and the bags written by
recordTestBags.
"""
import json
import math
import os
import pathlib
import subprocess
import sys
import time

import numpy as np
import psutil
import pytest

from driver_views import driver_scan
from fake_pepper import BLIND, JOINTS, WHEELS
from pepper_interface_tests.emulator import scene
from rosmaster import NODES, kill_group, script, spawn, wait_until

HERE = NODES   # the node scripts' folder (test/nodes/)
LISTEN = [sys.executable, os.path.join(HERE, 'emu_listen.py')]
NS = '/naoqi_driver'
IR = NS + '/camera/ir/image_raw'

# topic -> (type, nominal Hz, frame_id, extra expectations): the reference facts, written out
# here independently of the emulator's own table (docs/drivers.md; robot = the CSSR4Africa fork
# of naoqi_driver with a stereo head, cameras asked at QVGA to keep the test cheap).
ROBOT = {
    NS + '/sonar/back': ('sensor_msgs/Range', 10, 'SonarBack_frame', dict(min=0.25, max=2.55)),
    # sonar.cpp: the raw distance, not clipped: the far wall ahead is ~4 m away
    NS + '/sonar/front': ('sensor_msgs/Range', 10, 'SonarFront_frame',
                          dict(min=0.25, max=2.55, raw_above=True)),
    NS + '/camera/front/image_raw': ('sensor_msgs/Image', 10, 'CameraTop_optical_frame',
                                     dict(encoding='rgb8', width=320, height=240)),
    NS + '/camera/bottom/image_raw': ('sensor_msgs/Image', 10, 'CameraBottom_optical_frame',
                                      dict(encoding='rgb8', width=320, height=240)),
    # stereo head: depth at stereo_resolution 9 = kQ720p
    NS + '/camera/depth/image_raw': ('sensor_msgs/Image', 10, 'CameraDepth_optical_frame',
                                     dict(encoding='16UC1', width=640, height=360)),
    NS + '/camera/stereo/image_raw': ('sensor_msgs/Image', 10, 'CameraDepth_optical_frame',
                                      dict(encoding='rgb8', width=640, height=180)),
    NS + '/laser': ('sensor_msgs/LaserScan', 10, 'base_footprint', dict(min=0.1, max=3.0)),
    NS + '/audio': ('pepper_interface_tests/AudioCustomMsg', 48000 / 4096.0, None, {}),
    '/joint_states': ('sensor_msgs/JointState', 50, '', dict(wheels_nan=True)),
    NS + '/odom': ('nav_msgs/Odometry', 15, 'odom', dict(child='base_link')),
    NS + '/imu/base': ('sensor_msgs/Imu', 10, 'base_footprint', {}),
    NS + '/imu/torso': ('sensor_msgs/Imu', 10, 'base_link', {}),
    '/camera/color/image_raw': ('sensor_msgs/Image', 15, None,
                                dict(encoding='rgb8', width=640, height=480)),
    '/camera/aligned_depth_to_color/image_raw': ('sensor_msgs/Image', 15, None,
                                                 dict(encoding='16UC1', width=640, height=480)),
}
# the awesomebytes Gazebo simulator; nominal rates are per simulated second
SIMULATOR = {
    '/pepper/sonar_back': ('sensor_msgs/Range', 20, 'SonarBack_frame',
                           dict(min=0.0, max=5.0, fov=1.05)),
    '/pepper/sonar_front': ('sensor_msgs/Range', 20, 'SonarFront_frame',
                            dict(min=0.0, max=5.0, fov=1.05)),
    '/pepper/camera/front/image_raw': ('sensor_msgs/Image', 5, 'CameraTop_optical_frame',
                                       dict(encoding='rgb8', width=640, height=480)),
    '/pepper/camera/bottom/image_raw': ('sensor_msgs/Image', 5, 'CameraBottom_optical_frame',
                                        dict(encoding='rgb8', width=640, height=480)),
    # gazebo_ros_openni_kinect with useDepth16UC1Format, update_rate 30
    '/pepper/camera/depth/image_raw': ('sensor_msgs/Image', 30, 'CameraDepth_optical_frame',
                                       dict(encoding='16UC1', width=320, height=240)),
    '/pepper/laser_2': ('sensor_msgs/LaserScan', 6.25, 'base_footprint', dict(min=0.1, max=7.0)),
    '/joint_states': ('sensor_msgs/JointState', 50, '', {}),
    '/pepper/odom': ('nav_msgs/Odometry', 20, 'odom', dict(child='base_footprint')),
}
AUDIO_BUFFER_MD5 = '50f300aa63f3c1b2f3d3173329165316'    # naoqi_bridge_msgs/AudioBuffer


# ---------------------------------------------------------------- helpers

def unique_name():
    """A node name of its own for each emulator run: `_param:=value` arguments become private
    params on the (shared) master and would otherwise be inherited by the next run."""
    return 'pepperEmulator_%d' % time.time_ns()


class Emulator:
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


def check_stream(topic, got, expected, tolerance=0.2, rtf=None):
    """Type, rate (+-tolerance), frame id, header and per-type facts of one topic. With rtf
    (sim time) the nominal rate holds per simulated second: rtf x nominal per wall second, and
    the nominal rate between header stamps."""
    type_name, hz, frame, extra = expected
    nominal = hz
    if rtf is not None:
        stamp_rate = got.get('stamp_rate', hz) if got else hz
        if got and not (1 - tolerance) * hz <= stamp_rate <= (1 + tolerance) * hz:
            return ['%s: %.2f Hz between stamps (sim time), expected %.2f' % (topic, stamp_rate, hz)]
        hz = hz * rtf
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
    # stamped on the receiver's clock: the freshest message within 1 s of its receipt (the
    # largest delay is the listener's backlog on a loaded machine: 1.31 s once at load 15, a
    # 640x480 stream of a Python listener)
    if rtf is None and 'stamp_delay_least' in got and got['stamp_delay_least'] > 1.0:
        problems.append('%s: header stamps at least %.2f s away from receive time'
                        % (topic, got['stamp_delay_least']))
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
    if type_name == 'sensor_msgs/LaserScan' and got['n'] == 488:
        # laser_publisher.py: 61 x 8 slots over +-120 deg, increment span / 488, mostly NaN,
        # the 45 points of three Gazebo lasers (fewer when two share a slot)
        if abs(got['angle_min'] + 2.0944) > 1e-3 or abs(got['angle_max'] - 2.0944) > 1e-3 or \
                abs(got['angle_increment'] - 4.18879 / 488) > 1e-5:
            problems.append('%s: angles %s..%s step %s' % (
                topic, got['angle_min'], got['angle_max'], got['angle_increment']))
        if not all(488 - 45 <= n < 488 - 30 for n in got['nan']) or max(got['blind']):
            problems.append('%s: NaN slots %s (expected 443..457, no -1)' % (topic, got['nan'][:5]))
        if abs(got['range_min'] - 0.1) > 1e-6 or abs(got['range_max'] - 7.0) > 1e-6:
            problems.append('%s: range limits %s..%s' % (topic, got['range_min'], got['range_max']))
        if min(got['valid_min']) < 0.3 or max(got['valid_max']) > 7.1:
            problems.append('%s: returns outside Gazebo 0.3..7 m' % topic)
    elif type_name == 'sensor_msgs/LaserScan':
        if got['n'] != 61 or any(idx != BLIND for idx in got['blind_idx']):
            problems.append('%s: %s ranges, blind beams %s' % (topic, got['n'], got['blind_idx'][0]))
        # laser.cpp:216-218: increment = 240 deg / 61 (so angle_min + 61 x increment = angle_max)
        if abs(got['angle_min'] + 2.0944) > 1e-3 or abs(got['angle_max'] - 2.0944) > 1e-3 or \
                abs(got['angle_increment'] - 2 * 2.0944 / 61) > 1e-6:
            problems.append('%s: angles %s..%s step %s' % (
                topic, got['angle_min'], got['angle_max'], got['angle_increment']))
        if abs(got['range_min'] - extra['min']) > 1e-6 or abs(got['range_max'] - extra['max']) > 1e-6:
            problems.append('%s: range limits %s..%s' % (topic, got['range_min'], got['range_max']))
        if max(got['nan']):
            problems.append('%s: NaN beams' % topic)
        # raw distances: walls beyond the advertised 3.0 m are published as they are
        if max(got['valid_max']) <= extra['max'] or min(got['valid_min']) < 0.3:
            problems.append('%s: distances %.2f..%.2f m, expected raw values beyond %.1f m' % (
                topic, min(got['valid_min']), max(got['valid_max']), extra['max']))
        if len(set(got['digest'])) < 0.9 * len(got['digest']):
            problems.append('%s: scans do not change' % topic)
    if type_name == 'sensor_msgs/Range':
        values = got['range']
        if got['radiation_type'] != 0 or abs(got['field_of_view'] - extra.get('fov', 0.5236)) > 1e-3 or \
                abs(got['min_range'] - extra['min']) > 1e-6 or abs(got['max_range'] - extra['max']) > 1e-6:
            problems.append('%s: Range fields %s' % (topic, {k: got[k] for k in (
                'radiation_type', 'field_of_view', 'min_range', 'max_range')}))
        top = 6.0 if extra['max'] < 3 else extra['max']     # naoqi_driver: raw, unclipped
        if None in values or min(values) < extra['min'] or max(values) > top:
            problems.append('%s: ranges outside %s..%s' % (topic, extra['min'], top))
        elif extra.get('raw_above') and max(values) <= extra['max']:
            problems.append('%s: never above the advertised %.2f m (clipped?)' % (topic, extra['max']))
        elif len(set(values)) < 3:
            problems.append('%s: range does not vary' % topic)
    if type_name in ('sensor_msgs/Imu', 'nav_msgs/Odometry'):
        if any(abs(q - 1.0) > 1e-6 for q in got['qnorm']):
            problems.append('%s: quaternion not unit (%s..%s)' % (topic, min(got['qnorm']), max(got['qnorm'])))
    if type_name == 'sensor_msgs/Imu':
        if any(a is None or abs(a - 9.81) > 0.3 for a in got['acc_z']):
            problems.append('%s: linear_acceleration.z is not gravity' % topic)
        if got['covariance0'] != [-1.0, -1.0, -1.0]:       # imu.cpp:123-126
            problems.append('%s: covariance[0] %s, expected -1 x 3' % (topic, got['covariance0']))
    if type_name == 'nav_msgs/Odometry':
        if 'child' in extra and got['child_frame_id'] != extra['child']:
            problems.append('%s: child_frame_id %s' % (topic, got['child_frame_id']))
        xs, ys = got['x'], got['y']
        if None in xs or max(xs) - min(xs) < 0.01:
            problems.append('%s: the robot does not move' % topic)
        # twist consistent with the pose: distance travelled ~ vx * time
        dt = (len(xs) - 1) / nominal           # in the stream's own (maybe simulated) seconds
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
        nan = WHEELS if extra.get('wheels_nan') else []
        if got['vel_nan'] != nan or got['eff_nan'] != nan:
            problems.append('%s: NaN velocity %s / effort %s, expected the wheels' % (
                topic, got['vel_nan'], got['eff_nan']))
    if type_name.endswith('AudioCustomMsg'):
        lengths = [got['len_' + c] for c in ('rearLeft', 'rearRight', 'frontLeft', 'frontRight')]
        if lengths != [4096] * 4:
            problems.append('%s: samples per channel %s' % (topic, lengths))
        if min(min(r[1:]) for r in got['rms']) < 10:
            problems.append('%s: a silent channel' % topic)
    return problems


# ---------------------------------------------------------------- the laser's geometry

def _device_point(t, device, ray):
    """One ray of one laser device, cast from the device's own mounting point: (x, y) in the
    device's frame, written out here from the world's pose and LASERS."""
    x, y, yaw = scene.robot_pose(t)
    sensor_yaw, ox, oy = scene.LASERS[device]
    wx = x + math.cos(yaw) * ox - math.sin(yaw) * oy
    wy = y + math.sin(yaw) * ox + math.cos(yaw) * oy
    r = float(scene.raycast(wx, wy, [yaw + sensor_yaw + ray], t)[0])
    return r * math.cos(ray), r * math.sin(ray)


@pytest.mark.parametrize('t', [0.0, 7.3, 31.0])
def test_robot_laser_is_built_as_laser_cpp_builds_it(t):
    """naoqi_driver src/converters/laser.cpp:165-205 transcribed: ALMemory's 90 values (per
    device Seg01..Seg15 X, Y, left to right), read back as result_value[28-i], [58-i], [88-i],
    each point rotated and shifted into base_footprint, 8 blind slots (-1.0) between."""
    rays_left_to_right = scene.LASER_RAYS[::-1]
    memory = [v for dev in range(3) for ray in rays_left_to_right for v in _device_point(t, dev, ray)]
    expected = driver_scan(memory)
    blind = [i in BLIND for i in range(61)]
    got = scene.laser_ranges(t, blind, 0.0, np.random.default_rng(0))
    assert np.allclose(got, expected, atol=1e-4), np.round(got - np.asarray(expected), 3)


def test_simulator_laser_miss_is_no_point(monkeypatch):
    """A ray that hits nothing within the Gazebo laser's range gives a NaN point (angle and
    distance), which laser_publisher.py:464-477 skips: never an infinite one, whose atan2
    would be a real angle and fill a slot."""
    monkeypatch.setattr(scene, 'GAZEBO_LASER_MAX', 2.5)      # the room's walls now lie beyond
    dist, angle = scene.gazebo_laser_points(0.0, 0.0, np.random.default_rng(0))
    far = np.array([math.hypot(*_device_point(0.0, dev, ray)) + 0.01 > 2.5     # Gazebo's mean 0.01
                    for dev in range(3) for ray in scene.LASER_RAYS])
    assert 5 < far.sum() < 45 and not np.isinf(dist).any()
    assert np.array_equal(np.isnan(angle), far) and np.array_equal(np.isnan(dist), far)


# ---------------------------------------------------------------- profiles

def test_robot_profile_all_topics(module_master, tmp_path):
    """Every robot topic (audio direct, RealSense on): types, sizes, frames, rates, content; CPU."""
    with Emulator(module_master, tmp_path, '_audio:=direct', '_realsense:=true',
                  '_camera_resolution:=QVGA') as emu:
        proc = psutil.Process(emu.proc.pid)
        cpu0, t0 = proc.cpu_times(), time.time()
        got = listen(module_master, list(ROBOT), 8.0)
        cpu1, t1 = proc.cpu_times(), time.time()
        log = emu.output()
    cpu = (cpu1.user + cpu1.system - cpu0.user - cpu0.system) / (t1 - t0)
    print('emulator CPU with every robot topic subscribed: %.0f%% of one core' % (100 * cpu))
    # /diagnostics too (emulator/events.py); no touch topics: the CSSR fork's boot_config.json
    assert 'all 15 publishers up (16 topics, robot profile' in log     # the tree's /tf too
    problems = [p for topic, exp in ROBOT.items() for p in check_stream(topic, got.get(topic), exp)]
    assert not problems, '\n'.join(problems)
    assert got[NS + '/odom']['publishers'] == ['/' + emu.name]
    assert cpu < 1.0, 'the emulator needs %.0f%% of a core' % (100 * cpu)


def test_simulator_profile(module_master, tmp_path):
    """The simulator's topics and characteristics on sim time at real-time factor 0.5 (rates
    per simulated second, /clock advancing at half the wall clock); none of the robot-only
    topics; /use_sim_time set while it runs and removed when it stops."""
    import rosgraph
    robot_only = [NS + '/camera/front/image_raw', NS + '/imu/base', NS + '/audio',
                  NS + '/camera/stereo/image_raw', '/camera/color/image_raw', '/speech']
    rtf = 0.5
    param = rosgraph.Master('/test', master_uri=module_master.env()['ROS_MASTER_URI'])
    with Emulator(module_master, tmp_path, '_profile:=simulator', '_audio:=direct',
                  '_realsense:=true', '_real_time_factor:=%g' % rtf) as emu:
        got = listen(module_master, list(SIMULATOR) + ['/clock'], 8.0,
                     *[a for t in robot_only for a in ('--absent', t)])
        assert param.getParam('/use_sim_time') is True
        assert 'sim time at real-time factor 0.5' in emu.output()
    assert not param.hasParam('/use_sim_time'), 'the emulator leaves the master as it found it'
    problems = [p for topic, exp in SIMULATOR.items()
                for p in check_stream(topic, got.get(topic), exp, rtf=rtf)]
    assert not problems, '\n'.join(problems)
    clock = got['/clock']['clock']
    (w0, c0), (w1, c1) = clock[0], clock[-1]
    assert abs((c1 - c0) / (w1 - w0) - rtf) < 0.05, 'sim time runs at the real-time factor'
    # 100 Hz of wall time (emulator/publishers.py), within the +-20 % every stream of this file
    # is held to (check_stream): a loaded machine measured 87.9 Hz over the 8 s
    assert 80 <= got['/clock']['rate'] <= 120, got['/clock']['rate']
    # header stamps are sim time (the /clock), not the wall clock
    odom = got['/pepper/odom']
    assert odom['stamp_delay'] > 1e8 and c1 < 60
    for topic in robot_only:        # the master may remember types of earlier runs' topics
        assert got[topic].get('count', 0) == 0 and got[topic]['publishers'] == [], topic
    assert not [n for n in got['/speech']['subscribers'] if 'pepperEmulator' in n]


def test_rate_factor_and_resolution(module_master, tmp_path):
    with Emulator(module_master, tmp_path, '_rate_factor:=0.5', '_camera_resolution:=QQVGA'):
        topics = [NS + '/camera/front/image_raw', NS + '/camera/depth/image_raw', '/joint_states']
        got = listen(module_master, topics, 5.0)
    front = got[NS + '/camera/front/image_raw']
    depth = got[NS + '/camera/depth/image_raw']
    # the depth camera keeps its own boot_config resolution (stereo head: 640x360)
    assert (front['width'], front['height'], depth['width'], depth['height']) == (160, 120, 640, 360)
    assert 4.0 <= front['rate'] <= 6.0 and 20.0 <= got['/joint_states']['rate'] <= 30.0


def test_robot_stock_profile_and_heads(master, tmp_path):
    """robot-stock: naoqi_bridge_msgs/AudioBuffer (same md5 as the real package), 48 kHz,
    channelMap [3, 5, 0, 2], 8192 interleaved frames per message (~170 ms, ~5.9 Hz), QVGA
    cameras; xtion head: QVGA Xtion depth and no stereo topic; the robot profile's default
    cameras are the CSSR fork's VGA."""
    audio = NS + '/audio'
    with Emulator(master, tmp_path, '_profile:=robot-stock', '_head:=xtion') as emu:
        got = listen(master, [audio, NS + '/camera/front/image_raw',
                                     NS + '/camera/depth/image_raw', NS + '/laser', IR], 5.0,
                     '--absent', NS + '/camera/stereo/image_raw')
        log = emu.output()
    assert 'robot-stock profile, head xtion, audio direct' in log
    a = got[audio]
    assert a['type'] == 'naoqi_bridge_msgs/AudioBuffer' and a['md5'] == AUDIO_BUFFER_MD5
    assert (a['frequency'], a['channel_map'], a['data_len']) == (48000, [3, 5, 0, 2], 4 * 8192)
    assert abs(a['rate'] - 48000 / 8192.0) <= 0.2 * 48000 / 8192.0, a['rate']   # check_stream's +-20 %
    # interleaved: each channel keeps its own tone level (a planar reading would mix them)
    assert all(min(r[1:]) > 100 for r in a['rms'])
    front, depth = got[NS + '/camera/front/image_raw'], got[NS + '/camera/depth/image_raw']
    assert (front['width'], front['height'], depth['width'], depth['height']) == (320, 240, 320, 240)
    assert got[NS + '/camera/stereo/image_raw']['publishers'] == []
    ir = got[IR]        # the Xtion's infrared camera: 16UC1 in the depth's frame (camera.cpp:215-224)
    assert (ir['encoding'], ir['width'], ir['height'], ir['frames']) == \
        ('16UC1', 320, 240, ['CameraDepth_optical_frame']), ir
    assert not check_stream(NS + '/laser', got[NS + '/laser'], ROBOT[NS + '/laser'])
    with Emulator(master, tmp_path, '_audio:=off'):
        got = listen(master, [NS + '/camera/front/image_raw'], 2.0)
    front = got[NS + '/camera/front/image_raw']
    assert (front['width'], front['height']) == (640, 480)


def test_xtion_head_skips_the_stereo_camera_live(master, tmp_path):
    """A healthy Pepper 1.7 (Xtion head) does not fail for having no stereo camera: the IR
    topic the driver publishes on that head shows it, and stereoCamera is SKIPPED with that
    reason (before: FAIL "no publisher")."""
    with Emulator(master, tmp_path, '_profile:=robot-stock', '_head:=xtion', '_audio:=off'):
        out = tmp_path / 'out'
        p = subprocess.run(script('sensorTest') + [
            '--platform', 'robot', '--sensors', 'stereoCamera,depthCamera', '--duration', '2',
            '--wait', '3', '--mode', 'parallel', '--output-dir', str(out), '--no-show',
            '--no-history', '--no-diagnostics', '--no-report'],
            env=master.env(), capture_output=True, text=True, timeout=90)
    with open(str(out / 'sensorTestResults.json')) as f:
        got = {s['name']: s for s in json.load(f)['sensors']}
    assert p.returncode == 0, p.stdout + p.stderr
    stereo = got['stereoCamera']
    assert stereo['verdict'] == 'SKIPPED', stereo
    assert 'Xtion head' in stereo['reasons'][0] and IR in stereo['reasons'][0], stereo['reasons']
    assert got['depthCamera']['verdict'] == 'PASS', got['depthCamera']['reasons']


def test_healthy_but_unusual_conditions(module_master, tmp_path):
    """loaded: cameras ~1.3 fps with irregular gaps; dark: dim colour images; still: the robot
    stands still (odometry constant, twist 0) while the world moves."""
    topics = [NS + '/camera/front/image_raw', NS + '/laser']
    with Emulator(module_master, tmp_path, '_audio:=off', '_condition:=loaded',
                  '_camera_resolution:=QQVGA'):
        got = listen(module_master, topics, 8.0)
    front = got[NS + '/camera/front/image_raw']
    assert 0.8 <= front['rate'] <= 2.0 and 7 <= got[NS + '/laser']['rate'] <= 12
    with Emulator(module_master, tmp_path, '_audio:=off', '_condition:=dark',
                  '_camera_resolution:=QQVGA'):
        got = listen(module_master, topics, 3.0)
    assert 0 < max(got[NS + '/camera/front/image_raw']['max']) <= 40
    with Emulator(module_master, tmp_path, '_audio:=off', '_condition:=still'):
        got = listen(module_master, [NS + '/odom', NS + '/laser', NS + '/imu/base'], 3.0)
    odom = got[NS + '/odom']
    assert set(odom['x']) == {0.0} and set(odom['vx']) == {0.0} and set(odom['wz']) == {0.0}
    assert max(abs(g) for g in got[NS + '/imu/base']['gyro_z']) < 0.02
    assert len(set(got[NS + '/laser']['digest'])) > 5, 'noise and the walking person still move'


# ---------------------------------------------------------------- faults

BATCH_1 = ('frontCamera:frozen;bottomCamera:black;depthCamera:wrong_encoding;'
           'stereoCamera:wrong_step;laser:nan;frontSonar:out_of_range;backSonar:silent;'
           'imu:broken_quaternion;odometry:rate=0.3;jointState:die_after=8;'
           'microphone:silent_channel=rearRight;realsenseRGBCamera:wrong_type;'
           'realsenseDepthCamera:wrong_encoding')
BATCH_2 = ('LASER:out_of_range;frontsonar:nan;backSonar:rate=2;imu:nan;odometry:nan,broken_quaternion;'
           'jointState:nan,out_of_range;microphone:silent;frontCamera:wrong_encoding;'
           'bottomCamera:wrong_step;depthCamera:black;stereoCamera:die_after=8.5;'
           'realsenseDepthCamera:frozen;realsenseRGBCamera:black')


def _faults_batch_1(got, start):
    front = got[NS + '/camera/front/image_raw']
    assert len(set(front['digest'])) == 1 and front['count'] > 20, 'frozen: same bytes every frame'
    assert 8 <= front['rate'] <= 12, 'frozen camera keeps its rate'
    bottom = got[NS + '/camera/bottom/image_raw']
    assert max(bottom['max']) == 0 and bottom['count'] > 20, 'black: all-zero image'
    depth = got[NS + '/camera/depth/image_raw']
    assert depth['encoding'] == '32FC1' and depth['step'] == 640 * 2, 'wrong_encoding on depth'
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
    assert joints['count'] > 20 and joints['last_time'] - start < 8.5, 'die_after=8 stops it'
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
    # die_after=8.5: a stream is only published while it has a subscriber
    assert stereo['count'] > 5 and stereo['last_time'] - start < 9.0 and stereo['publishers'] == []
    rs_depth = got['/camera/aligned_depth_to_color/image_raw']
    assert len(set(rs_depth['digest'])) == 1 and rs_depth['count'] > 20
    assert max(got['/camera/color/image_raw']['max']) == 0


@pytest.mark.parametrize('faults,check', [(BATCH_1, _faults_batch_1), (BATCH_2, _faults_batch_2)],
                         ids=['batch1', 'batch2'])
def test_faults(module_master, tmp_path, faults, check):
    """Every fault type, on every sensor family it applies to, shows in what is received."""
    topics = [t for t in ROBOT]
    with Emulator(module_master, tmp_path, '_audio:=direct', '_realsense:=true',
                  '_camera_resolution:=QVGA', '_faults:=' + faults) as emu:
        # listen from the moment the emulator is up, so die_after can be timed: the dying
        # streams live 8 s, long enough for the listener (a new process: 5 s and more to connect
        # at load 15; with 3 s, it once connected after the joint states had died) and ended
        # before the 10 s window is
        wait_until(lambda: 'publishers up' in emu.output(), 30, emu.output)
        start = time.time()
        got = listen(module_master, topics, 10.0)
        log = emu.output()
    assert 'faults: ' in log and 'die_after' in log
    check(got, start)


def test_real_fault_classes(master, tmp_path):
    """The issue's fault classes as a real driver would show them: NaN attitude with covariance
    -1, a dead microphone inside an AudioBuffer (frontLeft = channelMap code 0, third column),
    an all-blind laser, a NaN sonar; and the simulator laser with no returns."""
    audio = NS + '/audio'
    faults = 'imu:nan_attitude;microphone:silent_channel=frontLeft;laser:all_blind;frontSonar:nan'
    with Emulator(master, tmp_path, '_profile:=robot-stock', '_faults:=' + faults):
        got = listen(master, [audio, NS + '/imu/base', NS + '/laser', NS + '/sonar/front'], 3.0)
    imu = got[NS + '/imu/base']
    assert all(imu['q_nan']) and imu['covariance0'] == [-1.0, -1.0, -1.0] and imu['count'] > 10
    a = got[audio]
    assert a['channel_map'] == [3, 5, 0, 2]
    assert all(r[3] == 0 and min(r[1], r[2], r[4]) > 100 for r in a['rms']), 'only frontLeft dead'
    laser = got[NS + '/laser']
    assert laser['n'] == 61 and all(b == 61 for b in laser['blind']), 'every slot -1.0'
    assert all(r is None for r in got[NS + '/sonar/front']['range']) and \
        got[NS + '/sonar/front']['count'] > 10
    with Emulator(master, tmp_path, '_profile:=simulator', '_real_time_factor:=1',
                  '_faults:=laser:no_returns'):
        got = listen(master, ['/pepper/laser_2'], 3.0)
    laser = got['/pepper/laser_2']
    assert laser['count'] > 5 and all(n == 488 for n in laser['nan']), 'no returns: all NaN'


@pytest.mark.parametrize('params,words', [
    (['_faults:=laser:melted'], ['unknown fault "melted"', 'nan', 'out_of_range', 'silent']),
    (['_faults:=tailCamera:frozen'], ['unknown sensor "tailCamera"', 'frontCamera', 'laser', 'imu']),
    (['_faults:=laser:broken_quaternion'], ['does not apply to laser', 'nan']),
    (['_faults:=microphone:silent_channel=rearRight'], ['~audio direct', 'silent-channel']),
    (['_profile:=simulator', '_faults:=imu:nan'], ['"imu" is not published', 'simulator']),
    (['_profile:=android'], ['android', 'robot, robot-stock, simulator']),
    (['_profile:=robot-stock', '_audio:=bridge'], ['second publisher', '~audio direct']),
    (['_profile:=simulator', '_real_time_factor:=-1'], ['real_time_factor', 'not a positive']),
    (['_faults:=imu:all_blind'], ['does not apply to imu', 'nan_attitude']),
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
        time.sleep(1.0)    # time for a second "not reachable", which must not come
        log = emu.output()
    assert log.count('not reachable') == 1, log
    assert url in log
    assert got[NS + '/laser']['count'] > 15 and got2[NS + '/laser']['count'] > 15


# ---------------------------------------------------------------- recordTestBags

def test_record_test_bags(recorded_bags):
    """recordTestBags writes small, complete bags (own roscore) that rosbag opens, from every
    profile: robot (stereo and Xtion heads), robot-stock (AudioBuffer), simulator (sim time at
    real-time factor 0.5, /clock recorded), good and with the real fault classes."""
    import rosbag
    out_dir = pathlib.Path(os.path.dirname(recorded_bags['robot_good']))
    names = sorted(os.listdir(out_dir))
    assert not [n for n in names if n.endswith('.active')], names
    stock = dict(ROBOT)
    stock[NS + '/audio'] = ('naoqi_bridge_msgs/AudioBuffer', 48000 / 8192.0, None, {})
    xtion = dict(ROBOT, **{IR: ('sensor_msgs/Image', 10, None, {})})
    sim = dict(SIMULATOR, **{'/clock': ('rosgraph_msgs/Clock', 100 / 0.5, None, {})})
    expected = {
        'robot_good.bag': (set(ROBOT), ROBOT),
        'robot_faulty.bag': (set(ROBOT) - {NS + '/sonar/back'}, ROBOT),   # silent: never published
        # an Xtion head: no stereo topic, the infrared camera instead (naoqi_driver.cpp:733-762)
        'robot_xtion_good.bag': (set(ROBOT) - {NS + '/camera/stereo/image_raw'} | {IR}, xtion),
        'robot_stock_good.bag': (set(stock), stock),
        'robot_stock_faulty.bag': (set(stock), stock),
        'simulator_good.bag': (set(sim), sim),
        'simulator_no_returns.bag': (set(sim), sim),
    }
    # every variant's tree: /tf with each joint state, /tf_static latched (the RealSense's frames;
    # the simulator's fixed joints), emulator/tf_publisher.py
    tree = {'/tf': ('tf2_msgs/TFMessage', 10, None, {}), '/tf_static': ('tf2_msgs/TFMessage', 0, None, {})}
    expected = {name: (topics | set(tree), dict(table, **tree)) for name, (topics, table) in expected.items()}
    for name, (topics, table) in expected.items():
        assert name in names, names
        path = out_dir / name
        size = path.stat().st_size
        # small: 7-8 MB of cameras, laser and audio over a few seconds, plus the tree's /tf (84
        # transforms with each joint state, about 1 MB): 10 MB
        assert size < 10e6, '%s is %.1f MB' % (name, size / 1e6)
        with rosbag.Bag(str(path)) as bag:
            info = bag.get_type_and_topic_info().topics
            assert set(info) == topics, '%s: %s' % (name, sorted(set(info) ^ topics))
            # bag time: wall seconds for the robot, simulated seconds (half as many) for Gazebo
            seconds = bag.get_end_time() - bag.get_start_time()
            for topic in topics:
                exp = table[topic]
                assert info[topic].msg_type == exp[0]
                assert info[topic].message_count >= 0.6 * exp[1] * seconds, \
                    (name, topic, info[topic].message_count, seconds)
            assert '/speech' not in info and '/rosout' not in info
            if name.startswith('simulator'):
                assert 1.5 <= seconds <= 4.5, 'sim time at rtf 0.5: %.1f s' % seconds
                scans = [m for _, m, _ in bag.read_messages(['/pepper/laser_2'])]
                assert scans[0].header.stamp.to_sec() < 60, 'stamps in sim time'
                returns = [sum(1 for r in m.ranges if not math.isnan(r)) for m in scans]
                if name == 'simulator_no_returns.bag':
                    assert max(returns) == 0
                else:
                    assert min(returns) >= 30 and len(scans[0].ranges) == 488
            if name == 'robot_faulty.bag':
                frames = {bytes(m.data) for _, m, _ in bag.read_messages([NS + '/camera/front/image_raw'])}
                assert len(frames) == 1, 'frontCamera:frozen recorded'
                scan = next(bag.read_messages([NS + '/laser']))[1]
                assert any(math.isnan(r) for r in scan.ranges)
            if name == 'robot_stock_faulty.bag':
                imu = next(bag.read_messages([NS + '/imu/base']))[1]
                assert math.isnan(imu.orientation.w) and imu.orientation_covariance[0] == -1
                scan = next(bag.read_messages([NS + '/laser']))[1]
                assert set(scan.ranges) == {-1.0}
                buf = next(bag.read_messages([NS + '/audio']))[1]
                assert list(bytearray(buf.channelMap)) == [3, 5, 0, 2]
                assert set(buf.data[2::4]) == {0} and len(set(buf.data[0::4])) > 100
            if name == 'robot_good.bag':
                frames = {bytes(m.data) for _, m, _ in bag.read_messages([NS + '/camera/front/image_raw'])}
                assert len(frames) > 10
                img = next(bag.read_messages([NS + '/camera/front/image_raw']))[1]
                assert (img.width, img.height) == (160, 120)
                scan = next(bag.read_messages([NS + '/laser']))[1]
                assert max(scan.ranges) > scan.range_max, 'raw laser distances recorded'
