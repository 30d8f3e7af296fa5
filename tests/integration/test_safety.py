"""Safety, the node side, against the real processes: huge headings, declared obstacles known
to the navigator without scans and solid in the simulator, goals behind them planned round and
goals too near them refused at once, one navigator at a time, reply encodings, teleport and reset under a running goal.

The system runs the default world (three obstacles) without the obstacle detector, as
``turtlectl launch --exclude obstacle_detector`` would: the navigator has no scans at all.
"""

from __future__ import annotations

import math
import queue
import signal
import subprocess
import time

import pytest
import zenoh

from tests.integration.harness import running_system, turtlectl
from tests.integration.test_goals import Background
from turtlectl.messages import (
    Ack,
    NavigateToRequest,
    Pose,
    Reset,
    TeleportAbsolute,
    TurtleStatus,
    Twist,
    decode,
    decode_any,
    encode,
    encoding_for,
)
from turtlectl.messages.keys import CMD_VEL, NAVIGATE_TO, POSE, RESET, STATUS, TELEPORT

pytestmark = pytest.mark.integration

NO_SCANS = """
[world]
obstacles = [
  { x = 2.0, y = 9.0, radius = 0.5 },
  { x = 9.0, y = 9.0, radius = 0.6 },
  { x = 9.0, y = 2.0, radius = 0.4 },
]
[[node]]
name = "sim"
run = "sim"
[[node]]
name = "navigator"
run = "navigator"
[[node]]
name = "status_monitor"
run = "status_monitor"
"""


@pytest.fixture(scope="module")
def no_scans(tmp_path_factory):
    path = tmp_path_factory.mktemp("safety") / "no_scans.toml"
    path.write_text(NO_SCANS)
    with running_system(path, ready=("sim", "navigator", "status_monitor")) as system:
        system.launch_file = path
        yield system


@pytest.mark.parametrize("theta, reduced", [(1e16, 280.0), (1e308, 296.0), (-1e16, 80.0)])
def test_huge_headings_are_reduced_in_degrees_and_reached(no_scans, theta, reduced):
    no_scans.teleport(5.0, 5.0, 0.0)
    response, _, feedback = no_scans.navigate(5.0, 5.0, theta)
    assert response.success, response
    assert response.theta == pytest.approx(reduced, abs=0.5) and response.time_taken < 5.0
    assert all(f.goal_theta == pytest.approx(reduced) for f in feedback)


def test_a_goal_behind_a_declared_obstacle_is_reached_round_it_without_scans(no_scans):
    no_scans.teleport(5.544445, 5.544445, 0.0)
    response, _, feedback = no_scans.navigate(10.5, 10.5, 0.0)  # the obstacle at (9, 9) on the straight way
    assert response.success, response
    assert feedback and all(f.scan_stale for f in feedback) and len(feedback[0].path) > 2


def test_a_goal_within_the_margin_of_a_declared_obstacle_is_refused_at_once_without_scans(no_scans):
    no_scans.teleport(5.544445, 5.544445, 0.0)
    response, elapsed, _ = no_scans.navigate(2.0, 9.6, 0.0)
    assert response.refused and not response.success and elapsed < 1.0, response
    assert response.reason == "invalid goal" and "m from the obstacle at (2, 9)" in response.detail
    assert no_scans.wait_stopped().x == pytest.approx(5.544445)


def test_without_scans_the_navigator_says_so_and_still_reaches_free_goals(no_scans):
    no_scans.teleport(2.0, 2.0, 0.0)
    start = len(no_scans.lines)
    response, _, feedback = no_scans.navigate(6.0, 3.0, 0.0)
    assert response.success, response
    assert feedback and all(f.scan_stale for f in feedback)
    no_scans.wait_line(r"navigator .*no recent scan: avoiding only the declared obstacles", 2.0, start)


def test_a_declared_obstacle_is_solid(no_scans):
    no_scans.teleport(2.0, 7.5, math.pi / 2)  # 1 m below the obstacle at (2, 9), r 0.5, facing it
    poses: queue.SimpleQueue = queue.SimpleQueue()
    sub = no_scans.session.declare_subscriber(POSE, lambda s: poses.put(decode(s.payload.to_bytes(), Pose)))
    pub = no_scans.session.declare_publisher(CMD_VEL, encoding=zenoh.Encoding(encoding_for(Twist)))
    start = len(no_scans.lines)
    try:
        deadline = time.monotonic() + 5.0
        seen: list[Pose] = []
        while not any(p.contact for p in seen):
            assert time.monotonic() < deadline, f"no contact within 5 s: {seen[-1:]}"
            pub.put(encode(Twist(linear=1.0)))
            time.sleep(0.1)  # pacing: a 10 Hz teleop
            while not poses.empty():
                seen.append(poses.get())
        for _ in range(5):  # keep pushing for another half second
            pub.put(encode(Twist(linear=1.0)))
            time.sleep(0.1)  # pacing: a 10 Hz teleop
        while not poses.empty():
            seen.append(poses.get())
    finally:
        sub.undeclare()
        pub.undeclare()
    assert all(math.hypot(p.x - 2.0, p.y - 9.0) >= 0.5 - 1e-9 for p in seen)
    assert seen[-1].y == pytest.approx(8.5, abs=1e-6) and seen[-1].contact
    no_scans.wait_line(r"sim .*contact with an obstacle at \(2\.000, 8\.500\)", 2.0, start)


def test_every_reply_names_its_own_type(no_scans):
    no_scans.teleport(2.0, 2.0, 0.0)
    replies = no_scans.call(NAVIGATE_TO, NavigateToRequest(x=6.0, y=2.5, theta=0.0))
    encodings = {type(decode_any(r.ok.payload.to_bytes())).__name__: str(r.ok.encoding) for r in replies}
    assert encodings == {
        "NavigateToFeedback": "application/msgpack;turtlectl/NavigateToFeedback",
        "NavigateToResponse": "application/msgpack;turtlectl/NavigateToResponse",
    }


@pytest.mark.parametrize(
    "node, says", [("navigator", "already serves navigate_to"), ("status_monitor", "already publishes robot/status")]
)
def test_a_second_navigator_or_status_monitor_refuses_to_start(no_scans, node, says):
    second = subprocess.run(
        [*turtlectl(), "run", node, "--file", str(no_scans.launch_file), "--connect", no_scans.endpoint],
        capture_output=True,
        text=True,
        timeout=30,
        stdin=subprocess.DEVNULL,
    )
    assert second.returncode == 4, second.stdout + second.stderr
    assert says in second.stderr and "not starting a second one" in second.stderr
    # the first one still serves
    no_scans.teleport(2.0, 2.0, 0.0)
    assert no_scans.navigate(3.0, 2.0, 0.0)[0].success


@pytest.mark.parametrize("how", ["teleported", "reset"])
def test_teleport_or_reset_cancel_a_running_goal(no_scans, how):
    no_scans.teleport(1.0, 5.0, 0.0)
    goal = Background(no_scans, 7.0, 5.0, 0.0)
    no_scans.wait_moving()
    if how == "teleported":
        replies = no_scans.call(TELEPORT, TeleportAbsolute(x=3.0, y=3.0, theta=0.0))
    else:
        replies = no_scans.call(RESET, Reset(), everyone=True)
    assert replies and all(r.ok is not None for r in replies)
    response, _, _ = goal.outcome()
    assert not response.success and response.reason == how, response
    pose = no_scans.wait_stopped()
    expected = (3.0, 3.0) if how == "teleported" else (5.544445, 5.544445)
    assert (pose.x, pose.y) == pytest.approx(expected, abs=1e-6)


def test_a_goal_sent_right_after_the_teleport_ack_starts_from_the_new_pose(no_scans):
    """(2, 10) lies behind the obstacle at (2, 9) seen from the spawn and 0.5 m straight ahead
    from (2, 10.5): a goal sent the moment the teleport is acknowledged must be planned from
    where the turtle is then: the Ack comes once the pose shows the teleport (before it, the
    navigator could still have the old pose and plan round the obstacle from the old place)."""
    for _ in range(5):
        no_scans.teleport(5.544445, 5.544445, 0.0)
        replies = no_scans.call(TELEPORT, TeleportAbsolute(x=2.0, y=10.5, theta=-math.pi / 2))
        assert decode(replies[0].ok.payload.to_bytes(), Ack).ok
        response, _, feedback = no_scans.navigate(2.0, 10.0, 270.0)
        assert response.success, response
        assert feedback[0].path == [pytest.approx((2.0, 10.5)), pytest.approx((2.0, 10.0))]


def test_teleports_are_not_charged_to_the_battery(no_scans):
    no_scans.teleport(1.0, 1.0, 0.0)
    for target in ((10.0, 1.0), (1.0, 10.0), (10.0, 6.0)):
        before = no_scans.collect(STATUS, TurtleStatus, 1, timeout=2.0)[0][1].battery
        no_scans.teleport(*target, 0.0)
        after = no_scans.collect(STATUS, TurtleStatus, 3, timeout=2.0)[-1][1]
        assert (after.x, after.y) == pytest.approx(target)
        assert before - after.battery < 0.01, (before, after.battery)  # 9 m would cost 0.9 %


def test_small_teleports_are_not_charged_to_the_battery_either(no_scans):
    """0.5 m teleports do not count as travel (read 0.1 s apart they would: 1 % of battery for
    twenty of them; time alone drains about 0.1 %)."""
    before = no_scans.collect(STATUS, TurtleStatus, 1, timeout=2.0)[0][1].battery
    for k in range(20):
        no_scans.teleport(3.0 + 0.5 * (k % 2), 3.0, 0.0)
        no_scans.collect(STATUS, TurtleStatus, 2, timeout=2.0)  # a status tick after each teleport
    after = no_scans.collect(STATUS, TurtleStatus, 3, timeout=2.0)[-1][1].battery
    assert before - after < 0.5, (before, after)  # 10 m of teleports would cost 1 %


def test_a_node_run_in_another_domain_joins_that_domain_not_this_system(no_scans):
    """`turtlectl --domain lab3 run navigator` starts the node in its --domain, not in the plain
    system (where it would be refused as a second navigator)."""
    tokens: queue.SimpleQueue = queue.SimpleQueue()
    watch = no_scans.session.liveliness().declare_subscriber(
        "lab3/@turtlectl/node/**", lambda s: tokens.put(str(s.key_expr))
    )
    other = subprocess.Popen(
        [
            *turtlectl(),
            "--domain",
            "lab3",
            "run",
            "navigator",
            "--file",
            str(no_scans.launch_file),
            "--connect",
            no_scans.endpoint,
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        stdin=subprocess.DEVNULL,
        text=True,
    )
    try:
        deadline = time.monotonic() + 15
        token = None
        while token is None:
            assert other.poll() is None, other.communicate()[0]
            assert time.monotonic() < deadline, "no lab3 navigator token within 15 s"
            try:
                token = tokens.get(timeout=0.2)
            except queue.Empty:
                pass
        assert token.startswith("lab3/@turtlectl/node/navigator/"), token
    finally:
        watch.undeclare()
        other.send_signal(signal.SIGINT)
        try:
            other.wait(5)
        except subprocess.TimeoutExpired:
            other.kill()


def test_reset_and_cancel_need_no_payload_at_all(no_scans):
    """docs/interfaces.md says a request without fields may be sent empty: a get on `reset`
    without a payload is answered, not with an ErrorReply ("Input data was truncated")."""
    replies = list(
        no_scans.session.get(
            RESET, consolidation=zenoh.ConsolidationMode.NONE, target=zenoh.QueryTarget.ALL, timeout=5.0
        )
    )
    assert len(replies) == 2 and all(r.ok is not None for r in replies), [r.err for r in replies]
    assert {decode(r.ok.payload.to_bytes(), Ack).detail for r in replies} == {
        "turtle1: battery full",
        "turtle back at its spawn pose",
    }


def test_the_turtle_may_be_teleported_onto_an_obstacle_s_surface_where_a_push_stops(no_scans):
    no_scans.teleport(2.0, 8.5, 0.0)  # the surface of the obstacle at (2, 9), r 0.5
    inside = no_scans.call(TELEPORT, TeleportAbsolute(x=2.0, y=8.6, theta=0.0))
    assert inside[0].err is not None and b"inside an obstacle" in inside[0].err.payload.to_bytes()


def test_a_goal_and_a_teleport_inside_an_obstacle_are_refused_with_the_same_exit_code(no_scans):
    no_scans.teleport(5.544445, 5.544445, 0.0)
    goal = no_scans.run_cli("goto", "2", "9", "0")  # the centre of the obstacle at (2, 9)
    teleport = no_scans.run_cli("teleport", "2", "9", "0")
    assert "inside an obstacle" in goal.stdout + goal.stderr and "inside an obstacle" in teleport.stderr
    assert goal.returncode == teleport.returncode == 2, (goal, teleport)
