"""Copied and near-identical microphone channels (sensors/channels.py; issue 24, point 8): real
AudioCustomMsg and AudioBuffer messages, serialized as they come off the wire, fed through the
microphone's SensorRun.

The margin (similar_channels_ratio 0.8) is measured here on the emulator's audio
(emulator/audio_source.py: a tone per channel plus noise, and spoken text) and on robot-shaped
recordings: one sound (speech rendered by espeak-ng, or its beeps; a 100 Hz hum) heard at four
places on a head with their arrival delays (an approximate geometry of Pepper's four
microphones: front and rear pairs 10 cm apart, 7 cm from front to rear), +-0.5 dB gain
tolerances and each microphone's own noise; and a quiet room (independent noise only).
"""
import numpy as np
import pytest

from driver_feed import ROBOT, feed, run_of
from fake_pepper import stock_audio_buffer
from pepper_interface_tests.audio_bridge import frame as wire_frame
from pepper_interface_tests.audio_bridge import layout
from pepper_interface_tests.audio_bridge.publisher import to_message
from pepper_interface_tests.emulator.audio_source import AudioSource, render_speech
from pepper_interface_tests.msg import AudioCustomMsg
from pepper_interface_tests.results import FAIL, PASS
from pepper_interface_tests.sensors.channels import ChannelSimilarity
from pepper_interface_tests.sources.naoqi_msgs import AUDIO_BUFFER_DEFINITION

RATE, N = 48000, 4096
NB = 34                 # 4096-sample buffers in 2.9 s (11.72 Hz) of a 3 s window
NAMES = ('rearLeft', 'rearRight', 'frontLeft', 'frontRight')
MICS = np.array([[-0.035, 0.05], [-0.035, -0.05], [0.035, 0.05], [0.035, -0.05]])   # m, approximate
AUDIO_BUFFER = 'naoqi_bridge_msgs/AudioBuffer'
AUDIO_CONN = {'type': AUDIO_BUFFER, 'message_definition': AUDIO_BUFFER_DEFINITION, 'callerid': '/naoqi_driver'}


def msg(block):
    return AudioCustomMsg(**{name: block[:, i].tolist() for i, name in enumerate(NAMES)})


def judged(blocks, tmp_path):
    run = run_of('microphone', tmp_path, ROBOT)
    return feed(run, [msg(b) for b in blocks], rate=RATE / float(N))


def tones(n=NB, speech=None):
    src = AudioSource(pattern='tones', seed=3)
    if speech:
        src.say(speech)
        while src.speaking and not src._speech:     # rendered in a thread: wait until queued
            import time
            time.sleep(0.05)
    return [src.read(N) for _ in range(n)]


def planar_as_interleaved(block):
    """A planar NAOqi buffer (rearLeft's n samples, then rearRight's ...) read as interleaved:
    what the emulator's fault planar_as_interleaved publishes (emulator/publishers.py)."""
    return np.ascontiguousarray(block.T).reshape(-1, 4)


def heard(sound, direction_deg, noise_dbfs=-60.0, gains_db=(0.0, 0.5, -0.5, 0.3), level=0.3, seed=1):
    """A robot-shaped recording: `sound` (float, peak 1) arriving from `direction_deg` at each
    microphone at its own time, with its gain and its own noise, in 4096-sample buffers."""
    rng = np.random.default_rng(seed)
    u = np.array([np.cos(np.radians(direction_deg)), np.sin(np.radians(direction_deg))])
    delays = -(MICS @ u) / 343.0 * RATE
    delays -= delays.min()
    t = np.arange(len(sound), dtype=float)
    out = np.stack([np.interp(t - d, t, sound) * 10 ** (g / 20.0) * level * 32767
                    for d, g in zip(delays, gains_db)], axis=1)
    out += rng.standard_normal(out.shape) * 32767 * 10 ** (noise_dbfs / 20.0)
    b = np.clip(np.rint(out), -32768, 32767).astype(np.int16)
    return [b[k:k + N] for k in range(0, len(b) - N + 1, N)][:NB]


def largest_ratio(blocks):
    sim = ChannelSimilarity(NAMES, -70.0)
    for b in blocks:
        w = b.astype(np.int64)
        sim.add(b, np.einsum('ij,ij->j', w, w).astype(float))
    return max(v for v in sim.ratios().values() if v is not None)


def copy_and_similar(r):
    return [x for x in r.reasons + r.warnings if 'sample for sample' in x or 'nearly identical' in x]


# ------------------------------------------------------------------ copied: FAIL, naming whose

def test_four_channels_carrying_one_microphone_fail_naming_the_copies(tmp_path):
    r = judged([np.repeat(b[:, :1], 4, axis=1) for b in tones()], tmp_path)
    assert r.verdict == FAIL
    hits = [x for x in r.reasons if 'sample for sample' in x]
    assert hits == ['rearRight, frontLeft and frontRight carry rearLeft\'s samples, sample for '
                    'sample, in all %d buffers with sound: one microphone copied into the others, '
                    'which were never measured (a bridge or driver filling several channels from '
                    'one buffer)' % NB], r.reasons
    assert r.values.channel_step_ratios['rearLeft-frontRight'] == 0
    assert not [x for x in r.warnings if 'nearly identical' in x]     # the failure says it


def test_two_copied_pairs_are_named_pair_by_pair(tmp_path):
    r = judged([b[:, [0, 0, 2, 2]] for b in tones()], tmp_path)
    assert r.verdict == FAIL
    assert [x.split(':')[0] for x in r.reasons if 'sample for sample' in x] == [
        'rearRight carries rearLeft\'s samples, sample for sample, in all %d buffers with sound' % NB,
        'frontRight carries frontLeft\'s samples, sample for sample, in all %d buffers with sound' % NB]


def test_a_copy_in_part_of_the_window_is_not_a_copy(tmp_path):
    """The rule is 'identical in every buffer with sound': one real buffer clears the pair."""
    blocks = tones()
    r = judged([np.repeat(b[:, :1], 4, axis=1) if k else b for k, b in enumerate(blocks)], tmp_path)
    assert not [x for x in r.reasons if 'sample for sample' in x], r.reasons


# ------------------------------------------------------------------ dealt out: WARN, naming the cause

@pytest.mark.parametrize('speech', [None, pytest.param('Hello, I am Pepper. One two three.',
                                                      marks=pytest.mark.integration)])   # espeak-ng
def test_planar_buffers_read_as_interleaved_warn_naming_the_cause(tmp_path, speech):
    r = judged([planar_as_interleaved(b) for b in tones(speech=speech)], tmp_path)
    assert r.verdict == PASS, r.reasons          # a warning, not a failure
    hits = [x for x in r.warnings if x.startswith('the four channels are nearly identical')]
    assert len(hits) == 1 and 'as when planar NAOqi buffers are read as interleaved' in hits[0], r.warnings
    assert '(similar_channels_ratio 0.8;' in hits[0]
    assert max(r.values.channel_step_ratios.values()) < 0.8


def test_dealt_out_samples_stay_below_the_margin():
    """Smooth sound gives (3/4)^2 = 0.56 for the widest step, noise low-passed to a few kHz
    3/4: both below 0.8."""
    assert 0.5 < largest_ratio([planar_as_interleaved(b) for b in tones()]) < 0.6
    rng = np.random.default_rng(5)
    box = np.ones(20) / 20      # noise low-passed by a 20-sample moving average
    low = [np.clip(np.rint(np.stack([np.convolve(rng.standard_normal(N + 19), box, 'valid')
                                     for _ in range(4)], axis=1) * 600), -32768, 32767).astype(np.int16)
           for _ in range(NB)]
    assert 0.7 < largest_ratio([planar_as_interleaved(b) for b in low]) < 0.8


# ------------------------------------------------------------------ healthy: no false alarm

@pytest.mark.integration     # espeak-ng renders the speech (a real process)
def test_the_emulators_healthy_audio_passes_far_above_the_margin(tmp_path):
    for blocks in (tones(), tones(speech='Hello, I am Pepper. Please touch my head.')):
        r = judged(blocks, tmp_path)
        assert r.verdict == PASS and not r.warnings, (r.reasons, r.warnings)
        assert min(r.values.channel_step_ratios.values()) > 30     # measured 33-297


@pytest.mark.integration     # espeak-ng renders the speech (a real process)
@pytest.mark.parametrize('direction', [0, 45, 90, 180])
def test_robot_shaped_speech_from_every_side_passes(tmp_path, direction):
    sound = render_speech('Hello, I am Pepper. Please touch my head. One two three four five.', RATE)
    sound = np.resize(sound, NB * N)
    r = judged(heard(sound, direction), tmp_path)
    assert r.verdict == PASS and not copy_and_similar(r), (r.reasons, r.warnings)
    assert max(r.values.channel_step_ratios.values()) > 10     # one pair may be low, not all six


def test_a_hum_from_straight_ahead_with_matched_gains_passes():
    """The hardest real case: a 100 Hz hum reaching the front and the rear pairs at once with
    perfectly matched gains and little noise; the front-to-rear delay keeps the largest pair
    far above the margin."""
    hum = np.sin(2 * np.pi * 100 * np.arange(NB * N) / RATE)
    assert largest_ratio(heard(hum, 0, noise_dbfs=-70, gains_db=(0, 0, 0, 0))) > 10


def test_a_dark_quiet_room_passes(tmp_path):
    """Four microphones hearing only their own noise (-62 dBFS, above silence_dbfs -70): every
    pair about 1 (independent noise), above the margin."""
    rng = np.random.default_rng(9)
    quiet = [np.rint(rng.standard_normal((N, 4)) * 26).astype(np.int16) for _ in range(NB)]
    r = judged(quiet, tmp_path)
    assert r.verdict == PASS and not r.warnings, (r.reasons, r.warnings)
    assert 0.95 < min(r.values.channel_step_ratios.values()) < 1.05


def test_digital_silence_is_no_copy_the_silence_rule_speaks(tmp_path):
    """Four all-zero channels are equal by being zero: not judged as copies (no buffer with
    sound); the silent-channel rule fails them, once each."""
    r = judged([np.zeros((N, 4), np.int16) for _ in range(NB)], tmp_path)
    assert r.verdict == FAIL and not copy_and_similar(r), r.reasons
    assert sorted(x for x in r.reasons if 'all samples are zero' in x) == sorted(
        'microphone %s is silent: all samples are zero' % n for n in NAMES)
    assert set(r.values.channel_step_ratios.values()) == {None}


# ------------------------------------------------------------------ the transports cannot make copies

@pytest.mark.parametrize('planar', [True, False])
def test_the_bridges_frame_format_keeps_four_microphones_apart(tmp_path, planar):
    """audio_bridge/frame.py in either declared layout, decoded by the bridge's publisher
    (to_message), gives the four microphones back as they were: no copy, no warning."""
    msgs = []
    for k, b in enumerate(tones()):
        payload = (np.ascontiguousarray(b.T) if planar else b).astype('<i2').tobytes()
        assert layout.suspect(planar, payload, 4) is None
        f = wire_frame.decode_frame(wire_frame.encode_frame(payload, 4, N, RATE, k, planar=planar))
        msgs.append(to_message(f, AudioCustomMsg))
    r = feed(run_of('microphone', tmp_path, ROBOT), msgs, rate=RATE / float(N))
    assert r.verdict == PASS and not r.warnings, (r.reasons, r.warnings)


def test_the_bridge_refuses_a_planar_buffer_declared_interleaved():
    """What would deal one microphone over four channels is caught at the bridge
    (audio_bridge/layout.py): the frame is refused, never published."""
    b = tones(1)[0]
    assert 'looks planar' in layout.suspect(False, np.ascontiguousarray(b.T).astype('<i2').tobytes(), 4)


@pytest.mark.parametrize('cmap', [(3, 5, 0, 2), (0, 2, 5, 3)])
def test_stock_naoqi_driver_interleaved_audio_buffers_pass(tmp_path, cmap):
    """Stock naoqi_driver's AudioBuffer (event/audio.cpp:170-180: the interleaved NAOqi buffer,
    columns named by channelMap) de-interleaved by the check: four microphones, no copy."""
    run = run_of('microphone', tmp_path, ROBOT)
    r = feed(run, [stock_audio_buffer(i, cmap=cmap) for i in range(17)], rate=48000 / 8192.0,
             type_name=AUDIO_BUFFER, conn=AUDIO_CONN)
    assert r.verdict == PASS and not r.warnings, (r.reasons, r.warnings)
    assert min(r.values.channel_step_ratios.values()) > 1
