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

FIXTURE = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'fixtures', 'emulator-run-v1.json')


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
