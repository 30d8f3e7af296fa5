"""A symmetric fleet: turtle1's nodes in namespace turtle1, as turtle2's are in turtle2 (its keys
turtle1/navigate_to, turtle1/robot/status); every tool addresses turtle1 as it addresses turtle2
(--turtle turtle1, Client(turtle="turtle1")), and without --turtle goto drives turtle1 there too."""

from __future__ import annotations

import threading

import pytest

from tests.integration.harness import running_system
from turtlectl.messages import TurtleStatus
from turtlectl.runtime.client.api import Client

pytestmark = pytest.mark.integration

KINDS = ("navigator", "status_monitor", "obstacle_detector")
TURTLES = ("turtle1", "turtle2")
NODES = ("sim", *(f"{t}/{k}" for t in TURTLES for k in KINDS))

LAUNCH = """
[[node]]
name = "sim"
run = "sim"
required = true
[node.params]
turtles = [{ name = "turtle2", x = 2.0, y = 5.5, theta = 0.0 }]
""" + "".join(
    f'\n[[group]]\nnamespace = "{t}"\n' + "".join(f'[[group.node]]\nname = "{k}"\nrun = "{k}"\n' for k in KINDS)
    for t in TURTLES
)


@pytest.fixture(scope="module")
def fleet(tmp_path_factory):
    path = tmp_path_factory.mktemp("symmetric") / "launch.toml"
    path.write_text(LAUNCH)
    with running_system(path, ready=NODES) as system:
        for turtle in TURTLES:
            system.collect(f"{turtle}/robot/status", TurtleStatus, 1, timeout=10.0)
        yield system


def test_turtle1s_keys_are_in_its_namespace(fleet):
    listed = fleet.run_cli("list")
    assert listed.returncode == 0, listed.stderr
    for key in ("turtle1/navigate_to", "turtle1/robot/status", "turtle1/obstacles", "turtle2/navigate_to"):
        assert key in listed.stdout, listed.stdout
    assert "turtle1/navigator" in listed.stdout


def test_every_tool_addresses_turtle1_as_turtle2(fleet):
    for turtle, x in (("turtle1", 5.5444), ("turtle2", 2.0)):
        status = fleet.run_cli("echo", "robot/status", "--turtle", turtle, "--once", "--json")
        assert status.returncode == 0 and f'"x":{x}' in status.stdout.replace(" ", ""), status.stdout + status.stderr
        got = fleet.run_cli("param", "get", "navigator", "goal_timeout", "--turtle", turtle)
        assert got.returncode == 0 and got.stdout.strip() == "30.0", got.stdout + got.stderr
        with Client(fleet.endpoint, turtle=turtle) as client:
            assert client.node_info("navigator").name == f"{turtle}/navigator"
            assert isinstance(client.latest("robot/status"), TurtleStatus)
    rates = fleet.run_cli("hz", "obstacles", "--turtle", "turtle1", "--duration", "1.5", "--json")
    assert rates.returncode == 0 and "turtle1/obstacles" in rates.stdout, rates.stdout + rates.stderr
    levels = fleet.run_cli("log-level", "turtle1", "INFO")
    assert levels.returncode == 0 and sorted(line.partition(":")[0] for line in levels.stdout.splitlines()) == [
        f"turtle1/{k}" for k in sorted(KINDS)
    ], levels.stdout + levels.stderr


def test_goals_reach_turtle1_with_and_without_turtle(fleet):
    named = fleet.run_cli("goto", "6.5", "5.5", "0", "--turtle", "turtle1")
    assert named.returncode == 0, named.stdout + named.stderr
    plain = fleet.run_cli("goto", "5.5", "6.5", "90")  # goto drives turtle1 wherever its nodes run
    assert plain.returncode == 0, plain.stdout + plain.stderr
    with Client(fleet.endpoint) as client:
        assert client.goto(5.5, 5.5, 0.0, timeout=20.0).success


def test_a_teleport_cancels_the_goal_of_turtle1s_navigator_in_its_namespace(fleet):
    """The simulator cancels a moved turtle's goal: turtle1's navigator in namespace turtle1 too."""
    result: dict[str, object] = {}

    def go() -> None:
        with Client(fleet.endpoint, turtle="turtle1") as client:
            result["r"] = client.goto(9.5, 5.5, 0.0, timeout=30.0)

    assert fleet.run_cli("teleport", "1", "5.5", "0").returncode == 0
    thread = threading.Thread(target=go)
    thread.start()
    started = lambda: any(  # noqa: E731
        line.startswith("turtle1/navigator ") and "goal (9.500, 5.500" in line for line in fleet.output().splitlines()
    )
    fleet.wait_until(started, 10.0, "turtle1's navigator to start the goal")
    moved = fleet.run_cli("teleport", "2", "2", "0", "--turtle", "turtle1")
    thread.join(30.0)
    assert moved.returncode == 0, moved.stdout + moved.stderr
    response = result["r"]
    assert not response.success and response.reason == "teleported", response
