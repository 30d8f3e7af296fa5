"""ROS 2 message types as DDS sees them, for Eclipse Cyclone DDS's Python binding (``cyclonedds``).

A ROS 2 node built on Fast DDS (the ``rmw_fastrtps_cpp`` of the pip-installed rclpy wheels) matches a
Cyclone DDS reader or writer when, and only when:

* the DDS topic is ``rt/`` + the ROS topic without its leading slash (``/turtle1/cmd_vel`` is
  ``rt/turtle1/cmd_vel``): :func:`dds_topic`;
* the DDS type name is ``<package>::msg::dds_::<Name>_`` (``geometry_msgs::msg::dds_::Twist_``):
  each class below names it with ``typename=``;
* the struct is keyless and final, its fields in the ``.msg`` order, each of the ``.msg`` type
  (``float32`` is :data:`t.float32`, ``float64`` is :data:`t.float64`, ``T[]`` a sequence,
  ``T[36]`` an array), encoded as XCDR1 (plain CDR): :data:`XCDR1`, in the writer's and reader's QoS;
* the Cyclone participant ignores Fast DDS's XTypes type information
  (``<Compatibility><IgnoreTypeInformation>1.15</IgnoreTypeInformation>``, 1.15 being eProsima's
  vendor id): without it, no type holding a sequence (``LaserScan``) ever matches.

This module declares types only: importing it opens no socket (it does load the Cyclone DDS C library,
~0.35 s, so import it lazily, never on a command's start-up path).
"""

# no `from __future__ import annotations`: cyclonedds reads the field types at run time and cannot
# resolve them as strings (`t.float32`)

from dataclasses import dataclass, field

import cyclonedds.idl.types as t
from cyclonedds.idl import IdlStruct
from cyclonedds.idl.annotations import final
from cyclonedds.qos import Policy

#: the data representation a ROS 2 (Fast DDS) peer expects: XCDR1, classic CDR
XCDR1 = Policy.DataRepresentation(use_cdrv0_representation=True)


def dds_topic(ros_topic: str) -> str:
    """The DDS topic of a ROS 2 topic: ``/turtle1/cmd_vel`` -> ``rt/turtle1/cmd_vel``."""
    return "rt/" + ros_topic.lstrip("/")


def dds_type_name(ros_type: str) -> str:
    """The DDS type name of a ROS 2 type: ``geometry_msgs/msg/Twist`` -> ``geometry_msgs::msg::dds_::Twist_``."""
    package, kind, name = ros_type.split("/")
    return f"{package}::{kind}::dds_::{name}_"


# builtin_interfaces


@dataclass
@final
class Time(IdlStruct, typename="builtin_interfaces::msg::dds_::Time_"):
    """builtin_interfaces/msg/Time: sec (s, int32) and nanosec (ns, uint32, [0, 1e9))."""

    sec: t.int32 = 0
    nanosec: t.uint32 = 0


# std_msgs


@dataclass
@final
class Header(IdlStruct, typename="std_msgs::msg::dds_::Header_"):
    """std_msgs/msg/Header: when (stamp) and in which tf frame (frame_id) the data holds."""

    stamp: Time = field(default_factory=Time)
    frame_id: str = ""


@dataclass
@final
class String(IdlStruct, typename="std_msgs::msg::dds_::String_"):
    """std_msgs/msg/String."""

    data: str = ""


# geometry_msgs


@dataclass
@final
class Vector3(IdlStruct, typename="geometry_msgs::msg::dds_::Vector3_"):
    """geometry_msgs/msg/Vector3 (float64 x, y, z)."""

    x: t.float64 = 0.0
    y: t.float64 = 0.0
    z: t.float64 = 0.0


@dataclass
@final
class Twist(IdlStruct, typename="geometry_msgs::msg::dds_::Twist_"):
    """geometry_msgs/msg/Twist: linear m/s, angular rad/s, in the robot's frame."""

    linear: Vector3 = field(default_factory=Vector3)
    angular: Vector3 = field(default_factory=Vector3)


@dataclass
@final
class Point(IdlStruct, typename="geometry_msgs::msg::dds_::Point_"):
    """geometry_msgs/msg/Point (m)."""

    x: t.float64 = 0.0
    y: t.float64 = 0.0
    z: t.float64 = 0.0


@dataclass
@final
class Quaternion(IdlStruct, typename="geometry_msgs::msg::dds_::Quaternion_"):
    """geometry_msgs/msg/Quaternion; the identity by default."""

    x: t.float64 = 0.0
    y: t.float64 = 0.0
    z: t.float64 = 0.0
    w: t.float64 = 1.0


@dataclass
@final
class Pose(IdlStruct, typename="geometry_msgs::msg::dds_::Pose_"):
    """geometry_msgs/msg/Pose."""

    position: Point = field(default_factory=Point)
    orientation: Quaternion = field(default_factory=Quaternion)


@dataclass
@final
class Pose2D(IdlStruct, typename="geometry_msgs::msg::dds_::Pose2D_"):
    """geometry_msgs/msg/Pose2D: x, y in m, theta in rad."""

    x: t.float64 = 0.0
    y: t.float64 = 0.0
    theta: t.float64 = 0.0


def _zeros36() -> list[float]:
    return [0.0] * 36


@dataclass
@final
class PoseWithCovariance(IdlStruct, typename="geometry_msgs::msg::dds_::PoseWithCovariance_"):
    """geometry_msgs/msg/PoseWithCovariance: a 6x6 row-major covariance (x, y, z, roll, pitch, yaw)."""

    pose: Pose = field(default_factory=Pose)
    covariance: t.array[t.float64, 36] = field(default_factory=_zeros36)


@dataclass
@final
class TwistWithCovariance(IdlStruct, typename="geometry_msgs::msg::dds_::TwistWithCovariance_"):
    """geometry_msgs/msg/TwistWithCovariance."""

    twist: Twist = field(default_factory=Twist)
    covariance: t.array[t.float64, 36] = field(default_factory=_zeros36)


# nav_msgs


@dataclass
@final
class Odometry(IdlStruct, typename="nav_msgs::msg::dds_::Odometry_"):
    """nav_msgs/msg/Odometry: pose in header.frame_id, twist in child_frame_id."""

    header: Header = field(default_factory=Header)
    child_frame_id: str = ""
    pose: PoseWithCovariance = field(default_factory=PoseWithCovariance)
    twist: TwistWithCovariance = field(default_factory=TwistWithCovariance)


# sensor_msgs


@dataclass
@final
class LaserScan(IdlStruct, typename="sensor_msgs::msg::dds_::LaserScan_"):
    """sensor_msgs/msg/LaserScan: angles rad, times s, ranges m (float32)."""

    header: Header = field(default_factory=Header)
    angle_min: t.float32 = 0.0
    angle_max: t.float32 = 0.0
    angle_increment: t.float32 = 0.0
    time_increment: t.float32 = 0.0
    scan_time: t.float32 = 0.0
    range_min: t.float32 = 0.0
    range_max: t.float32 = 0.0
    ranges: t.sequence[t.float32] = field(default_factory=list)
    intensities: t.sequence[t.float32] = field(default_factory=list)


# rosgraph_msgs, rcl_interfaces


@dataclass
@final
class Clock(IdlStruct, typename="rosgraph_msgs::msg::dds_::Clock_"):
    """rosgraph_msgs/msg/Clock: the simulated time on ``/clock``."""

    clock: Time = field(default_factory=Time)


@dataclass
@final
class Log(IdlStruct, typename="rcl_interfaces::msg::dds_::Log_"):
    """rcl_interfaces/msg/Log, as on ``/rosout``: level 10 DEBUG, 20 INFO, 30 WARN, 40 ERROR, 50 FATAL."""

    stamp: Time = field(default_factory=Time)
    level: t.uint8 = 0
    name: str = ""
    msg: str = ""
    file: str = ""
    function: str = ""
    line: t.uint32 = 0


# turtlesim (no pip wheel provides it: an rclpy node cannot import it, ROS installs can)


@dataclass
@final
class TurtlesimPose(IdlStruct, typename="turtlesim::msg::dds_::Pose_"):
    """turtlesim/msg/Pose: x, y m, theta rad, velocities m/s and rad/s (float32)."""

    x: t.float32 = 0.0
    y: t.float32 = 0.0
    theta: t.float32 = 0.0
    linear_velocity: t.float32 = 0.0
    angular_velocity: t.float32 = 0.0


#: every type above by its ROS 2 name (``package/msg/Name``)
BY_ROS_NAME: dict[str, type[IdlStruct]] = {
    "builtin_interfaces/msg/Time": Time,
    "std_msgs/msg/Header": Header,
    "std_msgs/msg/String": String,
    "geometry_msgs/msg/Vector3": Vector3,
    "geometry_msgs/msg/Twist": Twist,
    "geometry_msgs/msg/Point": Point,
    "geometry_msgs/msg/Quaternion": Quaternion,
    "geometry_msgs/msg/Pose": Pose,
    "geometry_msgs/msg/Pose2D": Pose2D,
    "geometry_msgs/msg/PoseWithCovariance": PoseWithCovariance,
    "geometry_msgs/msg/TwistWithCovariance": TwistWithCovariance,
    "nav_msgs/msg/Odometry": Odometry,
    "sensor_msgs/msg/LaserScan": LaserScan,
    "rosgraph_msgs/msg/Clock": Clock,
    "rcl_interfaces/msg/Log": Log,
    "turtlesim/msg/Pose": TurtlesimPose,
}


# the capstone's status (docs/capstone.md): a type of turtlectl's own, named as a ROS package would
@dataclass
@final
class TurtleStatus(IdlStruct, typename="capstone_msgs::msg::dds_::TurtleStatus_"):
    """capstone_msgs/msg/TurtleStatus: x, y m; theta degrees [0, 360); vel_x, vel_y m/s; battery %."""

    x: t.float64 = 0.0
    y: t.float64 = 0.0
    theta: t.float64 = 0.0
    vel_x: t.float64 = 0.0
    vel_y: t.float64 = 0.0
    battery: t.float64 = 0.0


BY_ROS_NAME["capstone_msgs/msg/TurtleStatus"] = TurtleStatus


# rmw_dds_common: how a participant tells ROS 2 which nodes it holds (topic ``ros_discovery_info``,
# no ``rt/`` prefix; reliable, transient local, keep last 1).  A gid is the 16-byte DDS GUID of the
# participant, reader or writer.
@dataclass
@final
class Gid(IdlStruct, typename="rmw_dds_common::msg::dds_::Gid_"):
    """rmw_dds_common/msg/Gid: char[16], a DDS GUID (12-byte prefix, 4-byte entity id)."""

    data: t.array[t.uint8, 16] = field(default_factory=lambda: [0] * 16)


@dataclass
@final
class NodeEntitiesInfo(IdlStruct, typename="rmw_dds_common::msg::dds_::NodeEntitiesInfo_"):
    """rmw_dds_common/msg/NodeEntitiesInfo: one node, its namespace, and the gids of its readers and writers."""

    node_namespace: str = "/"
    node_name: str = ""
    reader_gid_seq: t.sequence[Gid] = field(default_factory=list)
    writer_gid_seq: t.sequence[Gid] = field(default_factory=list)


@dataclass
@final
class ParticipantEntitiesInfo(IdlStruct, typename="rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_"):
    """rmw_dds_common/msg/ParticipantEntitiesInfo: the nodes of one participant (its gid)."""

    gid: Gid = field(default_factory=Gid)
    node_entities_info_seq: t.sequence[NodeEntitiesInfo] = field(default_factory=list)


BY_ROS_NAME["rmw_dds_common/msg/Gid"] = Gid
BY_ROS_NAME["rmw_dds_common/msg/NodeEntitiesInfo"] = NodeEntitiesInfo
BY_ROS_NAME["rmw_dds_common/msg/ParticipantEntitiesInfo"] = ParticipantEntitiesInfo
