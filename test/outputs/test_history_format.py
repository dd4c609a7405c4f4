"""Unit: a run's JSON read back into typed results (sensorTestHistory, --rerun-failed).

test/fixtures/emulator-run-v1.json was written by sensorTest before the JSON named each sensor's
family (an emulator run of all 14 robot sensors, tools/demo.sh --duration 3): it must still read,
every sensor's values into its family's dataclass, and be written back with the same values.
"""
import copy
import dataclasses
import json
import math
import os

import pytest

from pepper_interface_tests import codec, results
from pepper_interface_tests.outputs.history import RunInfo, compare, read_back
from pepper_interface_tests.plan import catalog
from pepper_interface_tests.sensors import families
from pepper_interface_tests.sensors.values import Spread
from pepper_interface_tests.sensors.values.audio import AudioValues
from pepper_interface_tests.sensors.values.camera import CameraValues
from pepper_interface_tests.sensors.values.laser import BeamKind, LaserValues, LastScan
from pepper_interface_tests.stats import DelaySummary, StreamStats, StreamSummary

FIXTURE = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), 'fixtures', 'emulator-run-v1.json')


def old_run():
    with open(FIXTURE, encoding='utf-8') as f:
        return json.load(f)


def test_an_old_run_reads_into_each_familys_values():
    data = old_run()
    assert results.malformed(data) == ''
    run = read_back(data)
    assert [s.name for s in run.sensors] == [s['name'] for s in data['sensors']]
    for s in run.sensors:
        fam = catalog.SENSORS[s.name].family
        assert s.family == fam                          # named by the catalog: the old JSON has no family
        assert isinstance(s.values, families.values_of(fam)), (s.name, s.values)
        assert s.verdict in results.Verdict
    by = {s.name: s for s in run.sensors}
    assert isinstance(by['frontCamera'].values, CameraValues) and by['frontCamera'].values.width == 640
    assert by['frontCamera'].values.video.frames_written > 0
    assert isinstance(by['microphone'].values, AudioValues)
    assert set(by['microphone'].values.channels) == {'rearLeft', 'rearRight', 'frontLeft', 'frontRight'}
    assert all(isinstance(k, int) for k in by['microphone'].values.buffer_sizes)   # JSON keys are text
    assert isinstance(by['laser'].values.range_m, Spread)


def test_an_old_run_is_written_back_with_the_same_values():
    data = old_run()
    again = json.loads(json.dumps(read_back(data).to_dict()))    # as write_json writes it
    for old, new in zip(data['sensors'], again['sensors']):
        assert new['values'] == old['values'], old['name']
        assert new['family'] == catalog.SENSORS[old['name']].family
        for key in old:
            if key not in ('exit_code',):
                assert new[key] == old[key], (old['name'], key)


def test_history_compare_and_failed_read_typed_results():
    a = old_run()
    b = copy.deepcopy(a)
    b['sensors'][0]['verdict'] = 'FAIL'
    b['sensors'][0]['rate_hz'] = None
    rows = compare(RunInfo('a', '/a', a), RunInfo('b', '/b', b))
    row = rows[0]
    assert row['verdict_a'] == 'PASS' and row['verdict_b'] == 'FAIL' and row['verdict_changed']
    assert row['rate_flag'] is True
    assert results.not_passed(read_back(b)) == [b['sensors'][0]['name']]
    assert results.not_passed(results.read_run(b)) == [b['sensors'][0]['name']]   # without values


def test_values_that_do_not_fit_leave_the_verdict():
    data = old_run()
    data['sensors'][0]['values'] = {'range_m': 'not a spread'}
    run = read_back(data)
    assert run.sensors[0].values is None and run.sensors[0].verdict == data['sensors'][0]['verdict']


def test_codec_round_trip_enums_nan_and_nested():
    scan = LastScan(0.0, 0.1, [1.0, float('nan')], 0.1, 3.0, -1.0, [BeamKind.RETURN, BeamKind.NO_RETURN])
    v = LaserValues(beams=2, range_m=Spread(1.0, 1.0, 1.0), last_scan=scan)
    values, plots = codec.split(v)
    assert values == {'beams': 2, 'range_m': {'min': 1.0, 'mean': 1.0, 'max': 1.0}}   # None fields not written
    assert plots['last_scan']['ranges'] == [1.0, None] and plots['last_scan']['kinds'] == ['return', 'no return']
    back = codec.join(LaserValues, json.loads(json.dumps(values)), json.loads(json.dumps(plots)))
    assert back.last_scan.kinds == [BeamKind.RETURN, BeamKind.NO_RETURN] and math.isnan(back.last_scan.ranges[1])
    assert dataclasses.replace(back, last_scan=None) == dataclasses.replace(v, last_scan=None)


def test_codec_names_what_does_not_fit():
    with pytest.raises(codec.CodecError, match='no field width'):
        codec.join(LaserValues, {'width': 3}, {}, strict=True)
    with pytest.raises(codec.CodecError, match='LaserValues.last_scan.kinds'):
        codec.join(LaserValues, {}, {'last_scan': {'angle_min': 0.0, 'angle_increment': 0.1, 'ranges': [1.0],
                                                   'range_min': 0.1, 'range_max': 3.0, 'blind_value': None,
                                                   'kinds': ['sideways']}})


def test_every_family_registers_a_frozen_values_dataclass_with_defaults():
    for fam in families.FAMILIES.values():
        assert fam.values is not None and dataclasses.is_dataclass(fam.values), fam.name
        assert fam.values.__dataclass_params__.frozen, fam.name
        empty = fam.values()                          # every field has a default
        assert codec.join(fam.values, *codec.split(empty)) == empty


def test_stream_statistics_read_back_typed_and_are_written_with_the_same_keys():
    data = old_run()
    run = read_back(data)
    for old, s in zip(data['sensors'], run.sensors):
        assert isinstance(s.stats, StreamSummary), old['name']
        assert s.stats.messages == old['stats']['messages'] and s.stats.clock == 'wall'
        delay = old['stats']['delay_s']
        assert s.stats.delay_s == (DelaySummary(**delay) if delay is not None else None), old['name']
        assert results.summary_line(s).startswith('%d messages in' % old['messages'])
    fresh = StreamStats(start=0.0)
    for i in range(5):
        fresh.add(0.1 * i)                               # no header: no delay
    written = codec.to_json(fresh.summary())
    assert list(written) == list(old_run()['sensors'][0]['stats'])   # the same keys, in order
    assert written['delay_s'] is None and written['stamp_rate_hz'] is None
    not_listened = results.SensorResult('imu', 'IMU', '/imu', 'sensor_msgs/Imu', results.SKIPPED)
    assert not_listened.stats is None and results.sensor_dict(not_listened)['stats'] == {}
    assert results.read_run({'sensors': [results.sensor_dict(not_listened)]}).sensors[0].stats is None


def test_the_real_time_factor_is_written_on_the_sim_clock_only_and_null_when_unknown():
    sim = dataclasses.replace(StreamStats(start=0.0, clock='sim').summary(), real_time_factor=0.6)
    assert codec.to_json(sim)['real_time_factor'] == 0.6
    assert 'real_time_factor' not in codec.to_json(StreamStats(start=0.0).summary())
    unknown = json.loads(json.dumps(codec.to_json(dataclasses.replace(sim, real_time_factor=math.nan))))
    assert 'real_time_factor' in unknown and unknown['real_time_factor'] is None
    back = codec.from_json(StreamSummary, unknown)
    assert math.isnan(back.real_time_factor) and codec.to_json(back) == unknown     # null stays null


def test_stream_statistics_that_do_not_fit_leave_the_verdict():
    data = old_run()
    data['sensors'][0]['stats'] = {'messages': 'many', 'delay_s': 3}
    run = read_back(data)
    assert run.sensors[0].stats is None and run.sensors[0].verdict == data['sensors'][0]['verdict']
