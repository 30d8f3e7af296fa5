"""The ROS 2 package a ROS install builds to read /robot/status (examples/ros2/capstone_msgs) says what
the bridge writes and the bags record: one definition, three places that must agree."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import msgspec

from turtlectl.messages import TurtleStatus
from turtlectl.nodes.ros2_msgdefs import TURTLE_STATUS

PACKAGE = Path(__file__).resolve().parents[3] / "examples" / "ros2" / "capstone_msgs"


def fields(msg_text: str) -> list[tuple[str, str]]:
    rows = [line.split("#")[0].split() for line in msg_text.splitlines()]
    return [(row[1], row[0]) for row in rows if row]


def test_the_package_s_msg_is_the_one_the_bags_record():
    assert (PACKAGE / "msg" / "TurtleStatus.msg").read_text() == TURTLE_STATUS
    assert "<name>capstone_msgs</name>" in (PACKAGE / "package.xml").read_text()
    assert '"msg/TurtleStatus.msg"' in (PACKAGE / "CMakeLists.txt").read_text()


def test_the_msg_holds_the_capstone_s_fields_in_the_order_the_bridge_writes_them():
    from turtlectl.nodes import ros2_types

    written = [(f.name, "float64") for f in dataclasses.fields(ros2_types.TurtleStatus)]
    assert fields(TURTLE_STATUS) == written
    ours = [f.name for f in msgspec.structs.fields(TurtleStatus) if f.name not in ("stamp", "seq")]
    assert [name for name, _ in written] == ours
