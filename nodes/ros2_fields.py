"""turtlectl's messages as plain ROS 2 field values, and back, for a ROS library other than the
bridge's DDS binding (rosbags, for ROS 2 bags).

The conversions are the bridge's own (turtlectl.nodes.ros2_mapping: units, frames, what each ROS type
has no place for), so a bag and the bridge say the same thing: ``to_ros`` gives the ROS 2 type of
the table (turtlectl.nodes.ros2_profile) and the converted message as nested dicts in that type's
field names; ``from_ros`` reads a ROS 2 message back from any object with those fields as
attributes (rosbags' and cyclonedds' messages both are).  Both load ros2_mapping, and with it the
Cyclone DDS type declarations (the ``ros2`` extra), when first called; ``readable`` loads nothing.
"""

from __future__ import annotations

import dataclasses
from typing import Any

from turtlectl.messages import Message
from turtlectl.messages.codec import type_name
from turtlectl.nodes.ros2_profile import BY_ROS, BY_TURTLECTL
from turtlectl.nodes.ros2_table import turtle_of_key

#: the ROS types ``from_ros`` reads: those of the table (ros2_profile.TABLE), each one's
#: ros2_mapping function named
_FROM_NAMES: dict[str, str] = {
    "geometry_msgs/msg/Twist": "twist_from_ros",
    "turtlesim/msg/Pose": "pose_from_turtlesim",
    "sensor_msgs/msg/LaserScan": "scan_from_ros",
    "capstone_msgs/msg/TurtleStatus": "status_from_ros",
    "rosgraph_msgs/msg/Clock": "clock_from_ros",
    "rcl_interfaces/msg/Log": "log_from_ros",
}


def to_ros(message: Message, key: str = "") -> tuple[str, dict] | None:
    """(ROS 2 type, its fields as nested dicts) of ``message`` published on ``key`` (whose turtle names
    the frames: ``turtle2/obstacles`` is in ``turtle2/base_scan``); None for a type the table does not map."""
    row = BY_TURTLECTL.get(type_name(type(message)))
    if row is None:
        return None
    from turtlectl.nodes.ros2_mapping import TO_ROS

    convert = TO_ROS[row.ros][2]
    return row.ros, dataclasses.asdict(convert(message, turtle_of_key(key.lstrip("/"))))


def readable(ros_type: str) -> bool:
    """Whether ``from_ros`` reads ``ros_type`` (a row of the table)."""
    return ros_type in BY_ROS and ros_type in _FROM_NAMES


def from_ros(ros_type: str, message: Any) -> Message | None:
    """The turtlectl message a ROS 2 message of ``ros_type`` is (stamp from its header or its own time
    where the ROS type has one, else 0; seq 0); None for a type the table does not map."""
    if not readable(ros_type):
        return None
    from turtlectl.nodes import ros2_mapping

    return getattr(ros2_mapping, _FROM_NAMES[ros_type])(message)
