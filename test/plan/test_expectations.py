"""Typed expectations (expectations.py) and the file edge cases of every input file (issue 9,
"Files and values"): wrong types, impossible values, unknown and duplicate keys, non-UTF-8 files
and a UTF-8 BOM. Real files in a temporary folder; the command-line cases run the real
sensorTest script against a real roscore and check it exits 2 before listening.

Before the typed loader: `min_brightness: dark` crashed mid-run, `rates:` was silently ignored,
a duplicate YAML key silently won, `rate: [-16, -4]` was accepted, a non-UTF-8 file gave a
traceback and a BOM gave `unknown key "\\ufeffplatform"`.
"""
import dataclasses
import os
import subprocess

import pytest

from pepper_interface_tests.plan import catalog, expectations
from pepper_interface_tests.plan.settings import Options, load_plan
from plan_files import Files, error_of, write
from rosmaster import script

ALL = [n for n, s in catalog.SENSORS.items() if not s.opt_in]   # opt-in rows (motion: --move) aside


@pytest.fixture
def files(tmp_path):
    return Files(tmp_path)



def expect_error(files, text):
    write(files.expectations, text)
    return error_of(files.options())


# ------------------------------------------------------------------ wrong types, impossible values

@pytest.mark.parametrize('sensor, key, value, words', [
    ('frontCamera', 'min_brightness', 'dark', "min_brightness is 'dark', not a number"),
    ('frontCamera', 'frozen_frames', 'five', "frozen_frames is 'five', not a whole number"),
    ('frontCamera', 'frozen_frames', '2', 'must be at least 3'),
    ('frontCamera', 'stereo', 'maybe', 'not true or false'),
    ('microphone', 'sample_rate', 'fast', "sample_rate is 'fast'"),
    ('microphone', 'silence_dbfs', 'quiet', "silence_dbfs is 'quiet'"),
    ('microphone', 'silence_dbfs', '10', 'must be at most 0'),
    ('speech', 'subscriber_wait', 'soon', "subscriber_wait is 'soon'"),
    ('depthCamera', 'video_range', 'far', "video_range is 'far', not a [min, max] pair"),
    ('depthCamera', 'video_range', '[5, 5]', 'minimum is not below the maximum'),
    ('laser', 'rate', '[1, .inf]', 'both ends must be finite'),
    ('laser', 'quick_messages', '.inf', 'quick_messages is inf, not a whole number'),
    ('laser', 'max_invalid_share', 'half', "max_invalid_share is 'half', not a number"),
    ('laser', 'max_invalid_share', '1.5', 'must be at most 1'),
    ('jointState', 'joints', '"HeadYaw"', "joints is 'HeadYaw', not a list of names"),
    ('laser', 'ranges', '"61"', "ranges is '61', not a whole number"),
    ('laser', 'rate', '[-16, -4]', 'values below 0 are impossible'),
    ('laser', 'rate', '[0, 0]', 'nothing can be inside it'),
    ('laser', 'min_messages', '-3', 'min_messages is -3, must be at least 0'),
    ('laser', 'max_delay', '.nan', 'max_delay is nan, not a finite number'),
    ('depthCamera', 'median_range', '[8, 0.3]', 'minimum is not below the maximum'),
    ('odometry', 'child_frame_id', '12', 'child_frame_id is 12, not a text'),
    ('imu', 'nominal', '0', 'must be above 0'),
])
def test_wrong_types_and_impossible_values_name_file_line_and_fix(files, sensor, key, value, words):
    e = expect_error(files, 'defaults:\n  min_messages: 3\nrobot:\n  %s:\n    max_future: 1.0\n    %s: %s\n'
                     % (sensor, key, value))
    assert (e.path, e.line) == (files.expectations, 6), str(e)
    assert 'robot.%s' % sensor in e.message and words in e.message, e.message
    assert e.fix.startswith('write e.g. "%s:' % key) or e.fix.startswith('write e.g. %s:' % key), e.fix


def test_wrong_type_in_defaults(files):
    e = expect_error(files, 'defaults:\n  min_messages: 3\n  max_delay: soon\n')
    assert (e.line, 'defaults: max_delay') == (3, e.message[:len('defaults: max_delay')])


@pytest.mark.parametrize('text, line, words, fix', [
    ('robot:\n  laser:\n    rates: [4, 16]\n', 3, 'robot.laser: unknown key "rates"', 'did you mean "rate"'),
    ('robot:\n  laser:\n    min_brightness: 5\n', 3, 'unknown key "min_brightness"', 'ranges'),
    ('defaults:\n  max_dealy: 5\n', 2, 'defaults: unknown key "max_dealy"', 'did you mean "max_delay"'),
    ('robt:\n  laser:\n    rate: [4, 16]\n', 1, 'top level: unknown key "robt"', 'did you mean "robot"'),
])
def test_unknown_keys_are_errors(files, text, line, words, fix):
    e = expect_error(files, text)
    assert e.line == line and words in e.message and fix in e.fix, str(e)


@pytest.mark.parametrize('text, line, first', [
    ('robot:\n  laser:\n    rate: [4, 16]\n    ranges: 61\n    rate: [1, 2]\n', 5, 3),
    ('defaults:\n  min_messages: 3\nrobot:\n  imu: {}\ndefaults:\n  min_messages: 1\n', 5, 1),
    ('robot:\n  laser:\n    ranges: 61\n  imu:\n    nominal: 10\n  laser:\n    ranges: 90\n', 6, 2),
])
def test_duplicate_yaml_keys_name_both_lines(files, text, line, first):
    e = expect_error(files, text)
    assert e.line == line and 'duplicate key' in e.message and 'line %d' % first in e.message, str(e)


def test_one_sensor_under_two_spellings(files):
    e = expect_error(files, 'robot:\n  laser:\n    ranges: 61\n  Laser:\n    ranges: 90\n')
    assert e.line == 4 and 'twice' in e.message and 'line 2' in e.message, str(e)


def test_a_yaml_merge_key_may_be_overridden(files):
    write(files.expectations, 'robot:\n  frontCamera: &cam\n    min_brightness: 4.0\n    frozen_frames: 6\n'
                              '  bottomCamera:\n    <<: *cam\n    frozen_frames: 7\n')
    plan = load_plan(files.options(sensors=('frontCamera', 'bottomCamera')))
    front, bottom = (s.expect for s in plan.sensors)
    assert (front.frozen_frames, bottom.frozen_frames, bottom.min_brightness) == (6, 7, 4.0)


# ------------------------------------------------------------------ the typed objects

def test_defaults_live_in_the_dataclasses_and_values_are_typed(files):
    write(files.expectations, 'robot:\n  laser:\n    rate: [4, 16]\n    ranges: 61.0\n'
                              '  frontCamera:\n    nominal: 10\n')
    plan = load_plan(files.options(sensors=('laser', 'frontCamera', 'stereoCamera', 'speech')))
    laser, front, stereo, speech = (s.expect for s in plan.sensors)
    assert type(laser) is expectations.LaserExpect and laser.rate == (4.0, 16.0)
    assert laser.ranges == 61 and type(laser.ranges) is int
    assert (laser.min_messages, laser.max_delay, laser.max_future, laser.quick_messages,
            laser.max_gap_factor) == (3, 5.0, 1.0, 10, 3.0)
    assert (front.min_brightness, front.frozen_frames, front.stereo) == (5.0, 5, False)
    assert stereo.stereo is True           # a side-by-side pair unless the file says otherwise
    assert speech.subscriber_wait == 3.0 and speech.text
    with pytest.raises(dataclasses.FrozenInstanceError):
        laser.ranges = 1


def test_variants_refuse_names_the_family_does_not_declare():
    laser = expectations.default_for('laser')
    assert laser.max_delay == 5.0 and laser.ranges is None      # dataclass default; None = not checked
    assert laser.but(ranges=90).ranges == 90 and laser.ranges is None
    with pytest.raises(TypeError):
        laser.but(min_brightness=5.0)                            # a camera key, not a laser one
    assert not hasattr(laser, 'get')                             # no .get(key, fallback) anywhere


def test_every_family_has_a_class_and_the_shipped_file_loads():
    assert set(expectations.FAMILIES) == {s.family for s in catalog.SENSORS.values()}
    for platform in ('robot', 'simulator'):
        plan = load_plan(Options(platform=platform, sensors=tuple(ALL)))
        for s in plan.sensors:
            assert isinstance(s.expect, expectations.family_of(s.name))


def test_the_other_platform_section_may_hold_keys_of_a_future_version(files):
    write(files.expectations, 'robot:\n  laser:\n    ranges: 61\nsimulator:\n  laser:\n    rates: 5\n')
    assert load_plan(files.options(sensors=('laser',))).sensors[0].expect.ranges == 61


# ------------------------------------------------------------------ encodings and duplicates in .ini/.dat

@pytest.mark.parametrize('which', ['config', 'input', 'topics', 'expectations'])
def test_a_utf8_bom_is_accepted_in_every_file(files, which):
    path = getattr(files, which)
    with open(path, 'rb') as f:
        content = f.read()
    write(path, b'\xef\xbb\xbf' + content)
    plan = load_plan(files.options())
    assert plan.platform == 'robot' and len(plan.sensors) == len(ALL)


@pytest.mark.parametrize('which', ['config', 'input', 'topics', 'expectations'])
def test_a_file_that_is_not_utf8_names_the_file_line_and_fix(files, which):
    path = getattr(files, which)
    with open(path, 'rb') as f:
        content = f.read()
    write(path, content + '# caf\xe9 latin-1 comment\n'.encode('latin-1'))
    e = error_of(files.options())
    lines = content.count(b'\n') + 1
    assert (e.path, e.line) == (path, lines) and 'not UTF-8' in e.message, str(e)
    assert 'iconv' in e.fix


def test_platform_twice_in_the_configuration_names_both_lines(files):
    write(files.config, 'platform robot\nrobotTopics topics.dat\n# later\nPlatform simulator\n')
    e = error_of(files.options())
    assert (e.path, e.line) == (files.config, 4) and 'twice' in e.message and 'line 1' in e.message


def test_a_sensor_twice_in_the_topics_file_names_both_lines(files):
    write(files.topics, ''.join('%s /t/%s\n' % (n, n) for n in ALL) + 'Laser /other/laser\n')
    e = error_of(files.options())
    assert (e.path, e.line) == (files.topics, len(ALL) + 1)
    assert 'twice' in e.message and 'line %d' % (ALL.index('laser') + 1) in e.message


# ------------------------------------------------------------------ usage errors, exit 2 before listening

def run_sensor_test(master, files, *args):
    cmd = script('sensorTest') + ['--config', files.config, '--input', files.input,
                                  '--expectations', files.expectations, '--topics-dir', files.dir,
                                  '--output-dir', os.path.join(files.dir, 'out'), '--duration', '1',
                                  '--no-show'] + list(args)
    return subprocess.run(cmd, env=master.env(), capture_output=True, text=True, timeout=60)


def test_bad_expectations_exit_2_before_listening(module_master, files):
    write(files.expectations, 'robot:\n  frontCamera:\n    min_brightness: dark\n')
    p = run_sensor_test(module_master, files, '--sensors', 'frontCamera')
    assert p.returncode == 2, p.stdout + p.stderr
    assert '%s:3:' % files.expectations in p.stderr and 'min_brightness' in p.stderr
    assert 'Traceback' not in p.stderr + p.stdout
    assert not os.path.exists(os.path.join(files.dir, 'out', 'sensorTestResults.json'))


def test_non_utf8_expectations_exit_2_without_traceback(module_master, files):
    write(files.expectations, 'robot:\n  laser:\n    frame_id: b\xe4se\n'.encode('latin-1'))
    p = run_sensor_test(module_master, files, '--sensors', 'laser')
    assert p.returncode == 2 and 'not UTF-8' in p.stderr and 'Traceback' not in p.stderr, p.stderr


@pytest.mark.parametrize('value', ['', ',', ' '])
def test_empty_sensors_option_is_a_usage_error(module_master, files, value):
    p = run_sensor_test(module_master, files, '--sensors', value)
    assert p.returncode == 2, p.stdout + p.stderr
    assert 'names no sensor' in p.stderr and 'passed' not in p.stdout


def test_zero_selected_sensors_is_a_usage_error(module_master, files):
    write(files.input, ''.join('%s false\n' % n for n in ALL))
    p = run_sensor_test(module_master, files)
    assert p.returncode == 2, p.stdout + p.stderr
    assert 'no sensor is selected' in p.stderr and files.input in p.stderr
    assert '0 passed' not in p.stdout
