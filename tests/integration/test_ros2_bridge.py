"""The ROS 2 bridge against real rclpy nodes (the pip wheels, Fast DDS), all in one network namespace
holding only loopback (tests/integration/ros2_side.py): a launched system with ``run = "ros2_bridge"``,
rclpy nodes driving the turtle and reading its topics, rclpy's graph, and ROS topics into turtlectl."""

from __future__ import annotations

import json
import math

import pytest

from tests.integration.ros2_side import default_launch_with_bridge, ros_side

pytestmark = pytest.mark.integration

CHATTER = """
[[node.params.topics]]
key = "chatter"
ros = "/chatter"
type = "std_msgs/msg/String"
direction = "from_ros"
"""


@pytest.fixture(scope="module")
def side(tmp_path_factory):
    """The default system with the bridge (its default table and a /chatter row), in a namespace."""
    with ros_side() as s:
        s.launch(default_launch_with_bridge(CHATTER), tmp_path_factory.mktemp("ros2"), nodes=5)
        yield s


def echo_once(side, key: str) -> dict:
    done = side.tool("echo", key, "--once", "--json")
    assert done.returncode == 0, done.stdout + done.stderr
    return json.loads(done.stdout)


def test_an_rclpy_publisher_on_turtle1_cmd_vel_drives_the_turtle(side):
    before = echo_once(side, "turtle1/pose")
    driver = side.rclpy("probe.py", "drive", "1.0", "0.0", "1.5")
    driver.wait_for("^READY$")
    driver.wait_for("^DONE$")
    after = echo_once(side, "turtle1/pose")
    assert after["x"] - before["x"] > 0.5, (before, after)
    assert math.isclose(after["y"], before["y"], abs_tol=0.05), (before, after)


def test_an_rclpy_subscription_gets_the_odometry_of_turtlectls_pose(side):
    listener = side.rclpy("probe.py", "listen", "/turtle1/odom", "nav_msgs/msg/Odometry", "1")
    odom = listener.json_line("MSG")
    pose = echo_once(side, "turtle1/pose")  # the turtle stands still: the same pose
    assert odom["header"]["frame_id"] == "odom" and odom["child_frame_id"] == "turtle1/base_link"
    position, q = odom["pose"]["pose"]["position"], odom["pose"]["pose"]["orientation"]
    assert math.isclose(position["x"], pose["x"], abs_tol=1e-6) and math.isclose(position["y"], pose["y"], abs_tol=1e-6)
    assert math.isclose(math.atan2(2 * q["w"] * q["z"], 1 - 2 * q["z"] ** 2), pose["theta"], abs_tol=1e-6)


def test_an_rclpy_subscription_gets_the_scan_with_turtlectls_ranges(side):
    listener = side.rclpy("probe.py", "listen", "/obstacles", "sensor_msgs/msg/LaserScan", "1")
    scan = listener.json_line("MSG")
    ours = echo_once(side, "obstacles")  # the turtle stands still: the same ranges, as float32
    assert scan["header"]["frame_id"] == "turtle1/base_scan"
    assert len(scan["ranges"]) == len(ours["ranges"])
    for theirs, mine in zip(scan["ranges"], ours["ranges"], strict=True):
        assert math.isclose(theirs, float(mine), rel_tol=1e-6), (theirs, mine)
    assert math.isclose(scan["angle_min"], ours["angle_min"], rel_tol=1e-6)


def test_rclpys_graph_lists_turtlectls_nodes_and_topics_with_their_ros_types(side):
    wanted = "/turtle1/cmd_vel,/turtle1/pose,/turtle1/odom,/obstacles,/robot/status,/rosout"
    graph = side.rclpy("probe.py", "graph", wanted, "ros2_bridge,sim,navigator").json_line("GRAPH")
    topics = graph["topics"]
    assert topics["/turtle1/cmd_vel"] == ["geometry_msgs/msg/Twist"]
    assert topics["/turtle1/pose"] == ["turtlesim/msg/Pose"]
    assert topics["/turtle1/odom"] == ["nav_msgs/msg/Odometry"]
    assert topics["/obstacles"] == ["sensor_msgs/msg/LaserScan"]
    assert topics["/robot/status"] == ["capstone_msgs/msg/TurtleStatus"]
    assert "rcl_interfaces/msg/Log" in topics["/rosout"]
    assert {"ros2_bridge", "sim", "navigator", "status_monitor", "obstacle_detector"} <= set(graph["nodes"])


def test_turtlectl_echo_shows_an_rclpy_talkers_string(side):
    talker = side.rclpy("probe.py", "talk", "/chatter", "hello from rclpy")
    talker.wait_for("^READY$")
    said = echo_once(side, "chatter")
    assert said["data"] == "hello from rclpy"
    talker.stop()
