"""Integration: the motion check's live witnesses place joint states, odometry and the IMU at
their header stamps (motion/witnesses.py STAMPED, issue 41), through real rospy nodes: a
publisher (test/nodes/bursty_witnesses.py) turning the robot 0.5 rad between s = 1 and 2 and
holding what it samples from s = 1.5 to 2.3, then publishing it at once (a busy PC handing
messages over late), and a listener running motion/witnesses.Witnesses
(test/nodes/witness_listener.py). A step that ended at s = 2 must see the whole turn, and the
gyro integrated over the burst must give the turn, whatever the offset of the driver's clock."""
import json
import math
import os
import subprocess
import sys

import pytest

from pepper_interface_tests.motion import estimate
from rosmaster import NODES, kill_group, spawn, wait_until

TURN = 0.5          # rad, the publisher's turn
PLACED = 0.05       # s: a message placed this near the time it was sampled (20 ms samples)


def run(master, tmp_path, offset):
    prefix = '/bursty%d' % int(10 * offset + 100)
    out = tmp_path / 'witnesses.json'
    logs = {n: tmp_path / ('%s.log' % n) for n in ('listener', 'publisher')}
    with open(str(logs['listener']), 'w') as f:
        listener = spawn([sys.executable, os.path.join(NODES, 'witness_listener.py'), prefix, str(out)],
                         master.env(), stdout=f, stderr=subprocess.STDOUT)
    try:
        wait_until(lambda: 'listener up' in logs['listener'].read_text(), 30, logs['listener'].read_text)
        with open(str(logs['publisher']), 'w') as f:
            pub = spawn([sys.executable, os.path.join(NODES, 'bursty_witnesses.py'), prefix, str(offset)],
                        master.env(), stdout=f, stderr=subprocess.STDOUT)
        try:
            wait_until(lambda: 'done' in logs['publisher'].read_text(), 60, logs['publisher'].read_text)
        finally:
            kill_group(pub)
    finally:
        kill_group(listener)
    wait_until(out.exists, 10, logs['listener'].read_text)
    start = float(logs['publisher'].read_text().split('start ')[1].split()[0])
    return json.loads(out.read_text()), start


@pytest.mark.parametrize('offset', [0.0, -3.0, 2.0], ids=['same-clock', 'driver-3s-behind', 'driver-2s-ahead'])
def test_witnesses_handled_in_a_burst_are_placed_when_they_were_sampled(master, tmp_path, offset):
    data, start = run(master, tmp_path, offset)
    t0, t1 = start + 0.5, start + 2.0         # a step sent before the turn, ended as it ended
    for role, series in (('jointState', data['joints']), ('odometry', data['odom']), ('imu', data['gyro'])):
        log = data['log'][role]
        assert len(log) == len(series) and len(log) > 150, (role, len(log), len(series))
        # the delivery was bursty: the held samples (s 1.5-2.3) were handled 0.3 s late or more
        late = [handled - (stamp - offset) for stamp, handled in log]
        assert max(late) > 0.3, (role, max(late))
        # ... and each is placed at its sampling time, on this clock, whatever the driver's offset,
        # from the step's start on (before it, the least lateness may still be settling: on a
        # loaded machine the first messages can come tens of ms late, as witness_wait allows)
        wrong = [(round(stamp - offset - start, 3), round(t - (stamp - offset), 3))
                 for (stamp, _), (t, _) in zip(log, series)
                 if stamp - offset >= t0 and abs(t - (stamp - offset)) > PLACED]
        assert not wrong, (role, wrong[:5])
    # the step sees the turn as it was sampled; placed at their handling times, the held half was
    # outside it. "As sampled": each value at its own stamp on this clock, the publisher's truth
    # (on a loaded PC its 50 Hz loop can sleep 0.2 s, so the sampled turn may stop short of TURN:
    # seen at load 7, the last sample before the step's end at s = 1.82). Placed within PLACED
    # of it, a value moves at most PLACED x the peak rate (pi/4 rad/s): 0.04 rad.
    slack = PLACED * math.pi / 4

    def sampled(role, series):
        return [(stamp - offset, v) for (stamp, _), (_, v) in zip(data['log'][role], series)]
    arrival = [(handled, v) for (_, handled), (_, v) in zip(data['log']['odometry'], data['odom'])]
    truth = estimate.change(sampled('odometry', data['odom']), t0, t1)
    assert truth > 0.35, truth           # the publisher sampled most of the turn before t1
    assert abs(estimate.change(arrival, t0, t1) - truth) > 0.15      # what arrival times gave
    for role, series in (('odometry', data['odom']), ('jointState', data['joints'])):
        assert estimate.change(series, t0, t1) == pytest.approx(
            estimate.change(sampled(role, series), t0, t1), abs=slack)
    # the gyro integrated over the burst: the turn (arrival times stretch the last sample before
    # the hold over it)
    gyro = [(t, 0.0, 0.0, z) for t, z in data['gyro']]
    true_gyro = [(t, 0.0, 0.0, z) for t, z in sampled('imu', data['gyro'])]
    assert estimate.integrated_gyro(gyro, t0, start + 3.0)[2] == pytest.approx(
        estimate.integrated_gyro(true_gyro, t0, start + 3.0)[2], abs=slack)
    assert estimate.integrated_gyro(true_gyro, t0, start + 3.0)[2] == pytest.approx(TURN, abs=0.1)
    by_arrival = [(h, 0.0, 0.0, z) for (_, h), (_, z) in zip(data['log']['imu'], data['gyro'])]
    assert abs(estimate.integrated_gyro(by_arrival, t0, start + 3.0)[2] - TURN) > 0.15
    assert data['behind'] > 0.3 and math.isfinite(data['behind'])
    turned = [estimate.integrated_gyro(g, t0, start + 3.0)[2] for g in (gyro, by_arrival)]
    print('odometry over the step: %.3f rad placed, %.3f by arrival; gyro: %.3f rad placed, %.3f by arrival'
          % (estimate.change(data['odom'], t0, t1), estimate.change(arrival, t0, t1), turned[0], turned[1]))
