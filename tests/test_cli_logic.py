"""Pure logic of the command-line tools: graph, rates, message building, formats, the view."""

import math

import pytest

from cli.build import message_from_json, service_request, topic_message
from cli.errors import BadInput
from cli.format import csv_header, csv_row, message_block, select_field
from cli.graph import build_graph
from cli.rates import rate_stats
from cli.view import Scene, render
from messages import LaserScan, NavigateToFeedback, Pose, TeleportAbsolute, TurtleStatus, Twist
from messages.keys import EntityInfo, NodeInfo, entity_token, node_token
from messages.world import Obstacle, World


def test_graph_from_tokens():
    keys = [
        node_token(NodeInfo(name="sim", pid=1, host="h", start_ns=1_000_000_000)),
        node_token(NodeInfo(name="navigator", pid=2, host="h", start_ns=2_000_000_000)),
        entity_token(EntityInfo(node="sim", pid=1, role="pub", type_name="Pose", key="turtle1/pose")),
        entity_token(EntityInfo(node="navigator", pid=2, role="sub", type_name="Pose", key="turtle1/pose")),
        entity_token(EntityInfo(node="navigator", pid=2, role="srv", type_name="NavigateToRequest", key="navigate_to")),
        "@turtlectl/client/123-abc",
    ]
    graph = build_graph(keys, now_ns=5_000_000_000)
    assert [(n.name, n.uptime) for n in graph.nodes] == [("navigator", 3.0), ("sim", 4.0)]
    (topic,) = graph.topics
    assert (topic.key, topic.type, topic.publishers, topic.subscribers) == (
        "turtle1/pose",
        "Pose",
        ["sim"],
        ["navigator"],
    )
    assert [(s.key, s.servers) for s in graph.services] == [("navigate_to", ["navigator"])]


def test_rates_from_arrivals_and_stamps():
    arrivals = [i * 0.1 + (0.002 if i % 2 else 0.0) for i in range(11)]
    stamps = [int(i * 0.1 * 1e9) for i in range(11)]
    stats = rate_stats("k", arrivals, stamps)
    assert stats.rate == pytest.approx(10.0, rel=0.01)
    assert stats.publisher_rate == pytest.approx(10.0)
    assert stats.mean_period == pytest.approx(100.0, abs=0.3)
    assert stats.jitter_max == pytest.approx(2.0, abs=0.3)
    assert rate_stats("k", [1.0], [1]) is None


def test_messages_from_json_name_the_bad_field():
    assert topic_message("turtle1/cmd_vel", '{"linear": 1}') == Twist(linear=1.0)
    with pytest.raises(BadInput, match="linear: Expected `float`, got `str`"):
        topic_message("turtle1/cmd_vel", '{"linear": "x"}')
    with pytest.raises(BadInput, match="unknown field `boost`"):
        message_from_json('{"boost": 1}', Twist)
    with pytest.raises(BadInput, match="--type"):
        topic_message("some/key", "{}")
    assert service_request("turtle1/teleport_absolute", '{"x":1,"y":2,"theta":0}') == TeleportAbsolute(
        x=1, y=2, theta=0
    )
    assert service_request("turtlectl/params/sim", "{}") == b"{}"
    with pytest.raises(BadInput, match="not valid JSON"):
        service_request("any/key", "{")


def test_formats():
    scan = LaserScan(
        angle_min=0, angle_max=1, angle_increment=0.1, range_min=0, range_max=5, ranges=[1.0] * 20 + [math.inf]
    )
    block = message_block(scan)
    assert block.startswith("# LaserScan\n") and "... (21 values)]" in block and block.endswith("---")
    assert "inf" in message_block(scan, full=True)
    status = TurtleStatus(x=1.0, y=2.0, theta=3.0, vel_x=-0.0, vel_y=0.0, battery=50.0, stamp=7, seq=1)
    assert select_field(scan, "ranges.20") == math.inf and select_field(status, "battery") == 50
    with pytest.raises(BadInput, match="no field 'nope'"):
        select_field(status, "nope")
    assert csv_header(status) == "x,y,theta,vel_x,vel_y,battery,stamp,seq"
    assert csv_row(status).startswith("1.0,2.0,3.0,")


def test_view_draws_walls_obstacles_turtle_goal_and_status():
    world = World(size=10.0, obstacles=[Obstacle(x=8.0, y=8.0, radius=1.0)])
    scene = Scene(
        world=world,
        pose=Pose(x=5.0, y=5.0, theta=math.pi / 2),
        status=TurtleStatus(x=5, y=5, theta=90, vel_x=0, vel_y=0, battery=77.0),
        feedback=NavigateToFeedback(
            state="driving",
            distance_remaining=2,
            heading_remaining=0,
            eta=1,
            elapsed=0,
            x=5,
            y=5,
            theta=90,
            goal_x=2,
            goal_y=2,
        ),
        trail=[(4.0, 4.0)],
    )
    lines = render(scene, 60, 24)
    assert len(lines) == 24 and all(len(line) <= 60 for line in lines)
    assert lines[0].startswith("+-") and lines[0].endswith("+")
    grid = "\n".join(lines[1:-3])
    assert "↑" in grid and "X" in grid and "o" in grid and "." in grid
    assert "x  5.00 y  5.00 heading  90.0 deg" in lines[-2]
    assert "battery 77.0 %" in lines[-1] and "goal (2.00, 2.00) driving" in lines[-1] and "q quits" in lines[-1]
    assert "^" in "\n".join(render(scene, 60, 24, unicode=False))
    assert render(scene, 10, 3) == ["terminal too small"]
