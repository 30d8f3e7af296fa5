"""The ROS 2 bridge's logic on a FakeNode with a fake DDS side (no network): rows made as turtles
appear, both ways of cmd_vel without echo, nothing converted for a topic no ROS reader matched, the
system's nodes handed to the graph, another bridge said once."""

from __future__ import annotations

from typing import Any

import pytest

pytest.importorskip("cyclonedds")

from turtlectl.messages import Pose, Turtles, Twist  # noqa: E402
from turtlectl.messages.keys import EntityInfo, NodeInfo, entity_token, node_token  # noqa: E402
from turtlectl.nodes import ros2_bridge  # noqa: E402
from turtlectl.nodes import ros2_types as r  # noqa: E402
from turtlectl.runtime.fake import FakeNode  # noqa: E402


class FakeOut:
    def __init__(self) -> None:
        self.readers = 0
        self.written: list[Any] = []

    def write(self, sample: Any) -> None:
        self.written.append(sample)


class FakeLink:
    """What the bridge asks of nodes.ros2_link.DdsLink, kept for the test to look at and drive."""

    def __init__(self, deliver) -> None:
        self.deliver = deliver
        self.writers: dict[str, FakeOut] = {}
        self.readers: dict[str, Any] = {}
        self.nodes: dict[str, Any] = {}
        self.on_other_bridge = lambda _participant: None
        self.closed = False

    def writer(self, ros_topic: str, ros_type: type, qos: str) -> FakeOut:
        self.writers[ros_topic] = FakeOut()
        return self.writers[ros_topic]

    def reader(self, ros_topic: str, ros_type: type, qos: str, on_sample) -> None:
        self.readers[ros_topic] = on_sample

    def from_ros(self, ros_topic: str, sample: Any) -> None:
        self.deliver(self.readers[ros_topic], sample)

    def set_nodes(self, nodes: dict[str, Any]) -> None:
        self.nodes = nodes

    def close(self) -> None:
        self.closed = True


@pytest.fixture()
def bridge(monkeypatch):
    links: list[FakeLink] = []

    def fake_open(node):
        links.append(FakeLink(node.core.enqueue))
        return links[0], 0

    monkeypatch.setattr(ros2_bridge, "open_link", fake_open)
    with FakeNode(ros2_bridge.Ros2Bridge, name="ros2_bridge") as fake:
        fake.deliver("turtles", Turtles(names=["turtle1", "turtle2"], x=[1, 2], y=[1, 2], theta=[0, 0]))
        fake.advance(0.01)
        yield fake, links[0]


def test_each_turtle_gets_its_rows_when_the_simulator_reports_it(bridge):
    _fake, link = bridge
    assert set(link.readers) == {"/turtle1/cmd_vel", "/turtle2/cmd_vel"}


def test_a_ros_twist_is_published_on_the_turtles_key_and_not_sent_back(bridge):
    fake, link = bridge
    link.from_ros("/turtle2/cmd_vel", r.Twist(linear=r.Vector3(x=0.7), angular=r.Vector3(z=-0.2)))
    fake.advance(0.01)
    [sent] = fake.published("turtle2/cmd_vel")
    assert (sent.linear, sent.angular) == (0.7, -0.2)
    fake.deliver("turtle2/cmd_vel", sent)  # Zenoh hands the bridge its own message back
    fake.advance(0.01)
    assert "/turtle2/cmd_vel" not in link.writers or link.writers["/turtle2/cmd_vel"].written == []
    fake.deliver("turtle2/cmd_vel", Twist(linear=0.1, stamp=1))  # a turtlectl node's command crosses
    fake.advance(0.01)
    link.writers["/turtle2/cmd_vel"].readers = 1
    fake.deliver("turtle2/cmd_vel", Twist(linear=0.2, stamp=2))
    fake.advance(0.01)
    assert [w.linear.x for w in link.writers["/turtle2/cmd_vel"].written] == [0.2]


def test_nothing_is_converted_for_a_ros_topic_no_reader_matched(bridge):
    fake, link = bridge
    fake.deliver("turtle1/pose", Pose(x=1.0, y=2.0, theta=0.5))
    fake.advance(0.01)
    assert link.writers["/turtle1/pose"].written == [] and link.writers["/turtle1/odom"].written == []
    link.writers["/turtle1/odom"].readers = 1
    fake.deliver("turtle1/pose", Pose(x=1.5, y=2.0, theta=0.5, stamp=3_000_000_001))
    fake.advance(0.01)
    [odom] = link.writers["/turtle1/odom"].written
    assert odom.pose.pose.position.x == 1.5 and (odom.header.stamp.sec, odom.header.stamp.nanosec) == (3, 1)
    assert link.writers["/turtle1/pose"].written == []


def test_the_systems_nodes_are_handed_to_the_graph_as_they_come_and_go(bridge):
    fake, link = bridge
    nav = node_token(NodeInfo(name="turtle2/navigator", pid=7, host="h", start_ns=1))
    fake.liveliness(nav, True)
    fake.liveliness(node_token(NodeInfo(name="sim", pid=8, host="h", start_ns=1)), True)
    assert sorted(link.nodes) == ["sim", "turtle2/navigator"]
    fake.liveliness(nav, False)
    assert list(link.nodes) == ["sim"]


def test_each_node_is_given_the_bridged_topics_of_what_it_publishes_and_subscribes_to(bridge):
    fake, link = bridge
    fake.liveliness(node_token(NodeInfo(name="sim", pid=8, host="h", start_ns=1)), True)
    fake.liveliness(node_token(NodeInfo(name="navigator", pid=9, host="h", start_ns=1)), True)
    for node, pid, role, key in [
        ("sim", 8, "pub", "turtle1/pose"),
        ("sim", 8, "sub", "turtle1/cmd_vel"),
        ("navigator", 9, "pub", "turtle1/cmd_vel"),
        ("navigator", 9, "sub", "obstacles"),
    ]:
        fake.liveliness(entity_token(EntityInfo(node=node, pid=pid, role=role, type_name="turtlectl/X", key=key)), True)
    assert link.nodes["sim"] == (("/turtle1/odom", "/turtle1/pose"), ("/turtle1/cmd_vel",))
    assert link.nodes["navigator"] == (("/turtle1/cmd_vel",), ())


def test_another_bridge_is_said_once(bridge, caplog):
    fake, link = bridge
    for _ in range(3):
        link.deliver(link.on_other_bridge, "0102")
    fake.advance(0.01)
    said = [rec.getMessage() for rec in caplog.records if "another bridge" in rec.getMessage()]
    assert len(said) == 1 and "ROS 2 domain 0" in said[0]


def test_leaving_closes_the_dds_side(bridge):
    fake, link = bridge
    fake.shutdown()
    assert link.closed


def test_a_second_row_with_another_type_on_a_bridged_key_is_refused_in_one_line(bridge, caplog):
    fake, link = bridge
    fake.instance.add(ros2_bridge.BridgeTopic(key="turtle1/pose", ros="/pose_text", type="std_msgs/msg/String"))
    said = [rec.getMessage() for rec in caplog.records if "not bridged" in rec.getMessage()]
    assert said == [
        "turtle1/pose -> /pose_text not bridged: turtle1/pose is already bridged as Pose (to /turtle1/pose), one type a key"
    ]
