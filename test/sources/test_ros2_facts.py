"""Unit: the facts of a ROS 2 recording (test/helpers/ros2_facts.py, for holding the emulator on
ROS 2 against the real naoqi_driver2): types in bag_facts' names, frames, layout, rate, and the
offered QoS of each publisher from metadata.yaml, on an MCAP recording written with rosbags'
Writer and the QoS of naoqi_driver2's sonar publisher (keep-last 1, src/publishers/sonar.cpp:53)
and of its robot description (transient local, src/tools/robot_description.cpp:68-71)."""
from ros2_facts import differences, recording_facts
from rosbags_support import reads_ros2

pytestmark = reads_ros2


def _qos(depth, durability):
    from rosbags.interfaces import Qos, QosHistory, QosLiveliness, QosReliability, QosTime
    zero = QosTime(sec=0, nsec=0)
    return Qos(history=QosHistory.KEEP_LAST, depth=depth, reliability=QosReliability.RELIABLE,
               durability=durability, deadline=zero, lifespan=zero, liveliness=QosLiveliness.AUTOMATIC,
               liveliness_lease_duration=zero, avoid_ros_namespace_conventions=False)


def _write(path, sonar_depth, frame='SonarFront_frame'):
    from rosbags.interfaces import QosDurability
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore
    store = get_typestore(Stores.ROS2_HUMBLE)
    Range = store.types['sensor_msgs/msg/Range']
    Header = store.types['std_msgs/msg/Header']
    Time = store.types['builtin_interfaces/msg/Time']
    String = store.types['std_msgs/msg/String']
    with Writer(path, version=8, storage_plugin=StoragePlugin.MCAP) as w:
        sonar = w.add_connection('/sonar/front', 'sensor_msgs/msg/Range', typestore=store,
                                 offered_qos_profiles=[_qos(sonar_depth, QosDurability.VOLATILE)])
        desc = w.add_connection('/robot_description', 'std_msgs/msg/String', typestore=store,
                                offered_qos_profiles=[_qos(1, QosDurability.TRANSIENT_LOCAL)])
        w.write(desc, 10**9, store.serialize_cdr(String(data='<robot/>'), 'std_msgs/msg/String'))
        for i in range(11):
            ns = 10**9 + i * 10**8       # 10 Hz for one second
            m = Range(header=Header(stamp=Time(sec=1, nanosec=i * 10**8), frame_id=frame), radiation_type=0,
                      field_of_view=0.5236, min_range=0.25, max_range=2.55, range=1.0)
            w.write(sonar, ns, store.serialize_cdr(m, 'sensor_msgs/msg/Range'))


def test_facts_of_a_recording_with_the_publishers_qos(tmp_path):
    _write(tmp_path / 'rec', 1)
    facts = recording_facts(tmp_path / 'rec')
    sonar = facts['/sonar/front']
    assert sonar['type'] == 'sensor_msgs/Range' and sonar['frames'] == {'SonarFront_frame'}
    assert sonar['count'] == 11 and abs(sonar['rate'] - 10.0) < 1e-6
    assert sonar['facts'] == dict(radiation_type=0, field_of_view=0.5236, min_range=0.25, max_range=2.55)
    assert sonar['qos'] == (('reliable', 'volatile', 1),)
    assert facts['/robot_description']['qos'] == (('reliable', 'transient_local', 1),)


def test_differences_name_the_topic_and_the_fact(tmp_path):
    _write(tmp_path / 'real', 1)
    _write(tmp_path / 'emulator', 10, frame='sonar')
    real, emu = recording_facts(tmp_path / 'real'), recording_facts(tmp_path / 'emulator')
    assert differences(real, real) == {}
    got = differences(real, emu)
    assert set(got) == {('/sonar/front', 'frames'), ('/sonar/front', 'qos')}, got
    assert "'volatile', 10" in got[('/sonar/front', 'qos')]
    del emu['/robot_description']
    assert differences(real, emu)[('/robot_description', 'topic')] == 'only in the first recording'


def test_a_camera_info_has_its_calibration_under_ros1_names(tmp_path):
    """ROS 2's CameraInfo (d, k, r, p) gives bag_facts' calibration facts (D, K, R, P), and
    messages() yields the recording's messages in time order."""
    import numpy as np
    from rosbags.interfaces import QosDurability
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    from ros2_facts import messages
    store = get_typestore(Stores.ROS2_HUMBLE)
    T = store.types
    info = T['sensor_msgs/msg/CameraInfo'](
        header=T['std_msgs/msg/Header'](stamp=T['builtin_interfaces/msg/Time'](sec=1, nanosec=5),
                                        frame_id='CameraTop_optical_frame'),
        height=240, width=320, distortion_model='plumb_bob', d=np.array([0.1, 0.2, 0, 0, 0]),
        k=np.array([274.0, 0, 141, 0, 275, 106, 0, 0, 1]),
        r=np.array([1.0, 0, 0, 0, 1, 0, 0, 0, 1]),
        p=np.array([272.0, 0, 141, 0, 0, 273, 107, 0, 0, 0, 1, 0]), binning_x=0, binning_y=0,
        roi=T['sensor_msgs/msg/RegionOfInterest'](x_offset=0, y_offset=0, height=0, width=0, do_rectify=False))
    with Writer(tmp_path / 'rec', version=8, storage_plugin=StoragePlugin.MCAP) as w:
        c = w.add_connection('/camera/front/camera_info', 'sensor_msgs/msg/CameraInfo', typestore=store,
                             offered_qos_profiles=[_qos(10, QosDurability.VOLATILE)])
        for i in range(3):
            w.write(c, 10**9 + i, store.serialize_cdr(info, 'sensor_msgs/msg/CameraInfo'))
    facts = recording_facts(tmp_path / 'rec')['/camera/front/camera_info']
    assert facts['type'] == 'sensor_msgs/CameraInfo' and facts['frames'] == {'CameraTop_optical_frame'}
    assert facts['facts'] == dict(width=320, height=240, distortion_model='plumb_bob', D=(0.1, 0.2, 0, 0, 0),
                                  K=(274.0, 0, 141, 0, 275, 106, 0, 0, 1), R=(1.0, 0, 0, 0, 1, 0, 0, 0, 1),
                                  P=(272.0, 0, 141, 0, 0, 273, 107, 0, 0, 0, 1, 0))
    got = list(messages(tmp_path / 'rec', {'/camera/front/camera_info'}))
    assert [t for _, _, t in got] == [10**9, 10**9 + 1, 10**9 + 2]
    assert got[0][1].k[0] == 274.0
