"""The capstone's success criteria (docs/capstone.md), one test each, against the real multi-process system."""

from __future__ import annotations

import json
import math
import statistics
import subprocess

import msgspec
import pytest

from messages import ErrorReply, NavigateToResponse, Pose, TurtleStatus, decode
from messages.keys import NAVIGATE_TO, STATUS
from tests.integration.harness import DEFAULT_LAUNCH, turtlectl

pytestmark = pytest.mark.integration


def latest_pose(system) -> Pose:
    return system.latest_pose()


def navigate(system, x: float, y: float, theta: float) -> tuple[NavigateToResponse, float]:
    response, elapsed, _ = system.navigate(x, y, theta)
    return response, elapsed


def test_1_goal_is_reached_within_a_centimetre_and_half_a_degree(system):
    response, _ = navigate(system, 7.5, 4.0, 45.0)
    assert response.success, response
    pose = latest_pose(system)  # checked independently of what the navigator says
    assert math.hypot(pose.x - 7.5, pose.y - 4.0) <= 0.01
    assert abs(math.degrees(math.remainder(pose.theta - math.radians(45.0), 2 * math.pi))) <= 0.5
    assert response.position_error <= 0.01 and response.heading_error <= 0.5


def test_2_goal_three_metres_away_is_reached_within_two_seconds(system):
    start = latest_pose(system)
    # 3 m towards the world's centre-ish, and face the opposite way at the end
    bearing = math.atan2(5.5 - start.y, 5.5 - start.x) if math.hypot(5.5 - start.x, 5.5 - start.y) > 1 else 0.3
    goal = (start.x + 3.0 * math.cos(bearing), start.y + 3.0 * math.sin(bearing))
    heading = (math.degrees(start.theta) + 180.0) % 360.0
    response, elapsed = navigate(system, goal[0], goal[1], heading)
    assert response.success, response
    assert elapsed <= 2.0, f"3 m goal took {elapsed:.3f} s"
    pose = latest_pose(system)
    assert math.hypot(pose.x - goal[0], pose.y - goal[1]) <= 0.01


def test_3_status_arrives_every_100_ms(system):
    samples = system.collect(STATUS, TurtleStatus, 51, timeout=15.0)
    times = [t for t, _ in samples]
    periods = [b - a for a, b in zip(times, times[1:], strict=False)]
    within = sum(1 for p in periods if abs(p - 0.100) <= 0.010)
    assert within >= 0.95 * len(periods), f"only {within}/{len(periods)} periods within 100 ± 10 ms: {periods}"
    assert abs(statistics.mean(periods) - 0.100) <= 0.001, statistics.mean(periods)
    seqs = [m.seq for _, m in samples]
    assert seqs == list(range(seqs[0], seqs[0] + 51)), "status messages were lost"
    status = samples[-1][1]
    assert 0.0 <= status.theta < 360.0 and 0.0 <= status.battery <= 100.0


def test_6_time_taken_matches_the_client_clock(system):
    for goal in ((3.0, 3.0, 180.0), (6.0, 7.0, -45.0)):
        response, elapsed = navigate(system, *goal)
        assert response.success, response
        assert abs(response.time_taken - elapsed) <= 0.1, (response.time_taken, elapsed)


def test_goto_cli_reaches_and_prints_json(system):
    result = system.run_cli("goto", "4", "6", "-90", "--json")
    assert result.returncode == 0, result.stderr
    response = json.loads(result.stdout)
    assert response["type"] == "NavigateToResponse" and response["success"] is True
    assert abs(response["theta"] - 270.0) <= 1.0


def test_goto_cli_reports_an_unreachable_goal_with_exit_1(system):
    result = system.run_cli("goto", "20", "5", "0")
    assert result.returncode == 1
    assert "outside the world" in result.stdout


def test_echo_decodes_status_as_blocks_and_json(system):
    blocks = system.run_cli("echo", "robot/status", "--once")
    assert blocks.returncode == 0, blocks.stderr
    assert (
        blocks.stdout.startswith("# TurtleStatus\n")
        and "battery:" in blocks.stdout
        and blocks.stdout.strip().endswith("---")
    )
    lines = system.run_cli("echo", "turtle1/pose", "--count", "3", "--json")
    assert lines.returncode == 0, lines.stderr
    decoded = [json.loads(line) for line in lines.stdout.splitlines()]
    assert len(decoded) == 3 and {d["type"] for d in decoded} == {"Pose"}


def test_echo_tells_the_user_when_nothing_is_published(system):
    result = system.run_cli("echo", "no/such/topic", "--timeout", "4")
    assert result.returncode == 3
    assert "nothing published on no/such/topic yet" in result.stderr
    assert "no message on no/such/topic within 4 s" in result.stderr


def test_second_launch_on_a_busy_port_fails_at_once(system, tmp_path):
    result = subprocess.run(
        [*turtlectl(), "launch", str(DEFAULT_LAUNCH), "--port", str(system.port), "--log-dir", str(tmp_path)],
        capture_output=True,
        text=True,
        timeout=20,
    )
    assert result.returncode == 4, result.stdout + result.stderr
    assert "already in use" in result.stderr and f"--port {system.port + 1}" in result.stderr
    assert "started" not in result.stdout  # at once: before anything was spawned
    assert list(tmp_path.iterdir()) == []  # and no empty log folder left behind


def test_7_malformed_payloads_are_dropped_and_every_node_keeps_running(system):
    pids = dict(system.wait_ready())
    session = system.session
    for key in ("turtle1/cmd_vel", "turtle1/pose", "obstacles", "robot/status"):
        for payload in (b"\xc1\xc1", b"not msgpack", msgspec.msgpack.encode({"type": "Twist", "linear": "x"})):
            session.put(key, payload)
    replies = system.call(NAVIGATE_TO, TurtleStatus(x=1, y=1, theta=0, vel_x=0, vel_y=0, battery=1))
    assert len(replies) == 1 and replies[0].err is not None
    error = decode(replies[0].err.payload.to_bytes(), ErrorReply).error
    assert "not a valid NavigateToRequest" in error
    # every node still serves: a goal works and status still flows, from the same processes
    response, _ = navigate(system, 5.0, 5.0, 0.0)
    assert response.success, response
    system.collect(STATUS, TurtleStatus, 3, timeout=5.0)
    system.wait_until(lambda: system.alive == pids, 2.0, "the same node processes")
    system.wait_line(r"sim .*dropped malformed payload #1 on turtle1/cmd_vel", 5.0)
    system.wait_line(r"navigator .*dropped malformed payload #1 on navigate_to", 5.0)
    assert not [line for line in system.lines if "Traceback" in line]
