"""The ROS 2 bridge against real rclpy nodes (the pip wheels, Fast DDS), all in one network namespace
holding only loopback (tests/integration/ros2_side.py): a launched system with ``run = "ros2_bridge"``,
rclpy nodes driving the turtle and reading its topics, rclpy's graph, and ROS topics into turtlectl."""

from __future__ import annotations

import json
import math

import pytest

from tests.integration.ros2_side import default_launch_with_bridge, ros_side

pytestmark = pytest.mark.integration


def pose_now(side) -> dict:
    done = side.tool("echo", "turtle1/pose", "--once", "--json")
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


def test_an_rclpy_publisher_on_turtle1_cmd_vel_drives_the_turtle(tmp_path):
    with ros_side() as side:
        side.launch(default_launch_with_bridge(), tmp_path, nodes=5)
        before = pose_now(side)
        driver = side.rclpy("probe.py", "drive", "1.0", "0.0", "1.5")
        driver.wait_for("^READY$")
        driver.wait_for("^DONE$")
        after = pose_now(side)
        assert after["x"] - before["x"] > 0.5, (before, after)
        assert math.isclose(after["y"], before["y"], abs_tol=0.05), (before, after)
