"""turtlectl messages <-> ROS 2 types (nodes.ros2_mapping): values, units, frames, and the CDR bytes a
ROS 2 peer reads.  No network.  Skipped where the optional ``cyclonedds`` is not installed."""

import math
import struct

import pytest

pytest.importorskip("cyclonedds")

from turtlectl.messages import Clock, LaserScan, Log, Pose, TurtleStatus, Twist  # noqa: E402
from turtlectl.nodes import ros2_mapping as m  # noqa: E402
from turtlectl.nodes import ros2_types as r  # noqa: E402


def test_every_type_carries_the_dds_name_ros_2_matches_on():
    for ros_name, cls in r.BY_ROS_NAME.items():
        assert cls.__idl_typename__ == r.dds_type_name(ros_name)
    assert r.dds_type_name("geometry_msgs/msg/Twist") == "geometry_msgs::msg::dds_::Twist_"


def test_dds_topic_is_rt_and_the_name_without_its_slash():
    assert r.dds_topic("/turtle1/cmd_vel") == "rt/turtle1/cmd_vel"
    assert r.dds_topic("obstacles") == "rt/obstacles"


def test_twist_is_plain_xcdr1_little_endian_six_doubles():
    data = m.twist_to_ros(Twist(linear=1.5, angular=-0.25)).serialize()
    assert data[:4] == b"\x00\x01\x00\x00"  # CDR_LE encapsulation: XCDR1, as Fast DDS writes it
    assert struct.unpack("<6d", data[4:]) == (1.5, 0.0, 0.0, 0.0, 0.0, -0.25)


def test_twist_round_trip_keeps_what_a_unicycle_reads():
    ros = r.Twist(linear=r.Vector3(x=0.8, y=3.0), angular=r.Vector3(x=1.0, z=0.4))
    back = m.twist_from_ros(r.Twist.deserialize(ros.serialize()), stamp=7, seq=2)
    assert back == Twist(linear=0.8, angular=0.4, stamp=7, seq=2)


def test_pose_as_turtlesim_and_pose2d():
    pose = Pose(x=5.5, y=2.25, theta=-1.0, linear_velocity=0.5, angular_velocity=0.125, contact=True)
    ts = r.TurtlesimPose.deserialize(m.pose_to_turtlesim(pose).serialize())
    assert (ts.x, ts.y, ts.linear_velocity, ts.angular_velocity) == (5.5, 2.25, 0.5, 0.125)
    assert ts.theta == pytest.approx(-1.0, abs=1e-7)  # float32
    assert m.pose_from_turtlesim(ts).x == 5.5
    assert m.pose_to_pose2d(pose) == r.Pose2D(x=5.5, y=2.25, theta=-1.0)


@pytest.mark.parametrize("theta", [0.0, 1.0, -2.5, math.pi - 1e-9])
def test_odometry_carries_the_heading_as_a_quaternion(theta):
    odom = m.pose_to_odometry(Pose(x=1.0, y=2.0, theta=theta, linear_velocity=0.3, stamp=1_500_000_000_250))
    assert odom.header.frame_id == "odom" and odom.child_frame_id == "turtle1/base_link"
    assert (odom.header.stamp.sec, odom.header.stamp.nanosec) == (1500, 250)
    q = odom.pose.pose.orientation
    assert math.isclose(q.x**2 + q.y**2 + q.z**2 + q.w**2, 1.0)
    assert m.quaternion_to_yaw(q) == pytest.approx(theta)
    assert odom.twist.twist.linear.x == 0.3
    assert r.Odometry.deserialize(odom.serialize()) == odom


def test_scan_keeps_inf_and_names_the_scanner_frame():
    scan = LaserScan(
        angle_min=-math.pi,
        angle_max=math.pi,
        angle_increment=math.pi / 2,
        range_min=0.1,
        range_max=4.0,
        ranges=[1.0, math.inf, 2.5, 0.5],
        stamp=3_000_000_001,
    )
    ros = r.LaserScan.deserialize(m.scan_to_ros(scan, turtle="turtle2").serialize())
    assert ros.header.frame_id == "turtle2/base_scan"
    assert ros.ranges == [1.0, math.inf, 2.5, 0.5]
    back = m.scan_from_ros(ros)
    assert back.stamp == 3_000_000_001 and back.ranges == [1.0, math.inf, 2.5, 0.5]
    assert math.isnan(back.origin_x)
    assert back.angle_increment == pytest.approx(math.pi / 2)


def test_status_clock_and_log():
    status = TurtleStatus(x=1.0, y=2.0, theta=270.0, vel_x=0.1, vel_y=-0.1, battery=87.5)
    assert m.status_from_ros(r.TurtleStatus.deserialize(m.status_to_ros(status).serialize())) == status
    assert m.clock_to_ros(Clock(clock=2_000_000_003)).clock == r.Time(sec=2, nanosec=3)
    log = m.log_to_ros(Log(level=35, node="turtle2/navigator", message="blocked", line=-1, stamp=5))
    assert (log.level, log.name, log.msg, log.line) == (30, "turtle2.navigator", "blocked", 0)


def test_negative_stamps_floor_to_a_valid_time():
    t = m.ns_to_time(-1)
    assert (t.sec, t.nanosec) == (-1, 999_999_999)
    assert m.time_to_ns(t) == -1


def test_string_both_ways():
    from turtlectl.messages import String

    ros = m.string_to_ros(String(data="héllo", stamp=3, seq=1))
    assert r.String.deserialize(ros.serialize()) == r.String(data="héllo")
    assert m.string_from_ros(ros, stamp=9, seq=2) == String(data="héllo", stamp=9, seq=2)


def test_the_bridges_conversions_take_the_turtle_for_frames_and_the_stamp_for_what_comes_from_ros():
    odom = m.TO_ROS["nav_msgs/msg/Odometry"][2](Pose(x=1.0, y=2.0, theta=0.5), "turtle2")
    assert odom.child_frame_id == "turtle2/base_link"
    scan = m.TO_ROS["sensor_msgs/msg/LaserScan"][2](
        LaserScan(angle_min=0, angle_max=1, angle_increment=1, range_min=0, range_max=2, ranges=[1.0, 2.0]), "turtle3"
    )
    assert scan.header.frame_id == "turtle3/base_scan"
    twist = m.FROM_ROS["geometry_msgs/msg/Twist"][2](r.Twist(linear=r.Vector3(x=0.5)), 42)
    assert twist == Twist(linear=0.5, angular=0.0, stamp=42)
