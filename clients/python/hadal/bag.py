"""hadal.bag: read a rosbag2 bag that hadald --record or hadal-record wrote (sqlite3 storage), its messages
decoded into the values the client's readers give (hadal.Odometry, hadal.Imu, ...), with no ROS 2.

    from hadal.bag import Bag
    with Bag("runs/survey") as bag:
        print(bag.topics)                                  # {"/auv/odometry": "nav_msgs/msg/Odometry", ...}
        for t_s, odometry in bag.messages("/auv/odometry"):
            print(t_s, odometry.p_WB)

Times are the bag's: sim time for hadald --record and hadal-record --use-sim-time [s]. Images and sonar images
are not decoded (hadal.decodable_message_types() lists what is); Bag.raw gives any topic's CDR bytes.
"""

import glob
import os
import sqlite3

from ._hadal import decodable_message_types, decode_message


class Bag:
    """A rosbag2 bag directory (BAG_DIR/metadata.yaml and BAG_DIR/*.db3), opened read-only."""

    def __init__(self, path):
        self.path = os.fspath(path)
        databases = sorted(glob.glob(os.path.join(self.path, "*.db3")))
        if not os.path.isdir(self.path) or not databases:
            raise FileNotFoundError(f"{self.path}: not a rosbag2 bag with sqlite3 storage (no *.db3 in it)")
        self._connections = [sqlite3.connect(f"file:{database}?mode=ro", uri=True) for database in databases]
        self.topics = {}
        for connection in self._connections:
            for name, type_name in connection.execute("SELECT name, type FROM topics ORDER BY id"):
                self.topics[name] = type_name

    def _type(self, topic):
        if topic not in self.topics:
            raise KeyError(f"{self.path}: no topic {topic!r} (its topics: {', '.join(sorted(self.topics))})")
        return self.topics[topic]

    def raw(self, topic):
        """[(bag time [ns], CDR bytes)] of a topic, in time order."""
        self._type(topic)
        out = []
        for connection in self._connections:
            out += connection.execute(
                "SELECT m.timestamp, m.data FROM messages m JOIN topics t ON m.topic_id = t.id WHERE t.name = ? "
                "ORDER BY m.timestamp, m.id", (topic,)).fetchall()
        out.sort(key=lambda row: row[0])
        return [(int(t), bytes(data)) for t, data in out]

    def messages(self, topic):
        """[(bag time [s], message)] of a topic, decoded (hadal.decode_message), in time order."""
        type_name = self._type(topic)
        if type_name not in decodable_message_types():
            raise ValueError(f"{topic} is {type_name}, which hadal.bag does not decode (Bag.raw gives its bytes)")
        return [(t * 1e-9, decode_message(type_name, data)) for t, data in self.raw(topic)]

    def count(self, topic):
        return len(self.raw(topic))

    def close(self):
        for connection in self._connections:
            connection.close()
        self._connections = []

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False
