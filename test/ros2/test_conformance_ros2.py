"""The emulator on ROS 2, recorded live as the real naoqi_driver2 was (tools/real-driver2/record2.py:
the publishers' type and offered QoS from the graph, the CDR bytes as published), against every
healthy golden recording of test/fixtures/real-driver2/ (manifest.json), field by field with
test/helpers/ros2_facts.py: topic names, types, frames, each type's layout (image encodings and
sizes, laser slots, covariances, joint names, sonar geometry, diagnostics' status names, the
audio's frequency, channel map and size, each camera's calibration on camera_info) and the QoS
(reliability, durability, depth). Every
difference kept is in KNOWN with its reason, written out in docs/drivers.md ("The emulator on
ROS 2 against naoqi_driver2"). Run by the ROS 2 tier (tools/ros2/tests.sh); the same recordings
against the emulator's declared streams in every run: test/emulator/test_conformance2.py."""
import json
import os
import subprocess
import sys

import pytest

from pepper_interface_tests.emulator import camera_info
from ros2_facts import differences, healthy_recordings, recording_facts
from ros2_runs import domain_env, program
from rosmaster import kill_group, spawn, wait_until

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..')
GOLDEN2 = os.path.join(ROOT, 'test', 'fixtures', 'real-driver2')
RECORD2 = os.path.join(ROOT, 'tools', 'real-driver2', 'record2.py')
with open(os.path.join(GOLDEN2, 'manifest.json')) as _f:
    MANIFEST = json.load(_f)
SECONDS = 3.0
# (topic, key): why the emulator keeps it different (docs/drivers.md)
KNOWN = {
    # data = channels x the samples NAOqi sent (drv2 src/event/audio.cpp:184-186): the fake's
    # 4096 in the recordings, the emulator's robot-stock default 8192 (~audio_buffer 4096: the same)
    ('/audio', 'facts'): 'NAOqi buffer size',
}


def known(topic, key):
    """A difference kept: KNOWN, or /robot_description, which the emulator does not publish (no
    check reads it; test/emulator/test_conformance2.py NOT_EMULATED)."""
    return (topic, key) in KNOWN or (topic, key) == ('/robot_description', 'topic')


def record_emulator(tmp, recording, topics):
    """The emulator (its head: the recording's) recorded by record2.py for SECONDS."""
    env = domain_env()
    head = ['--head', 'xtion'] if recording.endswith('xtion') else []
    log = tmp / 'emulator.log'
    with open(str(log), 'w') as out:
        emu = spawn(program('pepperEmulator') + ['--condition', 'still'] + head, env,
                    stdout=out, stderr=subprocess.STDOUT)
    try:
        wait_until(lambda: 'publishers up' in log.read_text(), 40, log.read_text)
        out = tmp / 'emulator2'
        p = subprocess.run([sys.executable, RECORD2, str(out), str(SECONDS)] + topics, env=env,
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=120)
        assert p.returncode == 0 and out.is_dir(), p.stdout[-3000:]
        return recording_facts(str(out)), p.stdout
    finally:
        kill_group(emu)


@pytest.mark.parametrize('recording', healthy_recordings(MANIFEST))
def test_the_emulator_recorded_on_ros2_is_naoqi_driver2_field_by_field(tmp_path, recording):
    real = recording_facts(os.path.join(GOLDEN2, recording))
    # the topics the driver had a publisher for (record2 recorded no other)
    topics = [t for t in MANIFEST['recordings'][recording]['topics'] if t in real]
    # each camera's camera_info too, recorded or not (the driver publishes one beside every image)
    infos = [camera_info.info_topic(t) for t in topics if t.endswith('/image_raw') and real[t]['count']]
    emu, log = record_emulator(tmp_path, recording, topics + [i for i in infos if i not in topics])
    found = differences(real, {t: f for t, f in emu.items() if t in real or t not in infos})
    unexplained = {k: v for k, v in found.items() if not known(*k)}
    assert not unexplained, '\n'.join('%s %s: %s' % (t, k, v) for (t, k), v in sorted(unexplained.items()))
    # what carried messages from the driver carried messages from the emulator (the touch
    # events carried none: nobody touched either robot)
    silent = [t for t in topics if real[t]['count'] and t in emu and not emu[t]['count']]
    assert not silent, (silent, log[-2000:])
    assert emu['/sonar/front']['qos'] == (('reliable', 'volatile', 1),)
    for info in infos:      # the driver's tables (test/emulator/test_camera_info.py), the image's frame
        image = real[info.replace('/camera_info', '/image_raw')]
        got = emu.get(info)
        assert got and got['count'] and got['frames'] == image['frames'], (info, got, log[-2000:])
        model, d, k, r, p = camera_info.calibration(info.split('/')[2], image['facts']['width'],
                                                    image['facts']['height'])
        assert got['facts'] == dict(width=image['facts']['width'], height=image['facts']['height'],
                                    distortion_model=model, D=tuple(d), K=tuple(k), R=tuple(r), P=tuple(p)), info
        assert got['qos'] == (('reliable', 'volatile', 10),)


def test_the_emulator_sends_a_camera_info_only_while_its_image_is_subscribed(tmp_path):
    """As naoqi_driver2 2.1.2 converts a camera (src/publishers/camera.hpp:57-64: the image topic's
    subscribers, not image_transport's camera publisher's): the golden `audio` recording's
    camera_info came with the images subscribed (record2.py's +TOPIC); a camera_info subscriber
    alone got none from the driver, and gets none from the emulator."""
    real = recording_facts(os.path.join(GOLDEN2, 'audio'))
    assert real['/camera/depth/camera_info']['count'] > 10, real['/camera/depth/camera_info']
    emu, log = record_emulator(tmp_path, 'audio', ['/camera/front/camera_info', '/camera/depth/camera_info',
                                                   '+/camera/depth/image_raw'])
    assert emu['/camera/depth/camera_info']['count'] > 10, (emu.get('/camera/depth/camera_info'), log[-2000:])
    assert emu['/camera/front/camera_info']['count'] == 0, (emu['/camera/front/camera_info'], log[-2000:])
    assert '/camera/depth/image_raw' not in emu
