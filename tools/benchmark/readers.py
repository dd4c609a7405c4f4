#!/usr/bin/env python3
"""The floors of the recording benchmark: what the libraries themselves take to read and
deserialize every message of a recording, run as their own process (python readers.py KIND PATH).

  rosbag   a ROS 1 bag: rosbag's read_messages, each message deserialized into the class built
           from the bag's own definition (what `rosbag` gives a user, raw=False);
  rosbags  a ROS 2 recording: rosbags' Reader, each message deserialized by its typestore
           (Humble's standard types, plus every definition the recording stores) with
           deserialize_cdr, as rosbags' documentation reads a recording.
Prints the number of messages read."""
import sys


def read_rosbag(path: str) -> int:
    import rosbag
    n = 0
    with rosbag.Bag(path) as bag:
        for _topic, _msg, _t in bag.read_messages():
            n += 1
    return n


def read_rosbags(path: str) -> int:
    from rosbags.rosbag2 import Reader
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore
    store = get_typestore(Stores.ROS2_HUMBLE)
    n = 0
    with Reader(path) as reader:
        for conn in reader.connections:
            data = getattr(conn.msgdef, 'data', '')
            if data and getattr(conn.msgdef.format, 'name', '') == 'MSG':
                store.register(get_types_from_msg(data, conn.msgtype))
        for conn, _t, raw in reader.messages():
            store.deserialize_cdr(raw, conn.msgtype)
            n += 1
    return n


if __name__ == '__main__':
    kind, path = sys.argv[1], sys.argv[2]
    print((read_rosbag if kind == 'rosbag' else read_rosbags)(path))
