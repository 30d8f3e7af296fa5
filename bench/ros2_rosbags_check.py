"""Do Cyclone DDS's CDR bytes equal rosbags' for the same ROS 2 message, and does a rosbag2 MCAP bag written
from them read back message for message?  No network.  Needs the optional cyclonedds and rosbags.

    .venv/bin/python bench/ros2_rosbags_check.py [DIR]
"""

import math
import sys
import tempfile
from pathlib import Path

from rosbags.rosbag2 import Reader, StoragePlugin, Writer
from rosbags.typesys import Stores, get_typestore

from turtlectl.messages import LaserScan, Pose, Twist
from turtlectl.nodes import ros2_mapping as m


def main() -> int:
    store = get_typestore(Stores.ROS2_KILTED)
    scan = LaserScan(
        angle_min=-math.pi,
        angle_max=math.pi,
        angle_increment=math.pi / 2,
        range_min=0.1,
        range_max=4.0,
        ranges=[1.0, math.inf, 2.5, 0.5],
        stamp=1_700_000_000_123_456_789,
    )
    messages = [
        ("/turtle1/cmd_vel", "geometry_msgs/msg/Twist", m.twist_to_ros(Twist(linear=1.5, angular=-0.25))),
        ("/odom", "nav_msgs/msg/Odometry", m.pose_to_odometry(Pose(x=1.0, y=2.0, theta=0.5, stamp=5))),
        ("/obstacles", "sensor_msgs/msg/LaserScan", m.scan_to_ros(scan)),
    ]
    same = {}
    for _topic, ros_type, ros in messages:
        cyclone = ros.serialize()
        # rosbags' own message built from the same bytes, serialized again by rosbags
        theirs = store.serialize_cdr(store.deserialize_cdr(cyclone, ros_type), ros_type)
        same[ros_type] = bytes(theirs) == cyclone
    print("cyclone bytes == rosbags bytes:", same)
    out = Path(sys.argv[1] if len(sys.argv) > 1 else tempfile.mkdtemp()) / "bag"
    with Writer(out, version=9, storage_plugin=StoragePlugin.MCAP) as writer:
        conns = {t: writer.add_connection(t, ros_type, typestore=store) for t, ros_type, _ in messages}
        for i, (topic, _ros_type, ros) in enumerate(messages):
            writer.write(conns[topic], 1_700_000_000_000_000_000 + i, ros.serialize())
    with Reader(out) as reader:
        read = [(c.topic, c.msgtype, raw) for c, _t, raw in reader.messages()]
        print("storage:", sorted(p.name for p in out.iterdir()), "messages:", reader.message_count)
    ok = [bytes(raw) == ros.serialize() for (_t, _ty, raw), (_t2, _ty2, ros) in zip(read, messages, strict=True)]
    print("read back equal:", ok)
    return 0 if all(same.values()) and all(ok) else 1


if __name__ == "__main__":
    sys.exit(main())
