"""Unit: the report's drift block (outputs/report/drift_view.py): a sensor that drifted shows
each value then and now side by side under its warnings, with a trend plot over the run
history when the output folder keeps more than two runs; a run without drift reads no history
and shows no block. Real files in a temporary output folder; no ROS, no browser."""
import json
import os

from pepper_interface_tests import results
from pepper_interface_tests.outputs import baseline, drift
from pepper_interface_tests.outputs.report import drift_view, page
from pepper_interface_tests.results import PASS, RunResult, SensorResult
from pepper_interface_tests.sensors.values.audio import AudioValues, ChannelLevel


def mic(*levels):
    return SensorResult(name='microphone', title='Microphones', topic='/mic', msg_type='x', verdict=PASS,
                        family='audio', rate_hz=10.0, messages=100,
                        values=AudioValues(channels={c: ChannelLevel(rms_dbfs=v) for c, v in zip(
                            ('rearLeft', 'rearRight', 'frontLeft', 'frontRight'), levels)}))


def keep(base, run_id, levels, start):
    run = RunResult(platform='robot', mode='parallel', start=start, end=start + 10, run_id=run_id)
    run.sensors.append(mic(*levels))
    folder = os.path.join(base, 'runs', run_id)
    os.makedirs(folder)
    with open(os.path.join(folder, results.JSON_FILE), 'w') as f:
        json.dump(run.to_dict(), f)
    return folder


def drifted_run(base, n_before):
    ids = ['20261120-1015%02d' % i for i in range(n_before)]
    for i, run_id in enumerate(ids):
        keep(base, run_id, (-29, -30, -29, -30), 1795000000.0 + i)
    compare, _ = baseline.for_run(base, ids[0], 'robot')
    folder = os.path.join(base, 'runs', '20261127-090000')
    os.makedirs(folder)
    run = RunResult(platform='robot', mode='parallel', start=1795600000.0, end=1795600010.0,
                    run_id='20261127-090000')
    compare.out = open(os.devnull, 'w')
    compare.run_started(run, None)
    r = mic(-41, -30, -29, -31)
    compare.sensor_done(r)
    run.sensors.append(r)
    return run, folder


def test_then_and_now_side_by_side_and_a_trend_over_more_than_two_runs(tmp_path):
    run, folder = drifted_run(str(tmp_path), 3)
    html = page.render(run, folder, max_embed=0)
    assert 'Drift since the baseline run 20261120-101500' in html
    row = html[html.index('<td>rearLeft level</td>'):]
    row = row[:row.index('</tr>')]
    assert '-29 dBFS' in row and '-41 dBFS' in row and '12 dB quieter' in row
    assert 'alt="trend of rearLeft level over 4 runs"' in html


def test_two_runs_are_no_trend_and_no_drift_reads_no_history(tmp_path):
    run, folder = drifted_run(str(tmp_path), 1)
    html = page.render(run, folder, max_embed=0)
    assert 'Drift since the baseline' in html and 'trend of' not in html
    run.sensors[0].drift = []
    assert drift_view.history_for(run, folder) is None
    assert 'Drift since the baseline' not in page.render(run, folder, max_embed=0)


def test_a_run_without_a_history_folder_gets_the_table_without_a_trend(tmp_path):
    run, _ = drifted_run(str(tmp_path), 3)
    alone = tmp_path / 'alone'
    alone.mkdir()
    blocks = drift_view.blocks(run.sensors[0], run, drift_view.history_for(run, str(alone)))
    assert [type(b).__name__ for b in blocks] == ['Heading', 'Para', 'Table']
    assert blocks[2].rows[0][0] == 'rearLeft level'
    assert drift.RULES['level'].margin_text() == blocks[2].rows[0][4]
