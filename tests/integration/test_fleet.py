"""A fleet from one launch file (examples/fleet/launch.toml): three turtles, each with
its navigator, status monitor and obstacle detector, turtle2's and turtle3's in namespaces
(``[[group]]``).  Every tool reaches each turtle (``--turtle``), goals to all at once, two
turtles sent across each other's way both arrive without touching, reset puts every turtle of
the launch file back."""

from __future__ import annotations

import math
import signal
import subprocess
import threading
from pathlib import Path

import pytest

from tests.integration.harness import running_system, turtlectl
from turtlectl.messages import LaserScan, Turtles, TurtleStatus
from turtlectl.messages.keys import TURTLES
from turtlectl.runtime.client.api import Client

pytestmark = pytest.mark.integration

FLEET = Path(__file__).resolve().parents[2] / "examples" / "fleet" / "launch.toml"
KINDS = ("navigator", "status_monitor", "obstacle_detector")
NODES = ("sim", *KINDS, *(f"{t}/{k}" for t in ("turtle2", "turtle3") for k in KINDS))
STARTS = {"turtle1": (5.544445, 5.544445), "turtle2": (2.0, 5.5), "turtle3": (9.0, 5.5)}


@pytest.fixture(scope="module")
def fleet():
    with running_system(FLEET, ready=NODES) as system:
        for key in ("robot/status", "turtle2/robot/status", "turtle3/robot/status"):
            system.collect(key, TurtleStatus, 1, timeout=10.0)  # every turtle's data path flows
        yield system


def positions(system) -> dict[str, tuple[float, float]]:
    msg = system.collect(TURTLES, Turtles, 1, timeout=5.0)[0][1]
    return {n: (x, y) for n, x, y in zip(msg.names, msg.x, msg.y, strict=True)}


def goals_at_once(system, goals: dict[str, tuple[float, float, float]]) -> dict[str, object]:
    """Send each turtle its goal at once (a Client per turtle, in threads); each one's response."""
    done: dict[str, object] = {}

    def go(turtle: str) -> None:
        with Client(system.endpoint, turtle=turtle) as client:
            done[turtle] = client.goto(*goals[turtle], timeout=30.0)

    threads = [threading.Thread(target=go, args=(t,)) for t in goals]
    for t in threads:
        t.start()
    for t in threads:
        t.join(60.0)
    return done


def test_every_tool_sees_each_turtles_nodes_under_its_namespace(fleet):
    listed = fleet.run_cli("list")
    assert listed.returncode == 0, listed.stderr
    text = listed.stdout
    for key in ("turtle2/navigate_to", "turtle3/robot/status", "turtle2/obstacles", "turtle3/cmd_vel"):
        assert key in text, text
    assert "turtle2/navigator" in text and "turtle3/obstacle_detector" in text
    got = fleet.run_cli("param", "get", "turtle3/navigator", "goal_timeout")
    assert got.returncode == 0 and got.stdout.strip() == "60.0", got.stdout + got.stderr  # its own parameters
    assert fleet.run_cli("param", "get", "navigator", "goal_timeout").stdout.strip() == "30.0"
    status = fleet.run_cli("echo", "robot/status", "--turtle", "turtle3", "--once", "--json")
    assert status.returncode == 0 and '"x":9.0' in status.stdout.replace(" ", ""), status.stdout + status.stderr


def test_goals_to_every_turtle_at_once_are_all_reached(fleet):
    goals = {"turtle1": (5.5, 8.0, 90.0), "turtle2": (2.0, 3.0, -90.0), "turtle3": (9.0, 7.5, 90.0)}
    done = goals_at_once(fleet, goals)
    assert {t: getattr(r, "success", None) for t, r in done.items()} == dict.fromkeys(goals, True), done
    where = positions(fleet)
    for turtle, (x, y, _) in goals.items():
        assert math.dist(where[turtle], (x, y)) < 0.02, (turtle, where[turtle])
    back = fleet.run_cli("reset")
    assert back.returncode == 0 and "turtles back at their spawn poses" in back.stdout, back.stdout + back.stderr
    where = positions(fleet)
    for turtle, start in STARTS.items():
        assert math.dist(where[turtle], start) < 1e-6, (turtle, where[turtle])


def test_two_turtles_sent_across_each_others_way_both_arrive_and_never_touch(fleet):
    assert fleet.run_cli("teleport", "1", "1", "0").returncode == 0  # turtle1 out of the crossing
    assert fleet.run_cli("teleport", "2", "5.5", "0", "--turtle", "turtle2").returncode == 0
    assert fleet.run_cli("teleport", "5.5", "2", "90", "--turtle", "turtle3").returncode == 0
    least = [math.inf]
    sub = fleet.session.declare_subscriber(TURTLES, lambda s: least.__setitem__(0, min(least[0], _gap(s))))
    goals = {"turtle2": (9.0, 5.5, 0.0), "turtle3": (5.5, 9.0, 90.0)}
    done = goals_at_once(fleet, goals)
    sub.undeclare()
    assert {t: getattr(r, "success", None) for t, r in done.items()} == dict.fromkeys(goals, True), done
    assert least[0] >= 2 * 0.3, least[0]  # centres apart by at least two turtle radii: never touched
    assert "turtle2: contact" not in fleet.output() and "turtle3: contact" not in fleet.output()
    fleet.run_cli("reset")


def _gap(sample) -> float:
    from turtlectl.messages import decode

    msg = decode(sample.payload.to_bytes(), Turtles)
    where = dict(zip(msg.names, zip(msg.x, msg.y, strict=True), strict=True))
    return math.dist(where["turtle2"], where["turtle3"]) if {"turtle2", "turtle3"} <= where.keys() else math.inf


def test_two_turtles_swapping_places_head_on_both_arrive(fleet):
    """Sent to each other's places after standing in each other's scans, both goals are reached:
    an idle navigator reads `turtles` too, so the other turtle's scan hits do not enter its
    costmap (each goal would lie in a remembered obstacle)."""
    assert fleet.run_cli("reset").returncode == 0
    assert fleet.run_cli("teleport", "1", "1", "0").returncode == 0
    assert fleet.run_cli("teleport", "3", "5.5", "0", "--turtle", "turtle2").returncode == 0
    assert fleet.run_cli("teleport", "8", "5.5", "180", "--turtle", "turtle3").returncode == 0
    for key in ("turtle2/obstacles", "turtle3/obstacles"):  # idle, each scans the other a few times
        fleet.collect(key, LaserScan, 3, timeout=5.0)
    done = goals_at_once(fleet, {"turtle2": (8.0, 5.5, 0.0), "turtle3": (3.0, 5.5, 180.0)})
    assert {t: (getattr(r, "success", None), getattr(r, "reason", "")) for t, r in done.items()} == {
        "turtle2": (True, ""),
        "turtle3": (True, ""),
    }, done
    fleet.run_cli("reset")


def test_a_users_node_class_run_in_a_turtles_namespace_drives_that_turtle(fleet):
    """`turtlectl run ./patrol.py:Patrol --namespace turtle2`: the example's patrol, written for
    turtle1 (it calls navigate_to), is turtle2/patrol and calls turtle2/navigate_to."""
    patrol = FLEET.parent.parent / "patrol" / "patrol.py"
    run = subprocess.Popen(
        [*turtlectl(), "run", f"{patrol}:Patrol", "--namespace", "turtle2", "-p", "cx=2.5", "-p", "cy=3.5"]
        + ["-p", "side=1.0", "--connect", fleet.endpoint],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        stdin=subprocess.DEVNULL,
        text=True,
    )
    lines: list[str] = []
    threading.Thread(target=lambda: lines.extend(run.stdout), daemon=True).start()  # type: ignore[arg-type]
    try:
        reached = lambda: any("corner 0 reached" in line for line in lines)  # noqa: E731
        fleet.wait_until(lambda: reached() or run.poll() is not None, 60.0, "the patrol to reach its first corner")
        assert reached(), "".join(lines)
        assert "turtle2/patrol" in fleet.run_cli("list").stdout
        assert "turtle2/patrol" in fleet.run_cli("node", "list").stdout.splitlines()
    finally:
        run.send_signal(signal.SIGINT)
        run.wait(15)
    assert any("as node turtle2/patrol" in line for line in lines), "".join(lines)
    assert any(line.startswith("turtle2/navigator ") and "goal reached" in line for line in fleet.output().splitlines())
    fleet.run_cli("reset")


def test_teleporting_a_turtle_cancels_its_own_navigators_goal(fleet):
    result: dict[str, object] = {}

    def go() -> None:
        with Client(fleet.endpoint, turtle="turtle2") as client:
            result["r"] = client.goto(2.0, 1.0, 0.0, timeout=30.0)

    fleet.run_cli("teleport", "2", "9", "90", "--turtle", "turtle2")
    thread = threading.Thread(target=go)
    thread.start()
    started = lambda: any(  # noqa: E731
        line.startswith("turtle2/navigator ") and "goal (2.000, 1.000" in line for line in fleet.output().splitlines()
    )
    fleet.wait_until(started, 10.0, "turtle2's navigator to start the goal")
    moved = fleet.run_cli("teleport", "4", "4", "0", "--turtle", "turtle2")
    thread.join(30.0)
    assert moved.returncode == 0 and moved.stdout.startswith("turtle2 "), moved.stdout + moved.stderr
    response = result["r"]
    assert not response.success and response.reason == "teleported", response
    fleet.run_cli("reset")


def test_a_client_of_a_turtle_names_its_nodes_as_it_names_its_keys(fleet):
    """Client(turtle="turtle3").param("navigator", ...) answered turtle1's navigator's value, and
    set_param reconfigured turtle1's navigator: node names are resolved in the turtle's namespace,
    as keys are (``/sim``: outside any)."""
    with Client(fleet.endpoint, turtle="turtle3") as client:
        assert client.param("navigator", "goal_timeout") == 60.0
        assert client.node_info("navigator").name == "turtle3/navigator"
        assert client.params("/sim")["x"] == 5.544445
        client.set_param("navigator", "goal_timeout", 50.0)
    try:
        with Client(fleet.endpoint) as plain:  # without a turtle, names as written
            assert plain.param("navigator", "goal_timeout") == 30.0  # turtle1's untouched
            assert plain.param("turtle3/navigator", "goal_timeout") == 50.0
        got = fleet.run_cli("param", "get", "navigator", "goal_timeout", "--turtle", "turtle3")
        assert got.returncode == 0 and got.stdout.strip() == "50.0", got.stdout + got.stderr
        every = fleet.run_cli("param", "get", "*/navigator", "goal_timeout")
        assert every.returncode == 0, every.stderr
        assert set(every.stdout.split("\n")) >= {"turtle2/navigator: 30.0", "turtle3/navigator: 50.0"}, every.stdout
    finally:
        fleet.run_cli("param", "set", "navigator", "goal_timeout", "60", "--turtle", "turtle3")


def test_log_level_takes_a_glob_a_namespace_and_a_turtle(fleet):
    """`log-level 'turtle2/*' DEBUG` was refused though `log --node` takes globs."""
    glob = fleet.run_cli("log-level", "turtle2/*", "DEBUG")
    assert glob.returncode == 0, glob.stderr
    assert [line.partition(":")[0] for line in glob.stdout.splitlines()] == [f"turtle2/{k}" for k in sorted(KINDS)]
    first = fleet.run_cli("log-level", "turtle1", "INFO")  # turtle1's nodes: outside any namespace, not the simulator
    assert first.returncode == 0, first.stderr
    assert sorted(line.partition(":")[0] for line in first.stdout.splitlines()) == sorted(KINDS), first.stdout
    fleet.run_cli("log-level", "turtle2", "INFO")
    none = fleet.run_cli("log-level", "turtle9/*", "DEBUG")
    assert none.returncode == 3 and "no node named 'turtle9/*'" in none.stderr, none.stderr
