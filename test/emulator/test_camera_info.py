"""emulator/camera_info.py: the CameraInfo the emulator publishes on ROS 2 beside each image is
the real naoqi_driver2's, number for number. The expected values below are what naoqi_driver2
2.1.2 (tools/real-driver2, run against the fake NAOqi, 2026-12-07) published on
/camera/*/camera_info, recorded by tools/real-driver2/record2.py (stereo head: front, bottom,
depth 640x360, stereo 640x180; Xtion head: depth and ir 320x240); the golden recordings that list
camera_info are compared with the emulator again in test/emulator/test_conformance2.py."""
import pytest

from pepper_interface_tests.emulator import camera_info

STEREO_D = (-0.1685943305492401, 0.008818723261356354, -0.00018272129818797112, -1.4547906175721437e-05,
            0.013723761774599552)
STEREO_R = (0.9999847412109375, 0.0001308437786065042, 0.0055262246169149876, -0.00011159242421854287,
            0.9999939203262329, -0.0034838018473237753, -0.005526646971702576, 0.0034831317607313395,
            0.9999786615371704)
IDENTITY = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)
XTION_K = (262.5, 0.0, 159.75, 0.0, 262.5, 119.75, 0.0, 0.0, 1.0)
XTION_P = (262.5, 0.0, 159.75, 0.0, 0.0, 262.5, 119.75, 0.0, 0.0, 0.0, 1.0, 0.0)
RECORDED = {
    ('front', 320, 240): ('plumb_bob', (-0.0870160932911717, 0.128210165050533, 0.003379500659424,
                                        -0.00106205540818586, 0.0),
                          (274.139508945831, 0.0, 141.184472810944, 0.0, 275.741846757374, 106.693773654172,
                           0.0, 0.0, 1.0), IDENTITY,
                          (272.423675537109, 0.0, 141.131930791285, 0.0, 0.0, 273.515747070312, 107.391746054313,
                           0.0, 0.0, 0.0, 1.0, 0.0)),
    ('bottom', 320, 240): ('plumb_bob', (-0.0481869853715082, 0.0201858398559121, 0.0030362056699177,
                                         -0.00172241952442813, 0.0),
                           (278.236008818534, 0.0, 156.194471689706, 0.0, 279.380102992049, 126.007123836447,
                            0.0, 0.0, 1.0), IDENTITY,
                           (273.491455078125, 0.0, 155.112454709117, 0.0, 0.0, 275.743133544922,
                            126.057357467223, 0.0, 0.0, 0.0, 1.0, 0.0)),
    ('depth', 640, 360): ('plumb_bob', STEREO_D,
                          (351.5511779785156, 0.0, 323.9107971191406, 0.0, 351.2161560058594, 190.48583984375,
                           0.0, 0.0, 1.0), STEREO_R,
                          (284.9347839355469, 0.0, 322.3360290527344, 0.0, 0.0, 284.9347839355469,
                           196.68447875976562, 0.0, 0.0, 0.0, 1.0, 0.0)),
    ('stereo', 640, 180): ('plumb_bob', STEREO_D,
                           (175.7755889892578, 0.0, 161.9553985595703, 0.0, 175.6080780029297, 95.242919921875,
                            0.0, 0.0, 1.0), STEREO_R,
                           (142.46739196777344, 0.0, 161.1680145263672, 0.0, 0.0, 142.46739196777344,
                            98.34223937988281, 0.0, 0.0, 0.0, 1.0, 0.0)),
    ('depth', 320, 240): ('', (), XTION_K, IDENTITY, XTION_P),
    ('ir', 320, 240): ('', (), XTION_K, IDENTITY, XTION_P),
}


@pytest.mark.parametrize('view, width, height', sorted(RECORDED))
def test_the_calibration_is_the_one_naoqi_driver2_published(view, width, height):
    got = camera_info.calibration(view, width, height)
    assert got is not None
    assert tuple(tuple(x) if not isinstance(x, str) else x for x in got) == RECORDED[(view, width, height)]


def test_no_table_no_camera_info():
    """The driver's getEmptyInfo for what it has no table for: the emulator publishes none."""
    assert camera_info.calibration('realsense', 640, 480) is None
    assert camera_info.calibration('front', 1280, 960) is None
    assert camera_info.calibration('depth', 640, 180) is None      # the stereo image's size, not depth's


def test_the_topic_is_image_transports():
    assert camera_info.info_topic('/camera/front/image_raw') == '/camera/front/camera_info'
    assert camera_info.info_topic('camera/depth/image_raw') == 'camera/depth/camera_info'


def test_the_message_carries_the_table_with_either_ros_field_names():
    class Ros1Info:
        __slots__ = ('header', 'width', 'height', 'distortion_model', 'D', 'K', 'R', 'P')

        def __init__(self):
            self.header = type('H', (), {'frame_id': ''})()

    class Ros2Info:
        __slots__ = ('header', 'width', 'height', 'distortion_model', 'd', 'k', 'r', 'p')

        def __init__(self):
            self.header = type('H', (), {'frame_id': ''})()

    m1 = camera_info.message(Ros1Info, 'stereo', 640, 180, 'CameraDepth_optical_frame')
    m2 = camera_info.message(Ros2Info, 'stereo', 640, 180, 'CameraDepth_optical_frame')
    want = RECORDED[('stereo', 640, 180)]
    assert (m1.distortion_model, tuple(m1.D), tuple(m1.K), tuple(m1.R), tuple(m1.P)) == want
    assert (m2.distortion_model, tuple(m2.d), tuple(m2.k), tuple(m2.r), tuple(m2.p)) == want
    assert (m1.width, m1.height, m1.header.frame_id) == (640, 180, 'CameraDepth_optical_frame')
