"""recordTestBags: record small bags of the emulator (good and faulty robots, the simulator) with
`rosbag record`, for sensorTest --bag and for tests.

    recordTestBags --out DIR [--seconds 4] [--use-master] [--variants a,b] [--resolution QQVGA]
                   [--compression lz4|bz2|none]

Without --use-master a private roscore is started on a free port (and stopped at the end);
with it, the master of ROS_MASTER_URI is used (no other emulator may be running there).
Each variant: start the emulator (a robot profile with the microphones published by the
emulator itself and the RealSense on, or the simulator profile on sim time at real-time factor
0.5), wait until all its topics are advertised, `rosbag record` the sensor topics (and /clock for
the simulator: rosbag then stamps the bag in sim time; never /speech, /rosout, /diagnostics) for
--seconds of wall time, stop it with SIGINT to its process group, check that no .bag.active file
remains, open the bag with rosbag and print a summary.
Exit codes: 0 all bags written, 1 a recording failed, 2 bad usage or no master.
"""
import argparse
import os
import shutil
import subprocess
import sys
import time
from collections import OrderedDict
from typing import IO, Dict, Mapping, Optional, Sequence, Set, Tuple

import rosgraph

from ..rosmaster import MasterError, PrivateMaster, stop_group
from .faults import parse_faults
from .profiles import RESOLUTIONS, build_profile
from .tf_publisher import static_topic

# name -> (profile, faults, extra emulator params)
VARIANTS = OrderedDict([
    ('robot_good', ('robot', '', {})),
    ('robot_faulty', ('robot', 'frontCamera:frozen;laser:nan;imu:broken_quaternion;'
                               'backSonar:silent;microphone:silent_channel=rearRight;'
                               # data that looks healthy but cannot be real (issue 10)
                               'depthCamera:stuck;jointState:joint_jump;odometry:pose_jump', {})),
    ('robot_xtion_good', ('robot', '', {'head': 'xtion'})),
    ('robot_stock_good', ('robot-stock', '', {})),
    # the real fault classes: NaN attitude with covariance -1, a dead microphone inside
    # an AudioBuffer, an all-blind laser, a NaN sonar
    ('robot_stock_faulty', ('robot-stock', 'imu:nan_attitude;microphone:silent_channel=frontLeft;'
                                           'laser:all_blind;frontSonar:nan;'
                                           'odometry:twist_mismatch;realsenseDepthCamera:far_depth', {})),
    ('simulator_good', ('simulator', '', {})),
    ('simulator_faulty', ('simulator', 'depthCamera:wrong_encoding;laser:out_of_range;'
                                       'odometry:rate=0.3;frontSonar:silent;jointState:joint_jump', {})),
    ('simulator_no_returns', ('simulator', 'laser:no_returns', {})),
])
SIM_RTF = 0.5                  # the simulator bags' real-time factor
EXCLUDED = ('/speech', '/rosout', '/rosout_agg', '/diagnostics')


class RecordError(RuntimeError):
    pass


def _published(uri: str) -> Set[str]:
    state = rosgraph.Master('/recordTestBags', master_uri=uri).getSystemState()
    return {t for t, _ in state[0]}


def record_variant(name: str, out_dir: str, env: Mapping[str, str], seconds: float, resolution: str,
                   compression: str, log: IO[str]) -> str:
    profile_name, faults, extra = VARIANTS[name]
    parse_faults(faults)                                   # fail early on a typo
    profile = build_profile(profile_name, realsense=True, audio='direct', resolution=resolution,
                            head=extra.get('head', 'stereo'))
    topics = [t for s in profile.sensors for t in [s.topic] + [e[0] for e in s.extra]
              if t not in EXCLUDED]
    # the tree's latched /tf_static (the simulator's fixed joints, the RealSense's frames)
    topics += [t for t in map(static_topic, profile.sensors) if t]
    if profile.sim_time:
        topics.append('/clock')
    path = os.path.join(out_dir, name + '.bag')
    for stale in (path, path + '.active'):
        if os.path.exists(stale):
            os.remove(stale)
    emu_cmd = [sys.executable, '-m', 'pepper_interface_tests.emulator.node',
               '__name:=pepperEmulator_' + name, '_profile:=' + profile_name, '_audio:=direct',
               '_realsense:=true', '_camera_resolution:=' + resolution, '_faults:=' + faults,
               '_real_time_factor:=%g' % SIM_RTF] + ['_%s:=%s' % kv for kv in sorted(extra.items())]
    emu = subprocess.Popen(emu_cmd, env=env, stdout=log, stderr=subprocess.STDOUT,
                           start_new_session=True)
    rec = None
    try:
        deadline = time.time() + 30
        while not set(topics) <= _published(env['ROS_MASTER_URI']):
            if emu.poll() is not None:
                raise RecordError('%s: the emulator exited with code %s' % (name, emu.returncode))
            if time.time() > deadline:
                raise RecordError('%s: topics not advertised after 30 s: %s' % (
                    name, ', '.join(sorted(set(topics) - _published(env['ROS_MASTER_URI'])))))
            time.sleep(0.2)
        cmd = ['rosbag', 'record', '-O', path, '__name:=record_' + name]
        if compression != 'none':
            cmd.append('--' + compression)
        rec = subprocess.Popen(cmd + topics, env=env, stdout=log, stderr=subprocess.STDOUT,
                               start_new_session=True)
        deadline = time.time() + 20
        while not os.path.exists(path + '.active'):
            if rec.poll() is not None or time.time() > deadline:
                raise RecordError('%s: rosbag record did not start' % name)
            time.sleep(0.1)
        time.sleep(0.7 + seconds)                    # subscriptions connect, then the window
    finally:
        stop_group(rec)
        stop_group(emu)
    if os.path.exists(path + '.active'):
        raise RecordError('%s: %s.active remains: rosbag record was not stopped cleanly'
                          % (name, path))
    if not os.path.exists(path):
        raise RecordError('%s: %s was not written' % (name, path))
    return path


def summarize(path: str) -> Tuple[float, Dict[str, Tuple[str, int]]]:
    import rosbag
    with rosbag.Bag(path) as bag:
        info = bag.get_type_and_topic_info().topics
        duration = bag.get_end_time() - bag.get_start_time() if info else 0.0
        return duration, {t: (i.msg_type, i.message_count) for t, i in sorted(info.items())}


def main(argv: Optional[Sequence[str]] = None) -> int:
    p = argparse.ArgumentParser(prog='recordTestBags', description=__doc__.split('\n\n')[0])
    p.add_argument('--out', required=True, help='directory for the bags (created)')
    p.add_argument('--seconds', type=float, default=4.0, help='recording window per bag (4)')
    p.add_argument('--use-master', action='store_true',
                   help='use the running master of ROS_MASTER_URI instead of a private roscore')
    p.add_argument('--variants', default=','.join(VARIANTS),
                   help='comma-separated subset of: ' + ', '.join(VARIANTS))
    p.add_argument('--resolution', default='QQVGA', choices=sorted(RESOLUTIONS),
                   help='front/bottom/depth camera resolution (QQVGA keeps the bags small)')
    p.add_argument('--compression', default='lz4', choices=('lz4', 'bz2', 'none'))
    a = p.parse_args(argv)
    variants = [v.strip() for v in a.variants.split(',') if v.strip()]
    unknown = [v for v in variants if v not in VARIANTS]
    if unknown or not variants:
        p.error('unknown variant(s) %s; valid: %s' % (', '.join(unknown), ', '.join(VARIANTS)))
    if not a.seconds > 0:
        p.error('--seconds must be positive')
    if shutil.which('rosbag') is None:
        print('recordTestBags: error: rosbag not found on PATH (source the ROS setup)', file=sys.stderr)
        return 2
    out_dir = os.path.abspath(os.path.expanduser(a.out))
    os.makedirs(out_dir, exist_ok=True)
    log_path = os.path.join(out_dir, 'recordTestBags.log')
    written = []
    with open(log_path, 'w') as log:
        try:
            if a.use_master:
                env = dict(os.environ, PYTHONUNBUFFERED='1')
                if not rosgraph.Master('/recordTestBags').is_online():
                    print('recordTestBags: error: no ROS master at %s' % rosgraph.get_master_uri(),
                          file=sys.stderr)
                    return 2
                master = None
            else:
                try:
                    master = PrivateMaster('/recordTestBags').start()
                except MasterError as e:
                    raise RecordError(str(e)) from None
                env = master.env()
            try:
                for name in variants:
                    print('recordTestBags: recording %s (%.1f s) ...' % (name, a.seconds), flush=True)
                    written.append(record_variant(name, out_dir, env, a.seconds, a.resolution,
                                                  a.compression, log))
            finally:
                if master is not None:
                    master.stop()
        except RecordError as e:
            print('recordTestBags: error: %s (details in %s)' % (e, log_path), file=sys.stderr)
            return 1
    for path in written:
        duration, topics = summarize(path)
        print('%s  %.2f MB  %.1f s' % (path, os.path.getsize(path) / 1e6, duration))
        for topic, (msg_type, count) in topics.items():
            print('    %-45s %-38s %5d' % (topic, msg_type, count))
    return 0
