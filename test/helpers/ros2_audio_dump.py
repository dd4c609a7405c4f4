"""Test helper, a process of its own: the microphones as a ROS 2 subscriber receives them, from
naoqi_bridge_msgs/AudioBuffer (naoqi_driver2's form: channel_map, interleaved data) or
pepper_interface_tests/AudioCustomMsg (the ROS 1 bridge's form: one array per microphone).

    python ros2_audio_dump.py TOPIC AudioBuffer|AudioCustomMsg OUT.raw

Appends each message's samples to OUT.raw as int16 rows (rear left, rear right, front left,
front right: Pepper's channel codes 3, 5, 0, 2, placed by the channel_map for AudioBuffer), and
prints "dump up" once the topic's publisher is discovered, then "got N" after each message."""
import sys

import numpy as np

from ros2_spin import spin_until_sigterm

ORDER = (3, 5, 0, 2)     # rear left, rear right, front left, front right


def rows(msg, kind):
    if kind == 'AudioBuffer':
        cmap = list(msg.channel_map)
        data = np.asarray(msg.data, dtype='<i2').reshape(-1, len(cmap))
        assert msg.frequency == 48000, msg.frequency
        return data[:, [cmap.index(code) for code in ORDER]]
    return np.stack([np.asarray(getattr(msg, f), dtype='<i2')
                     for f in ('rear_left', 'rear_right', 'front_left', 'front_right')], axis=1)


def main():
    import rclpy
    topic, kind, path = sys.argv[1:4]
    if kind == 'AudioBuffer':
        from naoqi_bridge_msgs.msg import AudioBuffer as cls
    else:
        from pepper_interface_tests.msg import AudioCustomMsg as cls
    out = open(path, 'ab')
    count = [0]

    def got(msg):
        out.write(np.ascontiguousarray(rows(msg, kind), dtype='<i2').tobytes())
        out.flush()
        count[0] += 1
        print('got %d' % count[0], flush=True)
    rclpy.init()
    node = rclpy.create_node('audio_dump')
    node.create_subscription(cls, topic, got, 100)
    while node.count_publishers(topic) == 0:      # DDS discovery: the bridge's publisher seen
        rclpy.spin_once(node, timeout_sec=0.1)
    spin_until_sigterm(rclpy, node, 'dump up')


if __name__ == '__main__':
    main()
