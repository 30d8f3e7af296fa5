"""Simulated time, end to end: ``turtlectl launch --time-scale 5`` runs the simulator five times
as fast as the wall clock and every node on its ``clock``.  A goal is reached with the outcome
it has at 1x (success, within the navigator's tolerances), and its ``time_taken`` is in
simulated seconds: the movement as the poses' simulated stamps show it, more than the wall
clock saw go by.  The status monitor's 10 Hz is 10 Hz of simulated time."""

from __future__ import annotations

import math
import queue
import statistics
import time

import pytest

from tests.integration.harness import running_system
from turtlectl.messages import Clock, Pose, TurtleStatus, decode, encode
from turtlectl.messages.keys import CLOCK, POSE, STATUS

pytestmark = pytest.mark.integration


@pytest.fixture(scope="module")
def fast():
    with running_system(extra_args=("--time-scale", "5")) as system:
        yield system


def test_the_simulator_publishes_its_clock_at_the_factor(fast):
    clocks = [m for _, m in fast.collect(CLOCK, Clock, 20, timeout=10.0)]
    assert {c.real_time_factor for c in clocks} == {5.0}
    steps = {b.clock - a.clock for a, b in zip(clocks, clocks[1:], strict=False)}
    assert steps <= {16_000_000 * k for k in range(1, 10)}  # whole steps (a late one is skipped)


def test_a_goal_at_5x_has_the_outcome_of_1x_and_its_time_taken_in_simulated_seconds(fast):
    poses: queue.SimpleQueue[Pose] = queue.SimpleQueue()
    sub = fast.session.declare_subscriber(POSE, lambda s: poses.put(decode(s.payload.to_bytes(), Pose)))
    try:
        fast.wait_stopped()
        seen = [fast.wait_stopped()]
        while not poses.empty():  # the latest pose at rest before the call
            seen = [poses.get()]
        started = time.monotonic()
        response, _, _ = fast.navigate(3.0, 3.0, 180.0)
        wall = time.monotonic() - started
        fast.wait_stopped()
        while not poses.empty():
            seen.append(poses.get())
    finally:
        sub.undeclare()
    assert response.success, response
    assert response.position_error <= 0.01 and response.heading_error <= 0.5
    moving = [k for k, p in enumerate(seen) if p.linear_velocity != 0.0 or p.angular_velocity != 0.0]
    movement = (seen[moving[-1] + 1].stamp - seen[moving[0] - 1].stamp) / 1e9  # simulated s
    assert abs(response.time_taken - movement) <= 0.1, (response.time_taken, movement)
    assert response.time_taken > wall, f"{response.time_taken:.2f} simulated s took {wall:.2f} s of wall clock"
    distance = math.hypot(3.0 - seen[0].x, 3.0 - seen[0].y)
    assert response.time_taken >= distance / 4.0  # no faster than the turtle's 4 m/s in simulated time


def test_node_info_says_a_node_uses_sim_time(fast):
    """One can see whether a running node follows the clock."""
    done = fast.run_cli("node", "info", "navigator")
    assert done.returncode == 0, done.stderr
    assert "use_sim_time (its time is the simulator's clock)" in done.stdout.splitlines()[0]


def test_status_is_10_hz_of_simulated_time(fast):
    stamps = [m.stamp / 1e9 for _, m in fast.collect(STATUS, TurtleStatus, 21, timeout=10.0)]
    periods = [b - a for a, b in zip(stamps, stamps[1:], strict=False)]
    assert abs(statistics.median(periods) - 0.100) <= 0.010, periods


def test_verify_against_a_fast_system_measures_in_its_simulated_time_unasked(fast, tmp_path):
    """verify against a 5x system sees the clock's factor and measures goals in simulated time (in
    wall clock: "reported 1.537 s, the client measured 0.326 s")."""
    spec = tmp_path / "spec.toml"
    spec.write_text(
        'intent = "reported time"\n[[criterion]]\ncheck = "reported_time"\nname = "reported"\n'
        "goals = [[5.5, 5.5, 0.0]]\nwithin_s = 0.1\n"
    )
    done = fast.run_cli("verify", str(spec), timeout=120)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "the system's clock runs at 5x: measuring in its simulated time" in done.stderr


def test_launch_use_sim_time_puts_a_system_without_simulator_on_a_clock_from_elsewhere():
    """`launch --exclude sim --use-sim-time`, the system a replay (`play --clock`) drives: every
    node follows the clock key, and what it publishes is stamped with that clock's time, not the
    wall clock's (here the test publishes the clock and turtle1's pose, as a replay would)."""
    with running_system(extra_args=("--exclude", "sim", "--use-sim-time"), ready=()) as system:
        system.wait_ready(("navigator", "status_monitor", "obstacle_detector"))
        for node in ("navigator", "status_monitor", "obstacle_detector"):
            done = system.run_cli("node", "info", node)
            assert done.returncode == 0, done.stderr
            assert "use_sim_time (its time is the simulator's clock)" in done.stdout.splitlines()[0], done.stdout
        assert system.session is not None
        clock = system.session.declare_publisher(CLOCK)
        pose = system.session.declare_publisher(POSE)
        start = 10**18  # ns: 2001, far from the wall clock's time
        statuses: queue.SimpleQueue[TurtleStatus] = queue.SimpleQueue()
        sub = system.session.declare_subscriber(
            STATUS, lambda s: statuses.put(decode(s.payload.to_bytes(), TurtleStatus))
        )
        try:
            began = time.monotonic()
            got: list[TurtleStatus] = []
            while len(got) < 3:
                assert time.monotonic() - began < 15.0, "no status on the published clock within 15 s"
                now = start + int((time.monotonic() - began) * 1e9)
                clock.put(encode(Clock(clock=now, stamp=now)))
                pose.put(encode(Pose(x=5.5, y=5.5, theta=0.0, linear_velocity=0.0, angular_velocity=0.0, stamp=now)))
                while not statuses.empty():
                    got.append(statuses.get())
                time.sleep(0.01)  # pacing: the clock's 100 Hz, as play --clock 100
            elapsed = int((time.monotonic() - began) * 1e9)
        finally:
            sub.undeclare()
            clock.undeclare()
            pose.undeclare()
        assert all(start <= s.stamp <= start + elapsed + 10**9 for s in got), [s.stamp for s in got]


def test_launch_use_sim_time_with_its_simulator_runs_on_the_simulators_clock():
    """With the simulator in the launch, `--use-sim-time` puts every node on its clock at the wall
    clock's pace (as `--time-scale 1`); the simulator makes the clock and never waits for one."""
    with running_system(extra_args=("--use-sim-time",)) as system:
        done = system.run_cli("node", "info", "navigator")
        assert "use_sim_time (its time is the simulator's clock)" in done.stdout.splitlines()[0], done.stdout
        clocks = [m for _, m in system.collect(CLOCK, Clock, 3, timeout=10.0)]
        assert {c.real_time_factor for c in clocks} == {1.0}
        [(_, status)] = system.collect(STATUS, TurtleStatus, 1, timeout=10.0)
        assert abs(status.stamp - clocks[-1].clock) < 5 * 10**9
