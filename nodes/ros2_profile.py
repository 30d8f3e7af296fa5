"""Which ROS 2 type each turtlectl type is in ROS 2 (a recording in rosbag2's profile, a bridge): the one table.

Pure data, no network, no ROS library.  A key becomes a ROS topic by a leading ``/``
(``turtle1/pose`` -> ``/turtle1/pose``; ``ros_topic``), and a ROS topic a key by dropping it.  Each entry also
gives the QoS a ROS publisher of that topic would offer (as rosbag2 records it per topic):
rclpy's default (reliable, volatile, keep last 10), and for the log stream rcl's ``/rosout``
profile (reliable, transient local, keep last 1000).
"""

from __future__ import annotations

import dataclasses
import re

#: the ROS 2 distribution whose message definitions the ROS types below follow
ROS_DISTRO = "kilted"


@dataclasses.dataclass(frozen=True)
class Qos:
    """A ROS 2 QoS profile as rosbag2 stores it (``offered_qos_profiles``)."""

    reliable: bool = True  # False: best effort
    transient_local: bool = False  # False: volatile
    depth: int = 10  # keep last ``depth``


DEFAULT_QOS = Qos()
ROSOUT_QOS = Qos(transient_local=True, depth=1000)


@dataclasses.dataclass(frozen=True)
class RosType:
    """One row of the table: turtlectl's type name and the ROS 2 type it is in ROS."""

    turtlectl: str  # "turtlectl/Twist"
    ros: str  # "geometry_msgs/msg/Twist"
    qos: Qos = DEFAULT_QOS


#: turtlectl type -> ROS 2 type, one row each; what does not fit each ROS type is said in
#: turtlectl.nodes.ros2_fields
TABLE: tuple[RosType, ...] = (
    RosType("turtlectl/Twist", "geometry_msgs/msg/Twist"),
    RosType("turtlectl/Pose", "turtlesim/msg/Pose"),
    RosType("turtlectl/LaserScan", "sensor_msgs/msg/LaserScan"),
    RosType("turtlectl/TurtleStatus", "capstone_msgs/msg/TurtleStatus"),
    RosType("turtlectl/Clock", "rosgraph_msgs/msg/Clock"),
    RosType("turtlectl/Log", "rcl_interfaces/msg/Log", ROSOUT_QOS),
)

BY_TURTLECTL = {row.turtlectl: row for row in TABLE}
BY_ROS = {row.ros: row for row in TABLE}


def ros_topic(key: str) -> str:
    """A turtlectl key as a ROS topic name: ``turtle1/pose`` -> ``/turtle1/pose``; a character a ROS
    name cannot hold (``.``, ``-``) becomes ``_`` (``turtlectl/log/turtle2.navigator`` ->
    ``/turtlectl/log/turtle2_navigator``)."""
    name = key if key.startswith("/") else "/" + key
    return re.sub(r"[^A-Za-z0-9_/]", "_", name)


def key_of(topic: str) -> str:
    """A ROS topic name as a turtlectl key: ``/turtle1/pose`` -> ``turtle1/pose``."""
    return topic[1:] if topic.startswith("/") and len(topic) > 1 else topic
