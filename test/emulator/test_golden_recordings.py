"""The golden recordings of the real ros-naoqi/naoqi_driver (test/fixtures/real-driver/, made by
tools/real-driver/record-golden.sh against the fake NAOqi): sensorTest's verdicts on each are
the expected ones, and the emulator's own streams match the real driver's, topic by topic
(names, types, md5, frame ids, encodings and sizes, array lengths and special values, rates as
configured). Every difference the emulator keeps is in KNOWN_DIFFERENCES with its reason,
written out in docs/drivers.md ("What the real driver published")."""
import json
import os
import subprocess

import pytest

from bag_facts import bag_facts
from driver_tree_compare import compare_trees
from pepper_interface_tests.emulator.profiles import build_profile
from pepper_interface_tests.plan import declaration, settings
from rosmaster import script

HERE = os.path.dirname(os.path.abspath(__file__))
GOLDEN = os.path.join(os.path.dirname(HERE), 'fixtures', 'real-driver')
with open(os.path.join(GOLDEN, 'manifest.json')) as _f:
    MANIFEST = json.load(_f)
BAGS = sorted(MANIFEST['bags'])
NS = '/naoqi_driver'
TOPICS = settings.read_topics(os.path.join(settings.package_dir(), 'data', 'pepperTopics.dat'))
SENSOR_OF = {topic: name for name, topic in TOPICS.items()}

# bag -> {sensor: (verdict, words in its first reason)}; any other sensor PASSES, except the
# touch sensors nobody touched (SKIPPED "not touched": unattended, from a bag).
EXPECTED = {
    'healthy_stereo': {},
    'healthy_xtion': {},
    # getImageRemote answers nothing: the driver publishes nothing (camera.cpp:274-281)
    'camera_fails': {'frontCamera': ('FAIL', 'camera/front/image_raw is not in the bag')},
    # a missing ALMemory key: -1 (from_any_value.cpp:186-199), published as the range
    'missing_key': {'frontSonar': ('FAIL', 'range is negative in')},
    'stuck_laser': {'laser': ('FAIL', 'front board (slots 23-37) stuck')},
    'touch': {'headTouch': ('PASS', '')},
    'hot_joint': {'robotHealth': ('FAIL', 'too hot (the driver\'s ERROR, 74 °C and above): HeadYaw 75')},
    'low_battery': {'robotHealth': ('FAIL', 'battery almost empty: 20% left')},
    # NAOqi 2.9: the driver registers no audio (naoqi_driver.cpp:823)
    'naoqi29': {'microphone': ('FAIL', 'topic /naoqi_driver/audio is not in the bag')},
    # the driver's own microphone stream (tools/real-driver/relay/audio_relay.cpp feeds it)
    'audio': {},
    # the robot moves (tools/real-driver/move.py): every witness agrees with the recorded turn
    # (test/motion/test_recorded.py judges it further); the stereo pair is not recorded (size)
    'move': {'stereoCamera': ('FAIL', 'stereo/image_raw is not in the bag')},
}
TOUCH = declaration.sensors_of('touch')


def sensors_in(bag):
    """The package's sensors on the bag's recorded topics (as the manifest lists them)."""
    names = [SENSOR_OF[t] for t in MANIFEST['bags'][bag]['topics'] if t in SENSOR_OF]
    if 'stereoCamera' not in names and 'depthCamera' in names:
        names.append('stereoCamera')
    return names


def head_skips(bag, names):
    """{sensor: ('SKIPPED', words)} for the sensors of one head only (the declaration's heads)
    in a bag that shows another head: its camera/ir or camera/stereo topic (naoqi_driver.cpp:
    733-762). healthy_xtion: the stereo camera; healthy_stereo: the Xtion's."""
    recorded = set(bag_facts(os.path.join(GOLDEN, bag + '.bag')))
    shown = [h for h, head in declaration.HEADS.items() if head.sign_topic in recorded]
    if len(shown) != 1:
        return {}
    return {n: ('SKIPPED', 'this robot has ' + declaration.HEADS[shown[0]].title) for n in names
            if shown[0] not in declaration.SENSORS[n].heads}


def run_sensor_test(bag, names, out):
    cmd = script('sensorTest') + ['--bag', os.path.join(GOLDEN, bag + '.bag'), '--platform', 'robot',
                                  '--sensors', ','.join(names), '--output-dir', str(out),
                                  '--no-history', '--no-report']
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=120,
                       env=dict(os.environ, ROS_MASTER_URI='http://127.0.0.1:1'))
    with open(str(out / 'sensorTestResults.json')) as f:
        return p, {s['name']: s for s in json.load(f)['sensors']}


def test_manifest_names_what_was_built():
    assert set(MANIFEST['sources']) == {'libqi', 'libqicore', 'naoqi_bridge_msgs', 'naoqi_driver'}
    assert all(len(s['commit']) == 40 for s in MANIFEST['sources'].values())
    total = sum(os.path.getsize(os.path.join(GOLDEN, b + '.bag')) for b in BAGS)
    assert total < 20e6, 'golden recordings take %.1f MB' % (total / 1e6)


@pytest.mark.parametrize('bag', BAGS)
def test_sensor_test_verdicts_on_the_real_driver(bag, tmp_path):
    names = sensors_in(bag)
    p, got = run_sensor_test(bag, names, tmp_path)
    expected = dict(head_skips(bag, names), **EXPECTED[bag])
    for name in names:
        s = got[name]
        if name in expected:
            verdict, words = expected[name]
            assert s['verdict'] == verdict, (name, s['verdict'], s['reasons'])
            assert not words or words in s['reasons'][0], (name, s['reasons'])
        elif name in TOUCH:
            assert s['verdict'] == 'SKIPPED' and 'not touched' in s['reasons'][0], (name, s['reasons'])
        else:
            assert s['verdict'] == 'PASS', (name, s['reasons'], p.stdout[-2000:])
    if bag == 'audio':      # four microphones, not copies (sensors/channels.py): no warning
        assert got['microphone']['warnings'] == [], got['microphone']['warnings']
        assert got['microphone']['values']['buffer_sizes'] == {'4096': got['microphone']['messages']}


# ------------------------------------------------------------------ the emulator against the real driver

# (topic, fact) -> why the emulator's recording differs from the real driver's: docs/drivers.md
# ("What the real driver published"). Nothing else may differ.
KNOWN_DIFFERENCES = {
    # recordTestBags records the front and bottom cameras at QQVGA to keep the test bags small
    # (emulator/bags.py); the emulator's robot-stock profile publishes QVGA like the driver,
    # checked against the profile below
    (NS + '/camera/front/image_raw', 'facts'): 'test bags at QQVGA',
    (NS + '/camera/bottom/image_raw', 'facts'): 'test bags at QQVGA',
}


def emulator_profile(head, audio_buffer=None):
    return build_profile('robot-stock', realsense=False, audio='direct', head=head, audio_buffer=audio_buffer)


def spec_topics(profile):
    return {t: s for s in profile.sensors for t in [s.topic] + [e[0] for e in s.extra]}


@pytest.mark.parametrize('bag, head', [('healthy_stereo', 'stereo'), ('healthy_xtion', 'xtion')])
def test_the_emulator_profile_publishes_what_the_driver_does(bag, head):
    """Topics, frames, image encodings and sizes and rates of the emulator's robot-stock profile
    (no faults) against the real driver's healthy recording: the same, topic by topic."""
    real = bag_facts(os.path.join(GOLDEN, bag + '.bag'))
    specs = spec_topics(emulator_profile(head))
    recorded = set(MANIFEST['bags'][bag]['topics'])
    problems = []
    for topic in sorted(recorded):
        if topic not in specs:
            continue        # the touch events (none in a healthy recording), the microphone
        spec = specs[topic]
        if spec.family == 'touch':
            continue        # events: a bag holds a topic only once a message came (nobody touched)
        if topic not in real:
            problems.append('%s: the emulator publishes it, the real driver did not' % topic)
            continue
        r = real[topic]
        if r['type'] != spec.msg_type:
            problems.append('%s: type %s, emulator %s' % (topic, r['type'], spec.msg_type))
        frame = dict(spec.extra).get(topic, spec.frame_id)
        # /diagnostics mixes nodes; /tf has no header (its frames: test/sensors/test_tf.py)
        if spec.family not in ('health', 'tf') and r['frames'] != {frame}:
            problems.append('%s: frames %s, emulator %r' % (topic, r['frames'], frame))
        if spec.is_image:
            got = (r['facts']['encoding'], r['facts']['width'], r['facts']['height'])
            if got != (spec.encoding, spec.width, spec.height):
                problems.append('%s: %s, emulator %s' % (topic, got, (spec.encoding, spec.width, spec.height)))
        # rates as configured (boot_config.json): the driver's against the emulator's nominal
        if spec.family not in ('touch', 'health') and not 0.8 * spec.rate <= r['rate'] <= 1.2 * spec.rate:
            problems.append('%s: %.1f Hz, emulator nominal %.1f Hz' % (topic, r['rate'], spec.rate))
    for topic in sorted(set(real) - set(specs)):
        if topic != '/diagnostics':
            problems.append('%s: the real driver publishes it, the emulator does not' % topic)
    assert not problems, '\n'.join(problems)


def test_the_emulator_streams_match_the_real_driver(recorded_bags):
    """The emulator's own recording (robot_stock_good: stock driver, stereo head) against the
    real driver's: type, md5, frame ids and each type's layout facts (laser slots and -1 blind
    slots, covariance markers, joint names and NaN columns, sonar geometry, image encodings)."""
    real = bag_facts(os.path.join(GOLDEN, 'healthy_stereo.bag'))
    emu = bag_facts(recorded_bags['robot_stock_good'])
    differences = {}
    for topic, r in sorted(real.items()):
        if topic == '/diagnostics':
            continue        # not in the emulator's bags (bags.py EXCLUDED): next test
        e = emu.get(topic)
        if e is None:
            differences[(topic, 'topic')] = 'missing from the emulator'
            continue
        for key in ('type', 'md5', 'frames', 'facts'):
            if r[key] != e[key]:
                differences[(topic, key)] = '%r != emulator %r' % (r[key], e[key])
    unexplained = {k: v for k, v in differences.items() if k not in KNOWN_DIFFERENCES}
    assert not unexplained, '\n'.join('%s %s: %s' % (t, k, v) for (t, k), v in unexplained.items())


def _status_facts(array):
    return {s.name: (s.hardware_id, s.level, s.message, tuple(v.key for v in s.values)) for s in array.status}


@pytest.mark.parametrize('bag, percent, hot', [('healthy_stereo', 87, None), ('hot_joint', 87, 'HeadYaw'),
                                               ('low_battery', 20, None)])
def test_the_emulator_diagnostics_match_the_real_driver(bag, percent, hot):
    """The emulator's DiagnosticArray (events.driver_array) built from the fake's world (the
    same temperatures, battery and limits) equals what the real driver published, status by
    status: name, hardware id, level, message, keys and the values."""
    import rosbag

    from pepper_interface_tests.emulator import events, fake_memory
    with rosbag.Bag(os.path.join(GOLDEN, bag + '.bag')) as b:
        real = [m for _, m, _ in b.read_messages(['/diagnostics'])]
    assert real
    msg = real[-1]
    temps = {s.name.split(':')[1]: float(dict((v.key, v.value) for v in s.values)['Temperature'])
             for s in msg.status
             if s.name.startswith('naoqi_driver_joints:') and s.name != 'naoqi_driver_joints:Status'}
    assert list(temps) == list(events.JOINTS)           # the driver's order: getBodyNames
    if hot:
        assert temps[hot] == fake_memory.HOT
    emu = events.driver_array(temps, percent, charging=False)
    assert _status_facts(msg) == _status_facts(emu)
    real_values = {s.name: [(v.key, v.value) for v in s.values] for s in msg.status}
    emu_values = {s.name: [(v.key, v.value) for v in s.values] for s in emu.status}
    assert real_values == emu_values


# ------------------------------------------------------------------ the microphone

def _audio(path):
    import rosbag
    with rosbag.Bag(path) as b:
        return [(m, t.to_sec()) for _, m, t in b.read_messages([NS + '/audio'])]


def _tone_order(msg):
    """The emulator world's tone (emulator/audio_source.py CHANNEL_TONES_HZ) found in each
    column of an interleaved AudioBuffer, column by column."""
    import numpy as np
    x = np.asarray(msg.data, dtype=np.float64).reshape(-1, len(msg.channelMap))
    freqs = np.fft.rfftfreq(len(x), 1.0 / msg.frequency)
    return [float(freqs[np.abs(np.fft.rfft(x[:, c] - x[:, c].mean())).argmax()]) for c in range(x.shape[1])]


def test_the_emulator_audio_matches_the_real_driver(recorded_bags):
    """The emulator's robot-stock AudioBuffer stream (robot_stock_good) against the real
    driver's (audio.bag, fed by the fake's ALAudioDevice through audio_relay): type, md5, frame
    id, frequency, channelMap, interleaved data of channels x samples, stamps taken on arrival,
    the rate 48000 / samples per buffer, and the four microphones in Pepper's order."""
    from pepper_interface_tests.emulator.audio_source import CHANNEL_TONES_HZ
    from pepper_interface_tests.emulator.naoqi_endpoint import BUFFER_SAMPLES
    from pepper_interface_tests.emulator.profiles import AUDIO_RATE, STOCK_AUDIO_BUFFER
    topic = NS + '/audio'
    real = bag_facts(os.path.join(GOLDEN, 'audio.bag'))[topic]
    emu = bag_facts(recorded_bags['robot_stock_good'])[topic]
    for key in ('type', 'md5', 'frames'):
        assert real[key] == emu[key], (key, real[key], emu[key])
    assert real['type'] == 'naoqi_bridge_msgs/AudioBuffer' and real['frames'] == {''}
    for key in ('frequency', 'channel_map'):
        assert real['facts'][key] == emu['facts'][key], (key, real['facts'][key], emu['facts'][key])
    assert real['facts']['frequency'] == 48000 and real['facts']['channel_map'] == (3, 5, 0, 2)
    # data = nbOfChannels x samplesByChannel of the buffer NAOqi sent (src/event/audio.cpp:185):
    # 4 x the fake's 4096; the emulator's robot-stock default is 4 x 8192 (the issue's ~170 ms
    # buffers, unconfirmed): KNOWN difference, docs/drivers.md; with ~audio_buffer 4096 the same
    assert real['facts']['data_len'] == 4 * BUFFER_SAMPLES
    assert emu['facts']['data_len'] == 4 * STOCK_AUDIO_BUFFER
    four_k = [s for s in emulator_profile('stereo', audio_buffer=BUFFER_SAMPLES).sensors if s.topic == topic][0]
    assert 4 * four_k.width == real['facts']['data_len']
    # one message per buffer: 48000 / samples per channel, within the other topics' +-20 %
    for facts, samples in ((real, BUFFER_SAMPLES), (emu, STOCK_AUDIO_BUFFER)):
        nominal = AUDIO_RATE / float(samples)
        assert 0.8 * nominal <= facts['rate'] <= 1.2 * nominal, (facts['rate'], nominal)
    assert 0.8 * four_k.rate <= real['rate'] <= 1.2 * four_k.rate
    # stamps: ros::Time::now() on arrival (audio.cpp:178), NAOqi's own timestamp unused: within
    # a second of the recording's time and strictly increasing, on both
    tones = [CHANNEL_TONES_HZ[n] for n in ('rearLeft', 'rearRight', 'frontLeft', 'frontRight')]
    for name, path in (('driver', os.path.join(GOLDEN, 'audio.bag')), ('emulator', recorded_bags['robot_stock_good'])):
        msgs = _audio(path)
        stamps = [m.header.stamp.to_sec() for m, _ in msgs]
        assert all(b > a for a, b in zip(stamps, stamps[1:])), name
        assert all(abs(t - s) < 1.0 for s, (_, t) in zip(stamps, msgs)), name
        # interleaved, columns in the world's order: rearLeft, rearRight, frontLeft, frontRight,
        # which channelMap [3, 5, 0, 2] names (sensors/audio.py); the driver copies the buffer
        # as it came, no reordering, no copy of one channel into the others
        got = _tone_order(msgs[len(msgs) // 2][0])
        assert all(abs(g - w) < 20 for g, w in zip(got, tones)), (name, got, tones)


@pytest.mark.parametrize('bag', ['healthy_stereo', 'move'])
def test_the_emulator_tree_is_the_real_drivers_tf(bag):
    """The emulator's /tf (emulator/urdf_tree.py driver_tree at a joint state's positions, and
    odom -> base_link) against the /tf the real naoqi_driver published with that joint state
    (tools/real-driver/record-golden.sh): the same 84 parent-child pairs, one root, the same
    stamp as the joint state, and every transform the same to 1e-5 m and 1e-5 in each quaternion
    component (the URDF's numbers, printed by the driver as float64). In `move` the head and the
    base turn, so the moving joints are compared away from zero too."""
    import rosbag

    with rosbag.Bag(os.path.join(GOLDEN, bag + '.bag')) as b:
        states = {}
        trees = []
        for topic, m, _ in b.read_messages(topics=['/joint_states', '/tf']):
            if topic == '/joint_states':
                states[m.header.stamp.to_nsec()] = dict(zip(m.name, m.position))
            else:
                trees.append(m)
    assert len(trees) > 100, len(trees)
    compared, head_yaws = compare_trees(trees, states, lambda x: x.header.stamp.to_nsec())
    assert compared > 100, compared
    if bag == 'move':
        assert max(abs(y) for y in head_yaws) >= 0.4, head_yaws
