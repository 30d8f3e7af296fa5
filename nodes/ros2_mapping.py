"""turtlectl's messages as their ROS 2 counterparts, and back: plain functions, no network.

Each function maps one turtlectl Struct (turtlectl.messages) to one ROS 2 type of
turtlectl.nodes.ros2_types, or the reverse, with the units and frames ROS expects (REP 103: SI units,
x forward, z up, yaw counter-clockwise; REP 105 frame names).  What does not fit the ROS type is
said in each docstring.

Stamps: turtlectl's ``stamp`` is ns since the Unix epoch (the wall clock, or the simulated clock);
ROS's ``builtin_interfaces/Time`` is the same instant as (sec, nanosec).
"""

import functools
import math
from collections.abc import Callable
from typing import Any

from turtlectl.messages import Clock, LaserScan, Log, Message, Pose, String, TurtleStatus, Twist
from turtlectl.nodes import ros2_dynamic, ros2_generic
from turtlectl.nodes import ros2_types as r

#: tf frames the bridge names by default: the world is ``odom`` (turtlesim's world is fixed, so odom
#: and map coincide); a turtle's body is ``<turtle>/base_link``, its scanner ``<turtle>/base_scan``
WORLD_FRAME = "odom"


def ns_to_time(ns: int) -> r.Time:
    """ns since the epoch -> builtin_interfaces/Time (sec, nanosec in [0, 1e9)); negative ns floor."""
    sec, nanosec = divmod(int(ns), 1_000_000_000)
    return r.Time(sec=sec, nanosec=nanosec)


def time_to_ns(t: r.Time) -> int:
    """builtin_interfaces/Time -> ns since the epoch."""
    return t.sec * 1_000_000_000 + t.nanosec


def twist_to_ros(msg: Twist) -> r.Twist:
    """turtlectl Twist -> geometry_msgs/Twist: linear.x m/s forward, angular.z rad/s CCW; stamp and seq
    have no place in a Twist (it has no header) and are dropped."""
    return r.Twist(linear=r.Vector3(x=msg.linear), angular=r.Vector3(z=msg.angular))


def twist_from_ros(msg: r.Twist, stamp: int = 0, seq: int = 0) -> Twist:
    """geometry_msgs/Twist -> turtlectl Twist, as turtlesim reads it: linear.x and angular.z only (a
    unicycle ignores linear.y/z and angular.x/y).  stamp: when the bridge received it, ns."""
    return Twist(linear=float(msg.linear.x), angular=float(msg.angular.z), stamp=stamp, seq=seq)


def pose_to_turtlesim(msg: Pose) -> r.TurtlesimPose:
    """turtlectl Pose -> turtlesim/msg/Pose (float32: ~1e-6 m resolution at 10 m); contact, stamp and
    seq have no place in it and are dropped."""
    return r.TurtlesimPose(
        x=msg.x,
        y=msg.y,
        theta=msg.theta,
        linear_velocity=msg.linear_velocity,
        angular_velocity=msg.angular_velocity,
    )


def pose_from_turtlesim(msg: r.TurtlesimPose, stamp: int = 0, seq: int = 0) -> Pose:
    """turtlesim/msg/Pose -> turtlectl Pose (values widened from float32)."""
    return Pose(
        x=float(msg.x),
        y=float(msg.y),
        theta=float(msg.theta),
        linear_velocity=float(msg.linear_velocity),
        angular_velocity=float(msg.angular_velocity),
        stamp=stamp,
        seq=seq,
    )


def pose_to_pose2d(msg: Pose) -> r.Pose2D:
    """turtlectl Pose -> geometry_msgs/Pose2D (x, y m; theta rad): what a pip-installed rclpy can import."""
    return r.Pose2D(x=msg.x, y=msg.y, theta=msg.theta)


def yaw_to_quaternion(yaw: float) -> r.Quaternion:
    """A rotation of ``yaw`` rad about +z as a unit quaternion."""
    return r.Quaternion(z=math.sin(yaw / 2), w=math.cos(yaw / 2))


def quaternion_to_yaw(q: r.Quaternion) -> float:
    """The yaw (rad, (-pi, pi]) of a quaternion, ignoring roll and pitch."""
    return math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))


def pose_to_odometry(msg: Pose, turtle: str = "turtle1", world_frame: str = WORLD_FRAME) -> r.Odometry:
    """turtlectl Pose -> nav_msgs/Odometry: pose in ``world_frame``, twist in ``<turtle>/base_link``
    (linear.x m/s, angular.z rad/s); covariances zero (the simulator's pose is exact)."""
    return r.Odometry(
        header=r.Header(stamp=ns_to_time(msg.stamp), frame_id=world_frame),
        child_frame_id=f"{turtle}/base_link",
        pose=r.PoseWithCovariance(
            pose=r.Pose(position=r.Point(x=msg.x, y=msg.y), orientation=yaw_to_quaternion(msg.theta))
        ),
        twist=r.TwistWithCovariance(
            twist=r.Twist(linear=r.Vector3(x=msg.linear_velocity), angular=r.Vector3(z=msg.angular_velocity))
        ),
    )


def scan_to_ros(msg: LaserScan, turtle: str = "turtle1") -> r.LaserScan:
    """turtlectl LaserScan -> sensor_msgs/LaserScan in ``<turtle>/base_scan``; ranges become float32
    (``inf`` stays ``inf``, REP 117), intensities empty, time_increment and scan_time 0 (the simulated
    scan is instantaneous).  origin_x/y/theta have no place in it: ROS gets them from tf."""
    return r.LaserScan(
        header=r.Header(stamp=ns_to_time(msg.stamp), frame_id=f"{turtle}/base_scan"),
        angle_min=msg.angle_min,
        angle_max=msg.angle_max,
        angle_increment=msg.angle_increment,
        range_min=msg.range_min,
        range_max=msg.range_max,
        ranges=list(msg.ranges),
    )


def scan_from_ros(msg: r.LaserScan, seq: int = 0) -> LaserScan:
    """sensor_msgs/LaserScan -> turtlectl LaserScan (origin unknown: NaN; stamp from the header)."""
    return LaserScan(
        angle_min=float(msg.angle_min),
        angle_max=float(msg.angle_max),
        angle_increment=float(msg.angle_increment),
        range_min=float(msg.range_min),
        range_max=float(msg.range_max),
        ranges=[float(x) for x in msg.ranges],
        stamp=time_to_ns(msg.header.stamp),
        seq=seq,
    )


def status_to_ros(msg: TurtleStatus) -> r.TurtleStatus:
    """turtlectl TurtleStatus -> capstone_msgs/msg/TurtleStatus, field for field (theta in degrees)."""
    return r.TurtleStatus(x=msg.x, y=msg.y, theta=msg.theta, vel_x=msg.vel_x, vel_y=msg.vel_y, battery=msg.battery)


def status_from_ros(msg: r.TurtleStatus, stamp: int = 0, seq: int = 0) -> TurtleStatus:
    """capstone_msgs/msg/TurtleStatus -> turtlectl TurtleStatus."""
    return TurtleStatus(
        x=msg.x, y=msg.y, theta=msg.theta, vel_x=msg.vel_x, vel_y=msg.vel_y, battery=msg.battery, stamp=stamp, seq=seq
    )


def clock_to_ros(msg: Clock) -> r.Clock:
    """turtlectl Clock -> rosgraph_msgs/Clock (real_time_factor has no place in it)."""
    return r.Clock(clock=ns_to_time(msg.clock))


def log_to_ros(msg: Log) -> r.Log:
    """turtlectl Log -> rcl_interfaces/Log for ``/rosout``.  Python's levels are ROS's numbers (10 DEBUG,
    20 INFO, 30 WARN, 40 ERROR, 50 FATAL); a custom level between two rounds down to one of them.
    name: the node's name with ``/`` as ROS loggers use ``.`` (``turtle2/navigator`` -> ``turtle2.navigator``)."""
    level = max(10, min(50, msg.level - msg.level % 10))
    return r.Log(
        stamp=ns_to_time(msg.stamp),
        level=level,
        name=msg.node.replace("/", "."),
        msg=msg.message,
        file=msg.file,
        function=msg.function,
        line=max(0, msg.line),
    )


def clock_from_ros(msg: r.Clock) -> Clock:
    """rosgraph_msgs/Clock -> turtlectl Clock, stamped at the clock's own time (as the simulator stamps it)."""
    ns = time_to_ns(msg.clock)
    return Clock(clock=ns, stamp=ns)


def log_from_ros(msg: r.Log) -> Log:
    """rcl_interfaces/Log -> turtlectl Log: the logger's ``.`` back to ``/`` in the node's name."""
    return Log(
        level=int(msg.level),
        node=str(msg.name).replace(".", "/"),
        message=str(msg.msg),
        file=str(msg.file),
        function=str(msg.function),
        line=int(msg.line),
        stamp=time_to_ns(msg.stamp),
    )


def string_to_ros(msg: String) -> r.String:
    """turtlectl String -> std_msgs/String (stamp and seq have no place in it)."""
    return r.String(data=msg.data)


def string_from_ros(msg: r.String, stamp: int = 0, seq: int = 0) -> String:
    """std_msgs/String -> turtlectl String; stamp: when the bridge received it, ns."""
    return String(data=msg.data, stamp=stamp, seq=seq)


def _pose_from_turtlesim(msg: r.TurtlesimPose, stamp: int) -> Pose:
    return pose_from_turtlesim(msg, stamp=stamp)


def _scan_from_ros(msg: r.LaserScan, stamp: int) -> LaserScan:
    return scan_from_ros(msg)


#: ROS 2 type -> (turtlectl type read on the key, its ROS type, ``convert(msg, turtle)``): what the
#: bridge writes to ROS.  turtle: the turtle the row is about (frame ids).  Keys: nodes.ros2_table.ROS_TYPES'
TO_ROS: dict[str, tuple[type[Message], type, Callable[[Any, str], Any]]] = {
    "geometry_msgs/msg/Twist": (Twist, r.Twist, lambda m, _t: twist_to_ros(m)),
    "turtlesim/msg/Pose": (Pose, r.TurtlesimPose, lambda m, _t: pose_to_turtlesim(m)),
    "nav_msgs/msg/Odometry": (Pose, r.Odometry, lambda m, t: pose_to_odometry(m, t)),
    "geometry_msgs/msg/Pose2D": (Pose, r.Pose2D, lambda m, _t: pose_to_pose2d(m)),
    "sensor_msgs/msg/LaserScan": (LaserScan, r.LaserScan, lambda m, t: scan_to_ros(m, t)),
    "capstone_msgs/msg/TurtleStatus": (TurtleStatus, r.TurtleStatus, lambda m, _t: status_to_ros(m)),
    "rosgraph_msgs/msg/Clock": (Clock, r.Clock, lambda m, _t: clock_to_ros(m)),
    "rcl_interfaces/msg/Log": (Log, r.Log, lambda m, _t: log_to_ros(m)),
    "std_msgs/msg/String": (String, r.String, lambda m, _t: string_to_ros(m)),
}

#: ROS 2 type -> (its ROS type, the turtlectl type published on the key, ``convert(msg, stamp_ns)``):
#: what the bridge reads from ROS.  stamp_ns: when it was received (the publisher restamps it)
FROM_ROS: dict[str, tuple[type, type[Message], Callable[[Any, int], Message]]] = {
    "geometry_msgs/msg/Twist": (r.Twist, Twist, lambda m, ns: twist_from_ros(m, stamp=ns)),
    "turtlesim/msg/Pose": (r.TurtlesimPose, Pose, _pose_from_turtlesim),
    "sensor_msgs/msg/LaserScan": (r.LaserScan, LaserScan, _scan_from_ros),
    "capstone_msgs/msg/TurtleStatus": (r.TurtleStatus, TurtleStatus, lambda m, ns: status_from_ros(m, stamp=ns)),
    "std_msgs/msg/String": (r.String, String, lambda m, ns: string_from_ros(m, stamp=ns)),
}


@functools.cache
def to_ros_of(ros_type: str) -> tuple[type[Message], type, Callable[[Any, str], Any]]:
    """What the bridge writes to ROS for a row of ``ros_type``: TO_ROS's, or a user's own flat type's
    generic struct (nodes.ros2_dynamic)."""
    known = TO_ROS.get(ros_type)
    if known is not None:
        return known
    cls = _user(ros_type)
    return cls, ros2_dynamic.idl_struct(cls), lambda m, _t: ros2_dynamic.to_ros(m)


@functools.cache
def from_ros_of(ros_type: str) -> tuple[type, type[Message], Callable[[Any, int], Message]]:
    """What the bridge reads from ROS for a row of ``ros_type``: FROM_ROS's, or a user's own flat
    type's (its publisher stamps it, if it has ``stamp`` and ``seq``)."""
    known = FROM_ROS.get(ros_type)
    if known is not None:
        return known
    cls = _user(ros_type)
    return ros2_dynamic.idl_struct(cls), cls, lambda m, _ns: ros2_dynamic.from_ros(m, cls)


def _user(ros_type: str) -> type[Message]:
    cls = ros2_generic.user_type(ros_type)
    if cls is None:
        raise ValueError(f"unknown ROS type {ros_type!r}")
    return cls
