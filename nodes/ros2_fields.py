"""turtlectl's messages as plain ROS 2 field values, and back: plain functions, no network, no ROS library.

``to_ros`` gives the ROS 2 type (turtlectl.nodes.ros2_profile) and the message's fields as nested
dicts in that type's field names and units (REP 103: SI units, yaw counter-clockwise; REP 105 frame
names), for any library to build its own message from (rosbags, a DDS binding).  ``from_ros`` reads
a ROS 2 message back from any object with those fields as attributes (rosbags' and cyclonedds'
messages both are).  What a ROS type has no place for is dropped, as each function says.

Stamps: turtlectl's ``stamp`` is ns since the Unix epoch; ROS's ``builtin_interfaces/Time`` is the
same instant as ``{sec, nanosec}``.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from turtlectl.messages import Clock, LaserScan, Log, Message, Pose, TurtleStatus, Twist
from turtlectl.messages.codec import type_name
from turtlectl.nodes.ros2_profile import BY_ROS, BY_TURTLECTL

#: the world's frame, and a turtle's scanner frame ``<turtle>/base_scan`` (as the bridge names them)
WORLD_FRAME = "odom"


def time_of(ns: int) -> dict[str, int]:
    """ns since the epoch -> builtin_interfaces/Time (nanosec in [0, 1e9); negative ns floor)."""
    sec, nanosec = divmod(int(ns), 1_000_000_000)
    return {"sec": sec, "nanosec": nanosec}


def ns_of(t: Any) -> int:
    """builtin_interfaces/Time -> ns since the epoch."""
    return int(t.sec) * 1_000_000_000 + int(t.nanosec)


def _twist(msg: Twist, key: str) -> dict:
    """linear.x m/s forward, angular.z rad/s CCW; stamp and seq dropped (a Twist has no header)."""
    return {"linear": {"x": msg.linear, "y": 0.0, "z": 0.0}, "angular": {"x": 0.0, "y": 0.0, "z": msg.angular}}


def _pose(msg: Pose, key: str) -> dict:
    """turtlesim/msg/Pose (float32); contact, stamp and seq dropped."""
    return {
        "x": msg.x,
        "y": msg.y,
        "theta": msg.theta,
        "linear_velocity": msg.linear_velocity,
        "angular_velocity": msg.angular_velocity,
    }


def _scan(msg: LaserScan, key: str) -> dict:
    """sensor_msgs/LaserScan in ``<turtle>/base_scan`` (the key's first part: ``turtle2/obstacles`` ->
    ``turtle2``, else ``turtle1``); ranges float32 (``inf`` stays), intensities empty, time_increment
    and scan_time 0; origin_x/y/theta dropped (ROS gets them from tf)."""
    first, sep, _ = key.lstrip("/").partition("/")
    turtle = first if sep and first.startswith("turtle") else "turtle1"
    return {
        "header": {"stamp": time_of(msg.stamp), "frame_id": f"{turtle}/base_scan"},
        "angle_min": msg.angle_min,
        "angle_max": msg.angle_max,
        "angle_increment": msg.angle_increment,
        "time_increment": 0.0,
        "scan_time": 0.0,
        "range_min": msg.range_min,
        "range_max": msg.range_max,
        "ranges": list(msg.ranges),
        "intensities": [],
    }


def _status(msg: TurtleStatus, key: str) -> dict:
    """capstone_msgs/msg/TurtleStatus field for field (theta in degrees); stamp and seq dropped."""
    return {"x": msg.x, "y": msg.y, "theta": msg.theta, "vel_x": msg.vel_x, "vel_y": msg.vel_y, "battery": msg.battery}


def _clock(msg: Clock, key: str) -> dict:
    """rosgraph_msgs/Clock; real_time_factor dropped."""
    return {"clock": time_of(msg.clock)}


def _log(msg: Log, key: str) -> dict:
    """rcl_interfaces/Log: Python's levels are ROS's numbers (a custom level rounds down to one);
    the node's name with ``.`` for ``/`` as ROS loggers write it."""
    return {
        "stamp": time_of(msg.stamp),
        "level": max(10, min(50, msg.level - msg.level % 10)),
        "name": msg.node.replace("/", "."),
        "msg": msg.message,
        "file": msg.file,
        "function": msg.function,
        "line": max(0, msg.line),
    }


_TO: dict[str, Callable[[Any, str], dict]] = {
    "turtlectl/Twist": _twist,
    "turtlectl/Pose": _pose,
    "turtlectl/LaserScan": _scan,
    "turtlectl/TurtleStatus": _status,
    "turtlectl/Clock": _clock,
    "turtlectl/Log": _log,
}


def to_ros(message: Message, key: str = "") -> tuple[str, dict] | None:
    """(ROS 2 type, its fields as nested dicts) of ``message`` published on ``key``; None for a type
    the table (turtlectl.nodes.ros2_profile) does not map."""
    name = type_name(type(message))
    row, convert = BY_TURTLECTL.get(name), _TO.get(name)
    if row is None or convert is None:
        return None
    return row.ros, convert(message, key)


def _from_twist(m: Any) -> Twist:
    """As turtlesim reads a Twist: linear.x and angular.z (a unicycle ignores the rest)."""
    return Twist(linear=float(m.linear.x), angular=float(m.angular.z))


def _from_pose(m: Any) -> Pose:
    return Pose(
        x=float(m.x),
        y=float(m.y),
        theta=float(m.theta),
        linear_velocity=float(m.linear_velocity),
        angular_velocity=float(m.angular_velocity),
    )


def _from_scan(m: Any) -> LaserScan:
    """Origin unknown (NaN); stamp from the header."""
    return LaserScan(
        angle_min=float(m.angle_min),
        angle_max=float(m.angle_max),
        angle_increment=float(m.angle_increment),
        range_min=float(m.range_min),
        range_max=float(m.range_max),
        ranges=[float(x) for x in m.ranges],
        stamp=ns_of(m.header.stamp),
    )


def _from_status(m: Any) -> TurtleStatus:
    return TurtleStatus(
        x=float(m.x),
        y=float(m.y),
        theta=float(m.theta),
        vel_x=float(m.vel_x),
        vel_y=float(m.vel_y),
        battery=float(m.battery),
    )


def _from_clock(m: Any) -> Clock:
    ns = ns_of(m.clock)
    return Clock(clock=ns, stamp=ns)


def _from_log(m: Any) -> Log:
    """The logger's ``.`` back to ``/`` in the node's name."""
    return Log(
        level=int(m.level),
        node=str(m.name).replace(".", "/"),
        message=str(m.msg),
        file=str(m.file),
        function=str(m.function),
        line=int(m.line),
        stamp=ns_of(m.stamp),
    )


_FROM: dict[str, Callable[[Any], Message]] = {
    "geometry_msgs/msg/Twist": _from_twist,
    "turtlesim/msg/Pose": _from_pose,
    "sensor_msgs/msg/LaserScan": _from_scan,
    "capstone_msgs/msg/TurtleStatus": _from_status,
    "rosgraph_msgs/msg/Clock": _from_clock,
    "rcl_interfaces/msg/Log": _from_log,
}


def readable(ros_type: str) -> bool:
    """Whether ``from_ros`` reads ``ros_type`` (a row of the table)."""
    return ros_type in BY_ROS and ros_type in _FROM


def from_ros(ros_type: str, message: Any) -> Message | None:
    """The turtlectl message a ROS 2 message of ``ros_type`` is (stamp 0 unless the ROS type has one,
    seq 0); None for a type the table does not map."""
    convert = _FROM.get(ros_type) if ros_type in BY_ROS else None
    return None if convert is None else convert(message)
