"""The emulator on ROS 2 against the real naoqi_driver2 (issue 44), on every healthy golden
recording the manifest of test/fixtures/real-driver2/ lists (read with rosbags: no ROS 2
install): what the emulator publishes on ROS 2 for the recording's head (the robot-stock
profile on data/naoqi_driver2Topics.dat, as node2.py starts it) has the driver's topic names,
types, frames, image encodings and sizes, rates (the fake's, boot_config.json), the QoS each
publisher offered (reliability, durability, depth: emulator/qos2.py), the /diagnostics array
status by status, the /tf tree pair by pair, and each camera's camera_info where a recording
holds it (emulator/camera_info.py), and the microphone's AudioBuffer layout and channel map on
`audio` (the fake's --audio-relay: /audio, the stereo head's camera_info streams,
/robot_description). The emulator's own live ROS 2 recording is held
to the same recordings field by field in the ROS 2 tier (test/ros2/test_conformance_ros2.py).
Every difference kept is in docs/drivers.md ("The emulator on ROS 2 against naoqi_driver2")."""
import functools
import json
import os

import pytest

from driver_tree_compare import compare_trees
from pepper_interface_tests.emulator import camera_info, events, qos2
from pepper_interface_tests.emulator.info import INFO_TOPIC_ROS2
from pepper_interface_tests.emulator.profiles import build_profile
from pepper_interface_tests.plan import declaration, settings
from ros2_facts import healthy_recordings, messages, offered_qos, recording_facts

HERE = os.path.dirname(os.path.abspath(__file__))
GOLDEN2 = os.path.join(os.path.dirname(HERE), 'fixtures', 'real-driver2')
with open(os.path.join(GOLDEN2, 'manifest.json')) as _f:
    MANIFEST = json.load(_f)
HEALTHY = healthy_recordings(MANIFEST)
# the healthy ones and `audio` (the fake's --audio-relay: /audio, each camera's camera_info alone,
# /robot_description), compared topic by topic (its topics are the stereo head's, standing still)
COMPARED = HEALTHY + [r for r in ('audio',) if r in MANIFEST['recordings']]
# the ones that hold the microphone (`audio`: recorded with the fake's --audio-relay)
WITH_AUDIO = [r for r in COMPARED if '/audio' in MANIFEST['recordings'][r]['topics']]
TOPICS2 = os.path.join(settings.package_dir(), 'data', 'naoqi_driver2Topics.dat')
# integration, not unit: every message of each recording is decompressed and decoded (about a
# second of CPU per recording), which the unit tier's budget is not for (docs/testing.md)
pytestmark = pytest.mark.integration
# published by naoqi_driver2 and not by the emulator, with the reason (docs/drivers.md); no
# check of this package reads it
NOT_EMULATED = {
    '/robot_description': 'the URDF text, transient-local (drv2 src/tools/robot_description.cpp:64-76)',
}
BATTERY = 87        # the fake NAOqi's charge (fake_memory.py), as in the ROS 1 golden recordings


def path_of(recording):
    return os.path.join(GOLDEN2, recording)


@functools.lru_cache(maxsize=None)
def facts_of(recording):
    return recording_facts(path_of(recording))


def head_of(recording):
    """The head a healthy recording shows: the one whose head-only topic carried messages."""
    facts = facts_of(recording)
    carried = ''.join(t for t, f in facts.items() if f['count'])
    shown = [h for h, head in declaration.HEADS.items() if head.sign_part in carried]
    assert len(shown) == 1, (recording, shown)
    return shown[0]


def emulator_specs(head):
    """{topic: SensorSpec} the emulator publishes on ROS 2 for `head` (node2.py's defaults), a
    camera's camera_info under its image's spec (camera_info.py: where the driver has a table)."""
    profile = build_profile('robot-stock', TOPICS2, realsense=False, audio='direct', head=head)
    specs = {t: s for s in profile.sensors for t in [s.topic] + [e[0] for e in s.extra]}
    specs.update({camera_info.info_topic(s.topic): s for s in profile.sensors
                  if s.is_image and camera_info.calibration(s.view, s.width, s.height)})
    return specs


def is_info(topic):
    return topic.endswith('/camera_info')


def test_every_healthy_recording_is_compared():
    assert 'healthy_stereo' in HEALTHY, sorted(MANIFEST['recordings'])
    assert 'audio' in COMPARED and WITH_AUDIO == ['audio'], sorted(MANIFEST['recordings'])


def test_the_audio_recording_holds_the_audio_and_every_camera_info():
    """What the audio and camera_info comparisons below need: /audio and a camera_info of each
    of the stereo head's cameras carried messages, the URDF once (transient-local)."""
    carried = {t: f['count'] for t, f in facts_of('audio').items()}
    infos = [camera_info.info_topic(t) for t in ('/camera/front/image_raw', '/camera/bottom/image_raw',
                                                  '/camera/depth/image_raw', '/camera/stereo/image_raw')]
    assert all(carried.get(t) for t in ['/audio'] + infos), carried
    assert carried.get('/robot_description') == 1, carried


@pytest.mark.parametrize('recording', COMPARED)
def test_the_emulator_on_ros2_publishes_what_naoqi_driver2_does(recording):
    """Topic by topic: the driver's type, frame, image encoding and size, rate; a topic the
    driver offered with no publisher (the other head's camera) the emulator does not publish."""
    real = facts_of(recording)
    specs = emulator_specs(head_of(recording))
    problems = []
    for topic in MANIFEST['recordings'][recording]['topics']:
        spec, r = specs.get(topic), real.get(topic)
        if topic in NOT_EMULATED:
            continue
        if topic == INFO_TOPIC_ROS2:    # published once at start (info.py): seen only by an early subscriber
            if r is None or r['type'] != 'naoqi_bridge_msgs/StringStamped':
                problems.append('%s: %s, emulator naoqi_bridge_msgs/StringStamped' % (topic, r and r['type']))
            continue
        if r is None:
            if spec is not None:
                problems.append('%s: the emulator publishes it, naoqi_driver2 had no publisher' % topic)
            continue
        if spec is None:
            problems.append('%s: naoqi_driver2 publishes it, the emulator does not' % topic)
            continue
        msg_type = 'sensor_msgs/CameraInfo' if is_info(topic) else spec.msg_type
        if r['type'] != msg_type:
            problems.append('%s: type %s, emulator %s' % (topic, r['type'], msg_type))
        if not r['count']:
            continue        # the touch events: published on a touch only (nobody touched)
        if is_info(topic):      # the calibration, number for number (also test_camera_info.py)
            model, d, k, r_, p = camera_info.calibration(spec.view, spec.width, spec.height)
            want = dict(width=spec.width, height=spec.height, distortion_model=model, D=tuple(d), K=tuple(k),
                        R=tuple(r_), P=tuple(p))
            if r['facts'] != want:
                problems.append('%s: %s, emulator %s' % (topic, r['facts'], want))
        frame = dict(spec.extra).get(topic, spec.frame_id)
        if spec.family != 'tf' and r['frames'] != {frame}:     # /tf: the tree, below
            problems.append('%s: frames %s, emulator %r' % (topic, r['frames'], frame))
        if spec.is_image and not is_info(topic):
            got = (r['facts']['encoding'], r['facts']['width'], r['facts']['height'])
            if got != (spec.encoding, spec.width, spec.height):
                problems.append('%s: %s, emulator %s' % (topic, got, (spec.encoding, spec.width, spec.height)))
        # the driver's rate against the emulator's nominal: both boot_config.json's; +-20 % for
        # a driver recorded on a loaded machine (the ROS 1 golden recordings' tolerance)
        # the audio's rate is its buffer size's: test_the_emulator_audio_matches_naoqi_driver2
        if spec.family not in ('touch', 'health', 'audio') and not 0.8 * spec.rate <= r['rate'] <= 1.2 * spec.rate:
            problems.append('%s: %.1f Hz, emulator nominal %.1f Hz' % (topic, r['rate'], spec.rate))
    assert not problems, '\n'.join(problems)


@pytest.mark.parametrize('recording', COMPARED)
def test_the_emulator_on_ros2_offers_naoqi_driver2s_qos(recording):
    """Each publisher's offered QoS in the recording (metadata.yaml, from the graph) against the
    one the emulator gives that stream on ROS 2: reliable, volatile, qos2's depth."""
    specs = emulator_specs(head_of(recording))
    offered = offered_qos(path_of(recording))
    assert offered, 'no offered QoS in %s/metadata.yaml' % recording
    wrong = {}
    for topic, profiles in offered.items():
        if topic in specs or topic == INFO_TOPIC_ROS2:
            # a camera_info: its image's (image_transport's camera publisher)
            depth = qos2.depth(specs[topic].family) if topic in specs else qos2.INFO_DEPTH
            want = (('reliable', 'volatile', depth),)
            if profiles != want:
                wrong[topic] = (profiles, want)
    assert not wrong, wrong
    if recording == 'audio':    # the microphone and the camera_info (their images' 10), the URDF latched
        assert offered['/audio'] == offered['/camera/front/camera_info'] == (('reliable', 'volatile', 10),)
        assert offered['/robot_description'] == (('reliable', 'transient_local', 1),)   # NOT_EMULATED
        return
    # the ones read from the source and shown by the driver: cameras 10, sonars 1, /tf 100
    assert offered['/camera/front/image_raw'] == (('reliable', 'volatile', 10),)
    assert offered['/sonar/front'] == (('reliable', 'volatile', 1),)
    assert offered['/tf'] == (('reliable', 'volatile', 100),)


def _status_facts(array):
    return {s.name: (s.hardware_id, int(s.level), s.message, [(v.key, v.value) for v in s.values])
            for s in array.status}


@pytest.mark.parametrize('recording', HEALTHY)
def test_the_emulator_diagnostics_match_naoqi_driver2(recording):
    """naoqi_driver2's DiagnosticArray against the emulator's (events.driver_array) built from
    the fake's world: name, hardware id, level, message, keys and values, status by status."""
    real = [m for _, m, _ in messages(path_of(recording), {'/diagnostics'})]
    assert real, 'no /diagnostics in %s' % recording
    msg = real[-1]
    temps = {s.name.split(':')[1]: float(dict((v.key, v.value) for v in s.values)['Temperature'])
             for s in msg.status
             if s.name.startswith('naoqi_driver_joints:') and s.name != 'naoqi_driver_joints:Status'}
    assert list(temps) == list(events.JOINTS)           # getBodyNames' order, as on ROS 1
    assert _status_facts(msg) == _status_facts(events.driver_array(temps, BATTERY, charging=False))


@pytest.mark.parametrize('recording', HEALTHY + [r for r in ('move',) if r in MANIFEST['recordings']])
def test_the_emulator_tree_is_naoqi_driver2s_tf(recording):
    """Every /tf message of naoqi_driver2 against the emulator's tree (urdf_tree.driver_tree at
    the joint state of the same stamp, and odom -> base_link): the same 84 parent-child pairs,
    one stamp, every transform the same to 1e-5 (q and -q: the same rotation); in `move` the
    head turns, so the moving joints are compared away from zero too."""
    states, trees = {}, []
    for topic, m, _ in messages(path_of(recording), {'/joint_states', '/tf'}):
        if topic == '/joint_states':
            states[(m.header.stamp.sec, m.header.stamp.nanosec)] = dict(zip(m.name, m.position))
        else:
            trees.append(m)
    assert len(trees) > 50, len(trees)
    compared, head_yaws = compare_trees(trees, states, lambda x: (x.header.stamp.sec, x.header.stamp.nanosec))
    assert compared > 50, compared
    if recording == 'move':
        assert max(abs(y) for y in head_yaws) >= 0.4, head_yaws


@pytest.mark.parametrize('recording', WITH_AUDIO)
def test_the_emulator_audio_matches_naoqi_driver2(recording):
    """naoqi_driver2's AudioBuffer where a recording holds /audio (`audio`, the fake's --audio-relay):
    type, frame id "", 48000 Hz, channel map [3, 5, 0, 2], data = 4 x the samples NAOqi sent, the
    rate the fake's buffers give; the emulator publishes that layout (docs/drivers.md)."""
    real = facts_of(recording)['/audio']
    assert real['count'] > 10, real
    from pepper_interface_tests.emulator.naoqi_endpoint import BUFFER_SAMPLES
    profile = build_profile('robot-stock', TOPICS2, audio='direct', head=head_of(recording),
                            audio_buffer=BUFFER_SAMPLES)      # ~audio_buffer 4096: the fake's buffers
    spec = [s for s in profile.sensors if s.topic == '/audio'][0]
    assert (real['type'], real['frames']) == (spec.msg_type, {spec.frame_id})
    from pepper_interface_tests.emulator.profiles import AUDIO_RATE
    from pepper_interface_tests.sources.naoqi_msgs import PEPPER_CHANNEL_MAP  # the emulator's
    assert (real['facts']['frequency'], real['facts']['channel_map']) == (AUDIO_RATE, tuple(PEPPER_CHANNEL_MAP)) \
        == (48000, (3, 5, 0, 2))
    assert real['facts']['data_len'] == 4 * BUFFER_SAMPLES == 4 * spec.width
    assert 0.8 * spec.rate <= real['rate'] <= 1.2 * spec.rate, (real['rate'], spec.rate)
