"""The ROS 2 bridge against real rclpy nodes (the pip wheels, Fast DDS), all in one network namespace
holding only loopback (tests/integration/ros2_side.py): a launched system with ``run = "ros2_bridge"``,
rclpy nodes driving the turtle and reading its topics, rclpy's graph, and ROS topics into turtlectl."""

from __future__ import annotations

import json
import math
import os
import re
import subprocess
import time

import pytest

from tests.integration.harness import turtlectl
from tests.integration.ros2_side import BRIDGE_NODE as BRIDGE
from tests.integration.ros2_side import ROOT, SCRIPTS, default_launch_with_bridge, require_ros2_side, ros_env, ros_side

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
        s.system = s.launch(default_launch_with_bridge(CHATTER), tmp_path_factory.mktemp("ros2"), nodes=5)
        yield s


def echo_once(side, key: str) -> dict:
    done = side.tool("echo", key, "--once", "--json")
    assert done.returncode == 0, done.stdout + done.stderr
    return json.loads(done.stdout)


def standing_still(side) -> dict:
    """The turtle's pose once it stands still (after a drive it coasts for a second), under a deadline."""
    deadline = time.monotonic() + 20
    while True:
        pose = echo_once(side, "turtle1/pose")
        if pose["linear_velocity"] == 0 and pose["angular_velocity"] == 0:
            return pose
        assert time.monotonic() < deadline, pose


def test_an_rclpy_publisher_on_turtle1_cmd_vel_drives_the_turtle(side):
    before = echo_once(side, "turtle1/pose")
    driver = side.rclpy("probe.py", "drive", "1.0", "0.0", "1.5")
    driver.wait_for("^READY$")
    driver.wait_for("^DONE$")
    after = echo_once(side, "turtle1/pose")
    assert after["x"] - before["x"] > 0.5, (before, after)
    assert math.isclose(after["y"], before["y"], abs_tol=0.05), (before, after)


def test_an_rclpy_subscription_gets_the_odometry_of_turtlectls_pose(side):
    pose = standing_still(side)
    listener = side.rclpy("probe.py", "listen", "/turtle1/odom", "nav_msgs/msg/Odometry", "1")
    odom = listener.json_line("MSG")
    assert odom["header"]["frame_id"] == "odom" and odom["child_frame_id"] == "turtle1/base_link"
    position, q = odom["pose"]["pose"]["position"], odom["pose"]["pose"]["orientation"]
    assert math.isclose(position["x"], pose["x"], abs_tol=1e-6) and math.isclose(position["y"], pose["y"], abs_tol=1e-6)
    assert math.isclose(math.atan2(2 * q["w"] * q["z"], 1 - 2 * q["z"] ** 2), pose["theta"], abs_tol=1e-6)


def test_an_rclpy_subscription_gets_the_scan_with_turtlectls_ranges(side):
    standing_still(side)
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
    graph = side.rclpy("probe.py", "graph", wanted, "ros2_bridge,sim,navigator", "sim").json_line("GRAPH")
    topics = graph["topics"]
    assert topics["/turtle1/cmd_vel"] == ["geometry_msgs/msg/Twist"]
    assert topics["/turtle1/pose"] == ["turtlesim/msg/Pose"]
    assert topics["/turtle1/odom"] == ["nav_msgs/msg/Odometry"]
    assert topics["/obstacles"] == ["sensor_msgs/msg/LaserScan"]
    assert topics["/robot/status"] == ["capstone_msgs/msg/TurtleStatus"]
    assert "rcl_interfaces/msg/Log" in topics["/rosout"]
    assert {"ros2_bridge", "sim", "navigator", "status_monitor", "obstacle_detector"} <= set(graph["nodes"])
    # ros2 node info /sim: what the simulator publishes and subscribes to, as far as it is bridged
    assert graph["publishers"]["/turtle1/pose"] == ["turtlesim/msg/Pose"]
    assert graph["publishers"]["/turtle1/odom"] == ["nav_msgs/msg/Odometry"]
    assert graph["subscribers"]["/turtle1/cmd_vel"] == ["geometry_msgs/msg/Twist"]


def test_rosout_reaches_a_reader_asking_for_rosouts_own_qos(side):
    """rcl publishes /rosout reliable and transient local; a reader asking for that (rqt_console)
    matches the bridge's writer only if it offers as much, and then gets the lines logged before."""
    spawned = side.tool("spawn", "2", "2", "0", "--name", "rosout_probe")  # lines logged after the bridge's own
    assert spawned.returncode == 0, spawned.stdout + spawned.stderr
    side.system.wait_for("bridging rosout_probe")
    reader = side.rclpy("probe.py", "listen", "/rosout", "rcl_interfaces/msg/Log", "1000", "transient_local")
    logged = json.loads(reader.wait_for("^MSG .*bridging turtle1").split(" ", 1)[1])  # said at the bridge's start
    assert logged["name"] == "ros2_bridge" and logged["level"] == 20, logged
    reader.stop()


def test_turtlectl_echo_shows_an_rclpy_talkers_string(side):
    talker = side.rclpy("probe.py", "talk", "/chatter", "hello from rclpy")
    talker.wait_for("^READY$")
    said = echo_once(side, "chatter")
    assert said["data"] == "hello from rclpy"
    talker.stop()


def test_a_ros_message_that_does_not_decode_is_one_line_and_the_bridge_keeps_going(side):
    garbage = side.turtlectl_python(str(SCRIPTS / "garbage.py"), "/chatter", "5", env=ros_env())
    garbage.wait_for("^SENT$")
    line = side.system.wait_for("did not decode")
    assert "/chatter" in line and "std_msgs/msg/String" in line
    talker = side.rclpy("probe.py", "talk", "/chatter", "still bridging")
    talker.wait_for("^READY$")
    assert echo_once(side, "chatter")["data"] == "still bridging"
    talker.stop()
    assert sum("did not decode" in x for x in side.system.lines) == 1  # once a topic


def test_a_second_bridge_of_a_system_is_refused_in_one_line_and_the_first_keeps_bridging(side):
    """Two bridges of one system on one ROS domain would feed each other: a Twist one writes to ROS the
    other brings back into the system, and the first sends it to ROS again, thousands a second, the
    turtle driving on a command its sender ended.  The second one refuses to start (exit 4), by any name."""
    second = side.spawn([*turtlectl(), "ros2", "bridge", "--name", "bridge_b", "--connect", side.endpoint])
    assert second.finish() == 4, second.text()
    said = [line for line in second.lines if "ros2/bridge" in line]
    assert len(said) == 1 and "ros2_bridge" in said[0], second.text()
    driver = side.rclpy("probe.py", "drive", "0.0", "0.5", "1.0")
    driver.wait_for("^READY$")
    assert driver.finish() == 0, driver.text()
    # after the driver's last Twist nothing drives the turtle: at most the navigator's idle stops
    rates = side.tool("hz", "turtle1/cmd_vel", "--duration", "2", "--json")
    seen = [json.loads(line)["rate"] for line in rates.stdout.splitlines() if line.startswith("{")]
    assert all(rate < 50 for rate in seen), rates.stdout + rates.stderr
    assert side.system.proc.poll() is None


def test_an_unknown_ros_type_in_the_table_is_one_line_at_check(tmp_path):
    path = tmp_path / "launch.toml"
    path.write_text(default_launch_with_bridge(CHATTER.replace("std_msgs/msg/String", "std_msgs/msg/Strng")))
    done = subprocess.run([*turtlectl(), "launch", str(path), "--check"], capture_output=True, text=True, timeout=60)
    assert done.returncode == 2
    assert done.stderr.strip().count("\n") == 0, done.stderr
    assert "unknown ROS type 'std_msgs/msg/Strng' for /chatter; did you mean std_msgs/msg/String?" in done.stderr


def test_without_cyclone_dds_the_bridge_says_how_to_install_it_and_exits_4(tmp_path):
    hidden = tmp_path / "hide" / "cyclonedds"
    hidden.mkdir(parents=True)
    (hidden / "__init__.py").write_text("raise ImportError('hidden for the test', name='cyclonedds')\n")
    env = {**os.environ, "PYTHONPATH": str(hidden.parent)}
    done = subprocess.run(
        [*turtlectl(), "ros2", "bridge", "--connect", "tcp/127.0.0.1:1"],
        capture_output=True,
        text=True,
        timeout=60,
        env=env,
    )
    assert done.returncode == 4, done.stdout + done.stderr
    assert "pip install 'turtlectl[ros2]'" in done.stderr


def test_the_how_tos_student_node_drives_the_turtle_and_reads_its_scan(side):
    """examples/ros2/drive_and_scan.py, as docs/how-to/ros2.md runs it: plain rclpy, no turtlectl."""
    before = standing_still(side)
    student = side.spawn(
        [str(require_ros2_side()), str(ROOT / "examples" / "ros2" / "drive_and_scan.py"), "--seconds", "4"],
        env=ros_env(),
    )
    assert student.finish() == 0, student.text()
    last = student.lines[-1]
    found = re.match(r"at \(([-\d.]+), ([-\d.]+)\), nearest ahead ([\d.inf]+) m, (\d+) scans", last)
    assert found, student.text()
    assert int(found[4]) >= 5, last  # 5 Hz for 4 s, less the matching
    after = echo_once(side, "turtle1/pose")
    assert math.hypot(after["x"] - before["x"], after["y"] - before["y"]) > 0.3, (before, after)
    assert math.isclose(float(found[1]), after["x"], abs_tol=0.2), (last, after)


def test_turtlectl_record_keeps_an_rclpy_talkers_string(side, tmp_path):
    talker = side.rclpy("probe.py", "talk", "/chatter", "kept")
    talker.wait_for("^READY$")
    echo_once(side, "chatter")  # it crosses now
    out = tmp_path / "chatter.mcap"
    done = side.tool("record", "chatter", "-o", str(out), "--duration", "1.5")
    talker.stop()
    assert done.returncode == 0, done.stdout + done.stderr
    info = subprocess.run([*turtlectl(), "info", str(out)], capture_output=True, text=True, timeout=60)
    assert info.returncode == 0, info.stderr
    assert re.search(r"chatter\s.*turtlectl/String", info.stdout), info.stdout


def test_a_fleet_on_simulated_time_is_bridged_turtle_by_turtle_with_its_clock(tmp_path):
    """examples/fleet (turtle1 outside a namespace, turtle2 and turtle3 in theirs) with --time-scale:
    each namespaced turtle's topics under its name, the nodes under their namespaces, and /clock."""
    fleet = (ROOT / "examples" / "fleet" / "launch.toml").read_text()
    with ros_side() as fleet_side:
        fleet_side.launch(fleet + BRIDGE, tmp_path, "--time-scale", "2", nodes=11)
        wanted = (
            "/turtle1/odom,/obstacles,/turtle2/cmd_vel,/turtle2/odom,/turtle3/obstacles,/turtle3/robot/status,/clock"
        )
        graph = fleet_side.rclpy("probe.py", "graph", wanted, "turtle2/navigator,navigator").json_line("GRAPH")
        topics = graph["topics"]
        assert topics["/turtle2/cmd_vel"] == ["geometry_msgs/msg/Twist"]
        assert topics["/turtle3/obstacles"] == ["sensor_msgs/msg/LaserScan"]
        assert topics["/turtle3/robot/status"] == ["capstone_msgs/msg/TurtleStatus"]
        assert topics["/clock"] == ["rosgraph_msgs/msg/Clock"]
        assert {"navigator", "turtle2/navigator", "turtle3/obstacle_detector", "ros2_bridge"} <= set(graph["nodes"])
        scan = fleet_side.rclpy("probe.py", "listen", "/turtle2/obstacles", "sensor_msgs/msg/LaserScan", "1")
        assert scan.json_line("MSG")["header"]["frame_id"] == "turtle2/base_scan"


def test_under_secure_the_bridge_works_with_only_its_tables_keys(tmp_path, monkeypatch):
    """launch --secure: the router allows the bridge its table's keys (Ros2BridgeParams.narrow_interface)
    and the rclpy side still drives the turtle and talks on /chatter."""
    from turtlectl.runtime.client import credentials

    monkeypatch.setenv(credentials.ENV, str(tmp_path / "credentials.json"))
    with ros_side() as secure:
        system = secure.launch(default_launch_with_bridge(CHATTER), tmp_path, "--secure", nodes=5)
        before = echo_once(secure, "turtle1/pose")
        driver = secure.rclpy("probe.py", "drive", "1.0", "0.0", "1.0")
        driver.wait_for("^DONE$")
        assert echo_once(secure, "turtle1/pose")["x"] - before["x"] > 0.3
        talker = secure.rclpy("probe.py", "talk", "/chatter", "secure hello")
        talker.wait_for("^READY$")
        assert echo_once(secure, "chatter")["data"] == "secure hello"
        assert not [line for line in system.lines if "may not" in line or "ERROR" in line], system.text()
