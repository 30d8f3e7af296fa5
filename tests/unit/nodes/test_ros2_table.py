"""The ROS 2 bridge's table (nodes.ros2_table), pure: rows validated as a launch file is, the default
rows per turtle, what the bridge must not echo; and ``turtlectl ros2 bridge`` without the DDS side."""

from __future__ import annotations

import msgspec
import pytest

from turtlectl.messages import Twist
from turtlectl.nodes.params import Ros2BridgeParams
from turtlectl.nodes.ros2_table import ROS_TYPES, SYSTEM_ENTRIES, BridgeTopic, OwnEcho, turtle_entries, turtle_of_key


def row(**fields):
    return msgspec.convert(fields, BridgeTopic)


def test_a_row_names_its_turtlectl_type_by_its_ros_type():
    chatter = row(key="chatter", ros="/chatter", type="std_msgs/msg/String", direction="from_ros")
    assert (chatter.message_type, chatter.from_ros, chatter.to_ros, chatter.qos) == ("String", True, False, "reliable")


def test_an_unknown_ros_type_is_one_line_naming_the_nearest_and_the_known():
    with pytest.raises(msgspec.ValidationError) as err:
        row(key="chatter", ros="/chatter", type="std_msgs/msg/Strin")
    text = str(err.value)
    assert "unknown ROS type 'std_msgs/msg/Strin' for /chatter; did you mean std_msgs/msg/String?" in text
    assert "\n" not in text


def test_a_type_that_crosses_one_way_only_is_refused_the_other():
    with pytest.raises(msgspec.ValidationError, match="crosses only to_ros, not from_ros"):
        row(key="turtle1/pose", ros="/odom", type="nav_msgs/msg/Odometry", direction="both")


@pytest.mark.parametrize("bad", ["chatter", "/has space", "/9", ""])
def test_a_ros_topic_is_absolute_and_a_ros_name(bad):
    with pytest.raises(msgspec.ValidationError):
        row(key="chatter", ros=bad, type="std_msgs/msg/String")


def test_the_launch_files_params_take_rows_and_refuse_unknown_keys():
    params = msgspec.convert(
        {"ros_domain": 7, "topics": [{"key": "a", "ros": "/a", "type": "std_msgs/msg/String"}]}, Ros2BridgeParams
    )
    assert params.ros_domain == 7 and params.topics[0].ros == "/a" and params.defaults
    assert msgspec.convert({}, Ros2BridgeParams).ros_domain == -1  # ROS_DOMAIN_ID, else 0
    with pytest.raises(msgspec.ValidationError, match="ros_domain"):
        msgspec.convert({"ros_domain": 233}, Ros2BridgeParams)
    with pytest.raises(msgspec.ValidationError, match="direction2"):
        msgspec.convert(
            {"topics": [{"key": "a", "ros": "/a", "type": "std_msgs/msg/String", "direction2": 1}]}, Ros2BridgeParams
        )


def test_turtle1_uses_the_single_turtle_keys_and_another_turtle_its_namespaces():
    one = {(r.key, r.ros, r.type, r.direction) for r in turtle_entries("turtle1")}
    assert one == {
        ("turtle1/cmd_vel", "/turtle1/cmd_vel", "geometry_msgs/msg/Twist", "both"),
        ("turtle1/pose", "/turtle1/pose", "turtlesim/msg/Pose", "to_ros"),
        ("turtle1/pose", "/turtle1/odom", "nav_msgs/msg/Odometry", "to_ros"),
        ("obstacles", "/obstacles", "sensor_msgs/msg/LaserScan", "to_ros"),
        ("robot/status", "/robot/status", "capstone_msgs/msg/TurtleStatus", "to_ros"),
    }
    two = {(r.key, r.ros) for r in turtle_entries("turtle2")}
    assert two == {
        ("turtle2/cmd_vel", "/turtle2/cmd_vel"),
        ("turtle2/pose", "/turtle2/pose"),
        ("turtle2/pose", "/turtle2/odom"),
        ("turtle2/obstacles", "/turtle2/obstacles"),
        ("turtle2/robot/status", "/turtle2/robot/status"),
    }
    assert [r.ros for r in SYSTEM_ENTRIES] == ["/clock", "/rosout"]


def test_the_turtle_of_a_key_names_its_frames():
    assert turtle_of_key("obstacles") == "turtle1"
    assert turtle_of_key("turtle2/robot/status") == "turtle2"
    assert turtle_of_key("turtlebot/x") == "turtle1"


def test_what_the_bridge_published_itself_is_not_sent_back_once():
    echo = OwnEcho(keep=2)
    mine = Twist(linear=1.0, stamp=5, seq=0)
    echo.sent(mine)
    assert echo.is_own(Twist(linear=1.0, stamp=5, seq=0))
    assert not echo.is_own(mine)  # forgotten once seen: a later equal one is someone else's
    assert not echo.is_own(Twist(linear=1.0, stamp=6, seq=0))


def test_every_type_of_the_table_has_its_conversions():
    pytest.importorskip("cyclonedds")
    from turtlectl.nodes.ros2_mapping import FROM_ROS, TO_ROS

    assert set(TO_ROS) == {t for t, (_, ways) in ROS_TYPES.items() if "to_ros" in ways}
    assert set(FROM_ROS) == {t for t, (_, ways) in ROS_TYPES.items() if "from_ros" in ways}
    for name, (msg_type, _ros, _fn) in TO_ROS.items():
        assert msg_type.__name__ == ROS_TYPES[name][0]
    for name, (_ros, msg_type, _fn) in FROM_ROS.items():
        assert msg_type.__name__ == ROS_TYPES[name][0]


def test_the_bridge_command_without_cyclone_dds_says_how_to_install_it(monkeypatch):
    import importlib.util

    from typer.testing import CliRunner

    from turtlectl.cli import main

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "cyclonedds" else real(name, *a))
    ran = CliRunner().invoke(main.app, ["ros2", "bridge"])
    assert ran.exit_code == 4 or getattr(ran.exception, "exit_code", None) == 4
    assert "pip install 'turtlectl[ros2]'" in main.error_line(ran.exception)


def test_the_bridge_may_do_what_its_table_says_and_a_secure_router_allows_only_that(tmp_path):
    from pathlib import Path

    from turtlectl.cli.system.access import node_rights
    from turtlectl.cli.system.launchfile import load_launch

    root = Path(__file__).resolve().parents[3]
    path = tmp_path / "launch.toml"
    path.write_text(
        (root / "launch.toml").read_text()
        + '\n[[node]]\nname = "ros2_bridge"\nrun = "ros2_bridge"\n[node.params]\nturtles = ["turtle1"]\n'
        + '[[node.params.topics]]\nkey = "chatter"\nros = "/chatter"\ntype = "std_msgs/msg/String"\ndirection = "from_ros"\n'
    )
    plan = load_launch(path, [])
    interface = plan.kinds["ros2_bridge"].interface
    assert interface.publishes == ("chatter", "turtle1/cmd_vel")
    assert set(interface.subscribes) == {
        "turtles",
        "clock",
        "turtlectl/log/*",
        "turtle1/cmd_vel",
        "turtle1/pose",
        "obstacles",
        "robot/status",
    }
    rights = node_rights("ros2_bridge", plan.kinds["ros2_bridge"])
    assert "**" not in rights["publish"] and "chatter" in rights["publish"]


def test_every_turtle_the_simulator_reports_when_none_are_listed():
    from turtlectl.nodes.ros2_table import bridged_keys

    keys = bridged_keys([], True, [])
    assert "*/cmd_vel" in keys["publishes"] and {"*/pose", "*/obstacles", "*/robot/status"} <= set(keys["subscribes"])
    assert bridged_keys([], False, []) == {"publishes": (), "subscribes": ()}


@pytest.mark.parametrize("bad", ["has space", "a/$b", "@turtlectl/x", "a//b", "a?"])
def test_a_key_is_a_plain_zenoh_key(bad):
    with pytest.raises(msgspec.ValidationError, match="key"):
        row(key=bad, ros="/x", type="std_msgs/msg/String")
    assert row(key="/turtle2/pose", ros="/p", type="turtlesim/msg/Pose").key == "/turtle2/pose"
