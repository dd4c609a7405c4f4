"""Bad ROS 2 recordings given to `sensorTest --bag`: a clear error naming the file and the fix
(exit 2) where nothing can be read, a per-sensor reason naming the topic where one topic cannot
be read, never a traceback. Real files written here (rosbags, mcap-ros2-support), then broken."""
import os
import shutil

import numpy as np

import fake_pepper as fake
import ros2_recordings as rr
from test_ros2_bags import run


def error_of(path, tmp_path, sensors='laser,imu'):
    p, data = run(path, tmp_path / 'out', sensors=sensors)
    assert p.returncode == 2, p.stdout + p.stderr
    assert not data
    text = p.stdout + p.stderr
    lines = [ln for ln in text.splitlines() if ln.startswith('sensorTest: error: ')]
    assert len(lines) == 1 and lines[0].startswith('sensorTest: error: %s: ' % path), text
    assert 'fix: ' in text, text
    return text


def truncated(src, dst):
    with open(src, 'rb') as f:
        data = f.read()
    with open(dst, 'wb') as f:
        f.write(data[:len(data) // 2])
    return str(dst)


def test_folder_without_metadata_yaml(tmp_path):
    folder = rr.write_rosbags(tmp_path / 'rec', rr.records(seconds=1.0), 'sqlite3')
    os.remove(os.path.join(folder, 'metadata.yaml'))
    out = error_of(folder, tmp_path)
    assert 'no metadata.yaml in this folder' in out and 'ros2 bag reindex' in out
    # its storage file alone is still a recording
    p, data = run(os.path.join(folder, 'rec.db3'), tmp_path / 'alone', sensors='laser,imu')
    assert p.returncode == 0 and data['laser']['messages'] == 10, p.stdout


def test_truncated_db3_and_mcap(tmp_path):
    recs = rr.records(seconds=1.0)
    folder = rr.write_rosbags(tmp_path / 'rec', recs, 'sqlite3')
    db3 = truncated(os.path.join(folder, 'rec.db3'), tmp_path / 'cut.db3')
    assert 'cannot open the ROS 2 recording' in error_of(db3, tmp_path / 'a')
    mcap = truncated(rr.write_mcap_ros2(tmp_path / 'whole.mcap', recs), tmp_path / 'cut.mcap')
    out = error_of(mcap, tmp_path / 'b')
    assert 'cannot open the ROS 2 recording' in out and 'mcap recover' in out
    # the same inside a rosbag2 folder
    mfolder = rr.write_rosbags(tmp_path / 'mrec', recs, 'mcap')
    truncated(os.path.join(mfolder, 'mrec.mcap'), tmp_path / 'tmp.mcap')
    shutil.move(str(tmp_path / 'tmp.mcap'), os.path.join(mfolder, 'mrec.mcap'))
    assert 'cannot open the ROS 2 recording' in error_of(mfolder, tmp_path / 'c')


def test_unknown_storage_plugin(tmp_path):
    folder = rr.write_rosbags(tmp_path / 'rec', rr.records(seconds=1.0), 'sqlite3')
    meta = os.path.join(folder, 'metadata.yaml')
    with open(meta) as f:
        text = f.read()
    with open(meta, 'w') as f:
        f.write(text.replace('storage_identifier: sqlite3', 'storage_identifier: rosbag_v3'))
    assert "Storage plugin 'rosbag_v3' not supported" in error_of(folder, tmp_path)


def test_empty_recording_and_renamed_mcap(tmp_path):
    from rosbags.rosbag2 import Writer
    from rosbags.typesys import Stores, get_typestore
    w = Writer(str(tmp_path / 'empty'), version=8)
    with w:
        w.add_connection('/laser', 'sensor_msgs/msg/LaserScan', typestore=get_typestore(Stores.ROS2_HUMBLE))
    assert 'holds no message' in error_of(str(tmp_path / 'empty'), tmp_path / 'a')
    mcap = rr.write_mcap_ros2(tmp_path / 'rec.mcap', rr.records(seconds=1.0))
    renamed = str(tmp_path / 'rec.bin')
    shutil.copy(mcap, renamed)
    assert 'rename it to end in .mcap' in error_of(renamed, tmp_path / 'b')


def test_a_topic_whose_type_has_no_definition(tmp_path):
    """A Humble-style sqlite3 recording (no definitions stored) with a type nobody defines: that
    sensor fails naming its topic and type, the others are judged."""
    from rosbags.rosbag2 import Writer
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore
    ts = get_typestore(Stores.ROS2_HUMBLE)
    ts.register(get_types_from_msg('std_msgs/Header header\nfloat32[] values\n', 'acme_msgs/msg/Scan'))
    scan = ts.types['acme_msgs/msg/Scan']
    header, time = ts.types['std_msgs/msg/Header'], ts.types['builtin_interfaces/msg/Time']
    nodef = {'msgdef': '', 'rihs01': 'RIHS01_' + '0' * 64}
    w = Writer(str(tmp_path / 'rec'), version=8)
    with w:
        laser = w.add_connection('/laser', 'acme_msgs/msg/Scan', **nodef)
        imu = w.add_connection('/imu/base', 'sensor_msgs/msg/Imu', **nodef)
        for r in rr.records(seconds=2.0, leave_out=[s for s in rr.TOPICS if s != 'imu']):
            ns = int(round(r.t * 1e9))
            m = scan(header=header(stamp=time(sec=int(r.t), nanosec=0), frame_id='x'),
                     values=np.array([1.0], dtype=np.float32))
            w.write(laser, ns, ts.serialize_cdr(m, 'acme_msgs/msg/Scan'))
            w.write(imu, ns, bytes(ts.ros1_to_cdr(fake.serialized(r.msg), 'sensor_msgs/msg/Imu')))
    p, data = run(str(tmp_path / 'rec'), tmp_path / 'out', sensors='laser,imu')
    assert p.returncode == 1, p.stdout + p.stderr
    note = [ln for ln in p.stdout.splitlines() if 'cannot be read' in ln]
    assert len(note) == 1 and 'topic /laser' in note[0] and 'acme_msgs/msg/Scan' in note[0], p.stdout
    assert data['laser']['verdict'] == 'FAIL'
    assert data['laser']['reasons'][0].startswith('topic /laser carries acme_msgs/Scan'), data['laser']
    assert data['imu']['verdict'] == 'PASS' and data['imu']['messages'] == 20
