"""The bag data source: replays a recorded bag through the same SensorRuns, with no master.

Time is the bag's record time: the runner's clock is a virtual clock that this source advances
by one tick per loop, feeding every message recorded up to that moment. Rates and delays are
therefore measured from the recorded times, exactly as they were on the robot.
"""
import os

from .settings import ConfigError


class BagSource:
    live = False

    def __init__(self, path):
        import rosbag
        if not os.path.exists(path):
            raise ConfigError('bag file not found', path, fix='give --bag an existing .bag file')
        try:
            bag = rosbag.Bag(path)
        except Exception as e:  # ROSBagException, unindexed or foreign files
            raise ConfigError('cannot open the bag: %s' % e, path,
                              fix='check it is a ROS 1 bag (rosbag info %s); reindex with '
                                  '"rosbag reindex" if it was not closed' % path)
        with bag:
            info = bag.get_type_and_topic_info()
            self.types = {t: v.msg_type for t, v in info.topics.items()}
            # raw = (type, bytes, md5sum, position, class generated from the connection's
            # definition): a type whose package is not installed is still decoded
            conns = {}
            self.messages = []
            for topic, raw, t in bag.read_messages(raw=True):
                conn = conns.get((raw[0], raw[2]))
                if conn is None:
                    conn = conns[(raw[0], raw[2])] = {
                        'type': raw[0], 'md5sum': raw[2],
                        'message_definition': getattr(raw[4], '_full_text', None)}
                self.messages.append((t.to_sec(), topic, raw[0], raw[1], conn))
            self.begin = bag.get_start_time() if self.messages else 0.0
            self.end = bag.get_end_time() if self.messages else 0.0
        self.messages.sort(key=lambda m: m[0])
        self.path = path
        self.now = self.begin
        self._next = 0
        self.runs = {}

    @property
    def length(self):
        return self.end - self.begin

    def clock(self):
        return self.now

    def attach(self, run):
        run.stats.clock = 'record'    # rates on the bag's record times (stats.py)
        self.runs.setdefault(run.plan.topic, []).append(run)

    def detach(self, run):
        runs = self.runs.get(run.plan.topic, [])
        if run in runs:
            runs.remove(run)

    def poll(self, run, now):
        pass

    def lookup(self, topic):
        t = self.types.get(topic)
        return (t, ['the bag']) if t else (None, None)

    def sleep(self, dt):
        self.now += dt
        msgs = self.messages
        while self._next < len(msgs) and msgs[self._next][0] <= self.now:
            t, topic, type_name, data, conn = msgs[self._next]
            self._next += 1
            for run in self.runs.get(topic, ()):
                run.feed_raw(type_name, data, t, t, conn)
