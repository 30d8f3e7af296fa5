"""Pure parts of the client rules: headings in [0, 360), the progress line's width, wildcard
JSON, the graph across domains, silence hints, type checks, exit codes of replies, the view."""

import json
import math
import os

import pytest
from typer.testing import CliRunner

from cli.build import service_request, topic_message
from cli.client import base_key, domain_prefix
from cli.errors import ExitCode, TurtlectlError, exit_code
from cli.format import heading_text, message_block, message_json, outcome_line, progress_line, teleport_line
from cli.graph import build_graph, graph_text
from cli.main import app
from cli.services import reply_code
from cli.topics import silence_text
from cli.view import Scene, render
from messages import (
    Ack,
    Cancel,
    LaserScan,
    NavigateToFeedback,
    NavigateToResponse,
    Pose,
    TurtleStatus,
    Twist,
)
from messages.keys import (
    EntityInfo,
    NodeInfo,
    client_token,
    domain_token,
    entity_token,
    node_token,
    parse_domain_token,
)
from messages.world import World
from runtime.session import CONNECT_ENV, DOMAIN_ENV

FEEDBACK = NavigateToFeedback(
    state="driving",
    distance_remaining=10.123,
    heading_remaining=179.9,
    eta=12.3,
    elapsed=14.5,
    x=11.08,
    y=11.08,
    theta=359.96,
    goal_x=1,
    goal_y=1,
    goal_theta=0,
)


@pytest.mark.parametrize(
    "degrees, shown", [(359.97, "0.0"), (360.0, "0.0"), (-0.0, "0.0"), (-45, "315.0"), (720.25, "0.2")]
)
def test_headings_are_shown_in_0_360_after_rounding(degrees, shown):
    assert heading_text(degrees) == shown


def test_goal_outcome_never_says_360_degrees():
    done = NavigateToResponse(success=True, time_taken=1.0, x=0.5, y=0.5, theta=359.99)
    assert "0.0 deg" in outcome_line(done) and "360" not in outcome_line(done)


def test_teleport_speaks_the_degrees_it_was_given():
    assert teleport_line(2, 2, 45) == "teleported to (2, 2, 45 deg)"
    assert teleport_line(4, 6, -90) == "teleported to (4, 6, 270 deg)"


@pytest.mark.parametrize("columns", [200, 80, 60, 40, 20, 5])
def test_the_progress_line_never_wraps(columns):
    line = progress_line(FEEDBACK, columns)
    assert len(line) <= columns - 1 or columns == 1
    assert line.startswith("driving"[: columns - 1]) and "\n" not in line and "360" not in line


def test_the_progress_line_keeps_what_fits_and_drops_the_least_useful_first():
    assert "14.5 s" in progress_line(FEEDBACK, 200) and "at (11.08, 11.08, 0 deg)" in progress_line(FEEDBACK, 200)
    narrow = progress_line(FEEDBACK, 50)
    assert "10.123 m" in narrow and "eta" in narrow and "14.5 s" not in narrow
    stale = NavigateToFeedback(**{**{f: getattr(FEEDBACK, f) for f in FEEDBACK.__struct_fields__}, "scan_stale": True})
    assert "no scan" in progress_line(stale, 120)


def test_wildcard_json_names_the_key():
    line = json.loads(message_json(Twist(linear=1.0), "turtle1/cmd_vel"))
    assert line["type"] == "Twist" and line["key"] == "turtle1/cmd_vel" and line["linear"] == 1.0
    assert "key" not in json.loads(message_json(Twist()))
    scan = LaserScan(angle_min=0, angle_max=0, angle_increment=0, range_min=0, range_max=1, ranges=[math.inf])
    assert json.loads(message_json(scan, "obstacles"))["ranges"] == [None]


def test_a_client_without_domain_sees_each_domain_prefixed():
    keys = [
        "lab1/" + node_token(NodeInfo(name="sim", pid=1, host="h", start_ns=1)),
        "lab1/" + entity_token(EntityInfo(node="sim", pid=1, role="pub", type_name="Pose", key="turtle1/pose")),
        "lab1/"
        + entity_token(
            EntityInfo(node="navigator", pid=2, role="srv", type_name="NavigateToRequest", key="navigate_to")
        ),
        node_token(NodeInfo(name="sim", pid=3, host="h", start_ns=1)),
        domain_token("lab1"),
        domain_token("lab2"),
    ]
    graph = build_graph(keys, now_ns=2)
    assert [(n.name, n.domain) for n in graph.nodes] == [("lab1/sim", "lab1"), ("sim", "")]
    assert [(t.key, t.publishers) for t in graph.topics] == [("lab1/turtle1/pose", ["lab1/sim"])]
    assert [(s.key, s.servers) for s in graph.services] == [("lab1/navigate_to", ["lab1/navigator"])]
    assert graph.domains == ["lab1", "lab2"]
    text = graph_text(graph)
    assert "lab1/sim" in text and "DOMAINS" in text and "lab1, lab2" in text


def test_an_empty_graph_says_what_to_do():
    graph = build_graph([], now_ns=0)
    graph.hint = "systems run in domain lab1 on this router: add it before the command, `turtlectl --domain lab1 ...`"
    assert (
        "(none: systems run in domain lab1 on this router: add it before the command, `turtlectl --domain lab1 ...`)"
        in graph_text(graph)
    )


def test_domain_and_client_tokens():
    assert domain_token("lab1") == "@turtlectl/domain/lab1" and parse_domain_token("@turtlectl/domain/lab1") == "lab1"
    assert parse_domain_token("@turtlectl/domain/a/b") is None and parse_domain_token("@turtlectl/node/x") is None
    assert client_token("42-abcd") == "@turtlectl/client/42-abcd"


def test_keys_reached_across_a_domain(monkeypatch):
    monkeypatch.delenv("TURTLECTL_DOMAIN", raising=False)
    assert domain_prefix("lab1/navigate_to") == "lab1/" and base_key("lab1/turtle1/cmd_vel") == "turtle1/cmd_vel"
    assert domain_prefix("navigate_to/cancel") == "" and domain_prefix("navigate_to/feedback") == ""
    assert base_key("some/thing") == "some/thing"
    monkeypatch.setenv("TURTLECTL_DOMAIN", "lab1")
    assert domain_prefix("lab1/navigate_to") == ""  # inside a domain keys are used as written


def _graph_with(*entities: EntityInfo, nodes: bool = True):
    keys = [entity_token(e) for e in entities]
    if nodes:
        keys.append(node_token(NodeInfo(name="navigator", pid=2)))
    return build_graph(keys, now_ns=0)


def test_silence_says_when_a_topic_is_published():
    feedback_pub = EntityInfo(
        node="navigator", pid=2, role="pub", type_name="NavigateToFeedback", key="navigate_to/feedback"
    )
    graph = _graph_with(feedback_pub)
    text = silence_text("navigate_to/feedback", graph, lambda: "")
    assert "navigator publishes it only while a goal runs" in text and "launch" not in text
    assert "navigator publishes it only while a goal runs" in silence_text("navigate_to/*", graph, lambda: "")
    status_pub = EntityInfo(node="status_monitor", pid=3, role="pub", type_name="TurtleStatus", key="robot/status")
    assert "for 3 s although status_monitor publishes it" in silence_text(
        "robot/status", _graph_with(status_pub), lambda: ""
    )
    assert "no running node publishes it" in silence_text("nosuch", graph, lambda: "")
    nothing = silence_text("robot/status", build_graph([], 0), lambda: "; systems run in domain lab1")
    assert "no turtlectl node runs on this router" in nothing and nothing.endswith("; systems run in domain lab1")
    assert "no turtlectl node runs in domain lab2" in silence_text(
        "robot/status", build_graph([], 0), lambda: "", "lab2"
    )


def test_silence_outside_a_domain_points_into_the_domain_that_publishes():
    keys = [
        "lab1/" + node_token(NodeInfo(name="status_monitor", pid=3)),
        "lab1/"
        + entity_token(
            EntityInfo(node="status_monitor", pid=3, role="pub", type_name="TurtleStatus", key="robot/status")
        ),
    ]
    text = silence_text("robot/status", build_graph(keys, 0), lambda: "")
    assert (
        text
        == "nothing published on robot/status here: it is published in domain lab1: add it before the command, `turtlectl --domain lab1 ...` (or use lab1/robot/status)"
    )


def test_a_known_key_keeps_its_type():
    assert type(topic_message("turtle1/cmd_vel", "{}", "Twist")) is Twist
    assert type(topic_message("some/topic", '{"x": 1, "y": 2, "theta": 0}', "Pose")) is Pose
    with pytest.raises(TurtlectlError) as err:
        topic_message("turtle1/cmd_vel", '{"x": 1, "y": 2, "theta": 0}', "Pose")
    assert exit_code(err.value) == ExitCode.BAD_INPUT and "turtle1/cmd_vel carries Twist, not Pose" in err.value.message
    with pytest.raises(TurtlectlError, match="navigate_to/cancel takes Cancel, not Pose"):
        service_request("navigate_to/cancel", '{"x": 1, "y": 2, "theta": 0}', "Pose")
    assert type(service_request("navigate_to/cancel", "{}", "Cancel")) is Cancel


def test_an_answer_that_says_no_is_exit_code_1():
    assert reply_code(Ack(ok=False, detail="no goal is running")) == ExitCode.FAILED
    assert reply_code(Ack()) == ExitCode.OK
    assert reply_code(NavigateToResponse(success=False, time_taken=0.0, reason="canceled")) == ExitCode.FAILED
    assert reply_code(NavigateToResponse(success=True, time_taken=1.0)) == ExitCode.OK
    assert reply_code(FEEDBACK) == ExitCode.OK


def test_the_view_has_a_legend_scan_hits_and_says_when_the_router_is_lost():
    scan = LaserScan(  # one beam straight ahead of a turtle facing +y: the hit is above it
        angle_min=0.0,
        angle_max=0.0,
        angle_increment=0.0,
        range_min=0.0,
        range_max=10.0,
        ranges=[3.0],
        origin_x=5.0,
        origin_y=2.0,
        origin_theta=math.pi / 2,
    )
    scene = Scene(world=World(size=10.0), pose=Pose(x=5.0, y=2.0, theta=math.pi / 2), scan=scan)
    lines = render(scene, 60, 24)
    grid = lines[1:-4]
    (hit_row,) = [i for i, row in enumerate(grid) if "*" in row]
    (turtle_row,) = [i for i, row in enumerate(grid) if "↑" in row]
    assert hit_row < turtle_row and grid[hit_row].index("*") == grid[turtle_row].index("↑")
    assert any(
        "o obstacle" in line and "* scan hit" in line and ". trail" in line and "X goal" in line for line in lines
    )
    assert any("c clears the trail" in line for line in lines)
    scene.router = "tcp/127.0.0.1:7447"
    assert "no router at tcp/127.0.0.1:7447" in render(scene, 80, 24)[-2]
    status = TurtleStatus(x=5, y=5, theta=0, vel_x=0, vel_y=0, battery=50)
    heading = render(Scene(world=World(size=10.0), pose=Pose(x=5.0, y=5.0, theta=-1e-9), status=status), 80, 24)[-2]
    assert "heading   0.0 deg" in heading


def test_the_outcome_says_why_and_what_to_do_next():
    low = NavigateToResponse(
        success=False,
        time_taken=0.0,
        reason="battery low",
        refused=True,
        detail="battery at 3.0 %, below the navigator's min_battery 5 %: `turtlectl reset` recharges it",
    )
    assert outcome_line(low) == f"refused: battery low ({low.detail})"
    blocked = NavigateToResponse(
        success=False, time_taken=12.0, reason="blocked", detail="the obstacle at (9, 9) stayed within 0.4 m"
    )
    assert outcome_line(blocked).startswith("not reached: blocked after 12.000 s (the obstacle at (9, 9) stayed")


def test_a_block_never_rounds_a_heading_up_to_360_and_writes_booleans_as_json_does():
    status = TurtleStatus(x=1.0, y=2.0, theta=359.99999, vel_x=0.0, vel_y=0.0, battery=50.0)
    assert "theta: 359.99999" in message_block(status)
    assert "contact: true" in message_block(Pose(x=2.0, y=8.5, theta=0.0, contact=True))


@pytest.mark.parametrize(
    "args",
    [
        ["list", "--domain", "lab9", "--connect", "tcp/127.0.0.1:1"],
        ["--domain", "lab9", "list", "--connect", "tcp/127.0.0.1:1"],
        ["--domain", "lab9", "--connect", "tcp/127.0.0.1:1", "list"],
        ["goto", "1", "1", "0", "--domain", "lab9", "--connect", "tcp/127.0.0.1:1"],
    ],
)
def test_domain_and_connect_work_before_and_after_the_command(args, monkeypatch):
    """A review found `turtlectl goto 5 5 0 --domain lab1` refused ("unexpected extra argument")
    right after a hint told the user to add --domain, and `turtlectl --connect ... list` refused."""
    monkeypatch.delenv(DOMAIN_ENV, raising=False)
    monkeypatch.delenv(CONNECT_ENV, raising=False)
    result = CliRunner().invoke(app, args)
    assert isinstance(result.exception, TurtlectlError), result.output  # it ran: nothing listens on port 1
    assert exit_code(result.exception) == ExitCode.UNREACHABLE and "tcp/127.0.0.1:1" in result.exception.message
    assert os.environ[DOMAIN_ENV] == "lab9"


def test_a_bad_domain_after_the_command_is_bad_input(monkeypatch):
    monkeypatch.delenv(DOMAIN_ENV, raising=False)
    result = CliRunner().invoke(app, ["list", "--domain", "a/b"])
    assert isinstance(result.exception, TurtlectlError) and exit_code(result.exception) == ExitCode.BAD_INPUT
