"""The ROS 2 profile's pure parts: the type table, turtlectl's own .msg texts, and turtlectl messages
as plain ROS field values and back (no ROS library, no network)."""

from __future__ import annotations

import math
from types import SimpleNamespace as NS

import pytest

from turtlectl.messages import Clock, Kill, LaserScan, Log, Pose, TurtleStatus, Twist
from turtlectl.messages.codec import TYPES_BY_NAME
from turtlectl.nodes import ros2_fields as f
from turtlectl.nodes import ros2_profile as p
from turtlectl.nodes.ros2_msgdefs import OWN


def ns(value):
    """Nested dicts as an object with attributes, as a ROS library's message is."""
    if isinstance(value, dict):
        return NS(**{k: ns(v) for k, v in value.items()})
    return value


def test_every_row_of_the_table_is_a_turtlectl_type_converted_both_ways():
    for row in p.TABLE:
        assert row.turtlectl in TYPES_BY_NAME
        assert f.readable(row.ros)
    assert p.BY_TURTLECTL["turtlectl/Log"].qos == p.ROSOUT_QOS
    assert set(OWN) == {"turtlesim/msg/Pose", "capstone_msgs/msg/TurtleStatus"}


def test_keys_and_ros_topics():
    assert p.ros_topic("turtle1/pose") == "/turtle1/pose" and p.ros_topic("/clock") == "/clock"
    assert p.ros_topic("turtlectl/log/turtle2.navigator") == "/turtlectl/log/turtle2_navigator"
    assert p.ros_topic("my-robot/x") == "/my_robot/x"
    assert p.key_of("/turtle1/pose") == "turtle1/pose" and p.key_of("/") == "/"


@pytest.mark.parametrize(
    "message",
    [
        Twist(linear=0.5, angular=-1.25),
        Pose(x=1.0, y=2.0, theta=-0.5, linear_velocity=0.25, angular_velocity=0.125),
        TurtleStatus(x=1.0, y=2.0, theta=350.0, vel_x=0.5, vel_y=-0.5, battery=87.5),
        Clock(clock=12_000_000_500, stamp=12_000_000_500),
        Log(level=30, node="turtle2/navigator", message="blocked", file="n.py", function="f", line=7, stamp=9),
    ],
)
def test_a_message_comes_back_from_its_ros_fields(message):
    converted = f.to_ros(message, "k")
    assert converted is not None
    ros_type, fields = converted
    assert ros_type == p.BY_TURTLECTL[type(message).__struct_config__.tag].ros
    assert f.from_ros(ros_type, ns(fields)) == message


def test_what_a_ros_type_has_no_place_for_is_dropped():
    _, twist = f.to_ros(Twist(linear=1.0, angular=2.0, stamp=5, seq=9))
    assert twist == {"linear": {"x": 1.0, "y": 0.0, "z": 0.0}, "angular": {"x": 0.0, "y": 0.0, "z": 2.0}}
    _, pose = f.to_ros(Pose(x=1.0, y=2.0, theta=0.0, contact=True, stamp=5))
    assert "contact" not in pose and "stamp" not in pose
    _, clock = f.to_ros(Clock(clock=1_500_000_000, real_time_factor=5.0))
    assert clock == {"clock": {"sec": 1, "nanosec": 500_000_000}}


def test_a_scan_is_in_its_turtles_scanner_frame_with_inf_kept():
    scan = LaserScan(
        angle_min=-1, angle_max=1, angle_increment=1, range_min=0.1, range_max=4, ranges=[1, math.inf], stamp=3
    )
    _, fields = f.to_ros(scan, "turtle2/obstacles")
    assert fields["header"] == {"stamp": {"sec": 0, "nanosec": 3}, "frame_id": "turtle2/base_scan"}
    assert fields["ranges"] == [1, math.inf] and fields["intensities"] == []
    assert f.to_ros(scan, "obstacles")[1]["header"]["frame_id"] == "turtle1/base_scan"
    back = f.from_ros("sensor_msgs/msg/LaserScan", ns(fields))
    assert back.ranges == [1, math.inf] and back.stamp == 3 and math.isnan(back.origin_x)


def test_a_log_level_between_two_of_ros_rounds_down():
    _, fields = f.to_ros(Log(level=25, node="n", message="m"))
    assert fields["level"] == 20 and fields["line"] == 0


def test_a_type_the_table_does_not_map_is_none():
    assert f.to_ros(Kill(name="turtle2")) is None
    assert f.from_ros("std_msgs/msg/String", NS(data="x")) is None and not f.readable("std_msgs/msg/String")


def test_a_bag_says_what_the_bridge_says():
    """One conversion: a bag's fields are the bridge's DDS message, field for field."""
    import dataclasses

    from turtlectl.nodes.ros2_mapping import scan_to_ros

    scan = LaserScan(
        angle_min=-1.0,
        angle_max=1.0,
        angle_increment=1.0,
        range_min=0.1,
        range_max=5.0,
        ranges=[1.0, math.inf, 2.0],
        stamp=7,
    )
    assert f.to_ros(scan, "turtle2/obstacles") == (
        "sensor_msgs/msg/LaserScan",
        dataclasses.asdict(scan_to_ros(scan, "turtle2")),
    )
