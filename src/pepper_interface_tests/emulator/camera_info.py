"""Each camera's CameraInfo as naoqi_driver2 publishes it beside the image, for the emulator on
ROS 2: image_transport's camera publisher (ros-naoqi/naoqi_driver2 2.1.2
src/publishers/camera.cpp:44-51) sends `<camera>/camera_info` with every image, the
calibration a fixed table per camera and resolution (src/converters/camera.cpp:57-180
getCameraInfo; src/converters/camera_info_definitions.hpp, line numbers below), stamped with
the image's stamp (camera.cpp:292), in the table's frame (the image's own). Held to the driver's
recording in test/emulator/test_conformance2.py."""
from typing import Any, Dict, Optional, Sequence, Tuple

import numpy as np

Calibration = Tuple[str, Sequence[float], Sequence[float], Sequence[float], Sequence[float]]
# (distortion model, D, K, R, P)
IDENTITY = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)
# (width, height): (K, D, P), distortion plumb_bob, R identity
TOP: Dict[Tuple[int, int], Tuple[Sequence[float], Sequence[float], Sequence[float]]] = {
    (640, 480): (  # createCameraInfoTOPVGA :34
        (556.845054830986, 0, 309.366895338178, 0, 555.898679730161, 230.592233628776, 0, 0, 1),
        (-0.0545211535376379, 0.0691973423510287, -0.00241094929163055, -0.00112245009306511, 0),
        (551.589721679688, 0, 308.271132841983, 0, 0, 550.291320800781, 229.20143668168, 0, 0, 0, 1, 0)),
    (320, 240): (  # createCameraInfoTOPQVGA :55
        (274.139508945831, 0, 141.184472810944, 0, 275.741846757374, 106.693773654172, 0, 0, 1),
        (-0.0870160932911717, 0.128210165050533, 0.003379500659424, -0.00106205540818586, 0),
        (272.423675537109, 0, 141.131930791285, 0, 0, 273.515747070312, 107.391746054313, 0, 0, 0, 1, 0)),
    (160, 120): (  # createCameraInfoTOPQQVGA :76
        (139.424539568966, 0, 76.9073669920582, 0, 139.25542782325, 59.5554242026743, 0, 0, 1),
        (-0.0843564504845967, 0.125733083790192, 0.00275901756247071, -0.00138645823460527, 0),
        (137.541534423828, 0, 76.3004646597892, 0, 0, 136.815216064453, 59.3909799751191, 0, 0, 0, 1, 0)),
}
BOTTOM: Dict[Tuple[int, int], Tuple[Sequence[float], Sequence[float], Sequence[float]]] = {
    (640, 480): (  # createCameraInfoBOTTOMVGA :100
        (558.570339530768, 0, 308.885375457296, 0, 556.122943034837, 247.600724811385, 0, 0, 1),
        (-0.0648763971625288, 0.0612520196884308, 0.0038281538281731, -0.00551104078371959, 0),
        (549.571655273438, 0, 304.799679526441, 0, 0, 549.687316894531, 248.526959297022, 0, 0, 0, 1, 0)),
    (320, 240): (  # createCameraInfoBOTTOMQVGA :121
        (278.236008818534, 0, 156.194471689706, 0, 279.380102992049, 126.007123836447, 0, 0, 1),
        (-0.0481869853715082, 0.0201858398559121, 0.0030362056699177, -0.00172241952442813, 0),
        (273.491455078125, 0, 155.112454709117, 0, 0, 275.743133544922, 126.057357467223, 0, 0, 0, 1, 0)),
    (160, 120): (  # createCameraInfoBOTTOMQQVGA :142
        (141.611855886672, 0, 78.6494086288656, 0, 141.367163830175, 58.9220646201529, 0, 0, 1),
        (-0.0688388724945936, 0.0697453843669642, 0.00309518737071049, -0.00570486993696543, 0),
        (138.705535888672, 0, 77.2544255212306, 0, 0, 138.954086303711, 58.7000861760043, 0, 0, 0, 1, 0)),
}
# the Xtion's VGA, QVGA, QQVGA (createCameraInfoDEPTHVGA :166, QVGA :187, QQVGA :207): K = P of
# 525 px at VGA, divided by 1, 2, 4 in float; no distortion model, no D
DEPTH_DIVISOR = {(640, 480): 1.0, (320, 240): 2.0, (160, 120): 4.0}
# the stereo pair's (createCameraInfoStereo :230-279, float32 arithmetic): the depth at 720p
# 1280x720 / 1, 640x360 / 2, 320x180 / 4, 160x90 / 8, 80x45 / 16 (:281-305) and the stereo
# image at 2560x720 / 1 ... 160x45 / 16 (:308-331)
STEREO_K = (703.102356, 0, 647.821594, 0, 702.432312, 380.971680, 0, 0, 1)
STEREO_D = (-0.168594331, .00881872326, -0.000182721298, -0.0000145479062, 0.0137237618)
STEREO_R = (0.999984741, 0.000130843779, 0.00552622462, -0.000111592424, 0.999993920, -0.00348380185,
            -0.00552664697, 0.00348313176, 0.999978662)
STEREO_P = (569.869568, 0, 644.672058, 0, 0, 569.869568, 393.368958, 0, 0, 0, 1, 0)
DEPTH_720P = {(1280 // d, 720 // d): float(d) for d in (1, 2, 4, 8, 16)}
STEREO_X2 = {(2560 // d, 720 // d): float(d) for d in (1, 2, 4, 8, 16)}
_SCALED = (0, 2, 4, 5)      # K's fx, cx, fy, cy; P's the same and more, below
_SCALED_P = (0, 2, 5, 6)


def _f32(values: Sequence[float], divisor: float, scaled: Sequence[int]) -> Tuple[float, ...]:
    """The driver's float arrays: each value a float32, the scaled ones divided as float32."""
    out = np.asarray(values, dtype=np.float32)
    out[list(scaled)] = out[list(scaled)] / np.float32(divisor)
    return tuple(float(v) for v in out)


def _stereo(divisor: float) -> Calibration:
    return ('plumb_bob', _f32(STEREO_D, 1.0, ()), _f32(STEREO_K, divisor, _SCALED),
            _f32(STEREO_R, 1.0, ()), _f32(STEREO_P, divisor, _SCALED_P))


def _depth(divisor: float) -> Calibration:
    k = (525 / divisor, 0, 319.5 / divisor, 0, 525 / divisor, 239.5 / divisor, 0, 0, 1)
    p = (k[0], 0, k[2], 0, 0, k[4], k[5], 0, 0, 0, 1, 0)
    return '', (), _f32(k, 1.0, ()), IDENTITY, _f32(p, 1.0, ())


def calibration(view: str, width: int, height: int) -> Optional[Calibration]:
    """(distortion model, D, K, R, P) naoqi_driver2 publishes for the emulator's camera `view`
    (front: kTopCamera, bottom: kBottomCamera, depth: kDepthCamera, stereo and ir:
    kInfraredOrStereoCamera) at width x height; None where the driver has no table (camera.cpp
    getEmptyInfo: then the emulator publishes none)."""
    size = (width, height)
    if view in ('front', 'bottom') and size in (TOP if view == 'front' else BOTTOM):
        k, d, p = (TOP if view == 'front' else BOTTOM)[size]
        return 'plumb_bob', tuple(map(float, d)), tuple(map(float, k)), IDENTITY, tuple(map(float, p))
    if view in ('depth', 'stereo', 'ir') and size in DEPTH_DIVISOR:
        return _depth(DEPTH_DIVISOR[size])
    scaled = DEPTH_720P if view == 'depth' else STEREO_X2 if view in ('stereo', 'ir') else {}
    return _stereo(scaled[size]) if size in scaled else None


def info_topic(image_topic: str) -> str:
    """image_transport's camera_info topic: beside the image's (`camera/front/image_raw` ->
    `camera/front/camera_info`)."""
    return image_topic.rsplit('/', 1)[0] + '/camera_info'


def message(cls: Any, view: str, width: int, height: int, frame_id: str) -> Optional[Any]:
    """A CameraInfo (of `cls`) of the table, without its stamp; None: no table."""
    cal = calibration(view, width, height)
    if cal is None:
        return None
    model, d, k, r, p = cal
    msg = cls()
    msg.header.frame_id = frame_id
    msg.width, msg.height, msg.distortion_model = width, height, model
    # ROS 1's names (D, K, R, P), or ROS 2's (d, k, r, p) in the genpy class built on ROS 2
    names = ('d', 'k', 'r', 'p') if 'd' in getattr(cls, '__slots__', ()) else ('D', 'K', 'R', 'P')
    for name, values in zip(names, (d, k, r, p)):
        setattr(msg, name, list(values))
    return msg


class CameraInfoSender:
    """The camera_info publisher beside one image topic: the table's message, stamped as each
    image is (`send`), keep-last 10 as the image (qos2.py)."""

    def __init__(self, image_topic: str, template: Any) -> None:
        from .. import rosapi
        from .qos2 import depth
        self.template = template
        self.pub = rosapi.publisher(info_topic(image_topic), 'sensor_msgs/CameraInfo', queue_size=depth('camera'),
                                    cls=type(template))

    def send(self, stamp: Any) -> None:
        self.template.header.stamp = stamp
        self.pub.publish(self.template)

    def close(self) -> None:
        self.pub.unregister()


def sender_for(image_topic: str, view: str, width: int, height: int, frame_id: str) -> Optional[CameraInfoSender]:
    """The sender for an image stream naoqi_driver2 has a calibration for (None: no table)."""
    from .. import rosapi
    template = message(rosapi.msg('sensor_msgs/CameraInfo'), view, width, height, frame_id)
    return CameraInfoSender(image_topic, template) if template is not None else None
