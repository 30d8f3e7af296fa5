"""The goal lifecycle against the real processes: feedback, preemption, cancel, a caller
that vanishes, obstacles that block and clear, battery low, teleport and reset.

The lifecycle system runs without the obstacle detector: the test itself is the
sensor, publishing LaserScans on ``obstacles`` over Zenoh like the detector would.
"""

from __future__ import annotations

import math
import os
import pty
import queue
import signal
import subprocess
import threading
import time

import pytest

from tests.integration.harness import read_until_closed, running_system, turtlectl
from turtlectl.messages import Ack, Cancel, LaserScan, Reset, TeleportAbsolute, TurtleStatus, Twist, decode, encode
from turtlectl.messages.keys import CANCEL, CMD_VEL, OBSTACLES, RESET, STATUS, TELEPORT

pytestmark = pytest.mark.integration

LIFECYCLE = """
[world]
size = 11.088889

[[node]]
name = "sim"
run = "sim"
[[node]]
name = "navigator"
run = "navigator"
[node.params]
blocked_timeout = 3.0
scan_timeout = 60.0  # a scan is remembered until the next one: only a clear scan can clear the way
[[node]]
name = "status_monitor"
run = "status_monitor"
"""

LOW_BATTERY = """
[[node]]
name = "sim"
run = "sim"
[[node]]
name = "navigator"
run = "navigator"
[node.params]
min_battery = 5.0
[[node]]
name = "status_monitor"
run = "status_monitor"
[node.params]
battery = 3.0
drain_per_second = 10.0
"""


@pytest.fixture(scope="module")
def lifecycle(tmp_path_factory):
    path = tmp_path_factory.mktemp("goals") / "lifecycle.toml"
    path.write_text(LIFECYCLE)
    with running_system(path, ready=("sim", "navigator", "status_monitor")) as system:
        yield system


class Background:
    """A goal running on a thread, so the test can act while it runs."""

    def __init__(self, system, x, y, theta):
        self.result: queue.SimpleQueue = queue.SimpleQueue()
        self.thread = threading.Thread(target=lambda: self.result.put(system.navigate(x, y, theta)), daemon=True)
        self.thread.start()

    def outcome(self, timeout=20.0):
        return self.result.get(timeout=timeout)


def scan(blocking: bool) -> LaserScan:
    """A full-circle scan; with ``blocking``, something 0.3 m in every direction."""
    n = 72
    return LaserScan(
        angle_min=-math.pi,
        angle_max=math.pi - 2 * math.pi / n,
        angle_increment=2 * math.pi / n,
        range_min=0.0,
        range_max=10.0,
        ranges=[0.3 if blocking else math.inf] * n,
    )


def test_feedback_streams_while_a_goal_runs(lifecycle):
    lifecycle.teleport(2.0, 2.0, 0.0)
    response, elapsed, feedback = lifecycle.navigate(9.0, 8.0, 90.0)
    assert response.success, response
    assert len(feedback) >= int(elapsed * 10) - 2  # about 10 per second
    distances = [f.distance_remaining for f in feedback]
    assert distances[0] > 8.0 and distances[-1] < distances[0]
    assert {"turning", "driving"} & {f.state for f in feedback}
    assert all(f.eta >= 0 for f in feedback)


def test_a_new_goal_preempts_the_running_one(lifecycle):
    lifecycle.teleport(2.0, 5.0, 0.0)
    first = Background(lifecycle, 10.0, 5.0, 0.0)
    lifecycle.wait_moving()
    second, _, _ = lifecycle.navigate(3.0, 3.0, 180.0)
    old, _, _ = first.outcome()
    assert not old.success and old.reason == "preempted"
    assert second.success, second


def test_cancel_stops_the_turtle_and_tells_the_caller(lifecycle):
    lifecycle.teleport(1.0, 1.0, 0.0)
    cmds: queue.SimpleQueue = queue.SimpleQueue()
    sub = lifecycle.session.declare_subscriber(CMD_VEL, lambda s: cmds.put(decode(s.payload.to_bytes(), Twist)))
    try:
        goal = Background(lifecycle, 10.0, 1.0, 0.0)
        lifecycle.wait_moving()
        replies = lifecycle.call(CANCEL, Cancel())
        ack = decode(replies[0].ok.payload.to_bytes(), Ack)
        assert ack.ok and "canceled the goal (10, 1, 0 deg)" in ack.detail
        response, _, _ = goal.outcome()
        assert not response.success and response.reason == "canceled"
        # the navigator's last word on cmd_vel is a stop, and the turtle brakes to rest; the stop
        # may arrive after the goal's response (a sample and a query's reply take separate ways: the
        # queue can be read before the stop is in it), so wait for it, then nothing but stops
        last = cmds.get(timeout=5.0)
        while last != Twist(linear=0.0, angular=0.0, stamp=last.stamp, seq=last.seq):
            last = cmds.get(timeout=5.0)
        while not cmds.empty():
            last = cmds.get()
        assert last == Twist(linear=0.0, angular=0.0, stamp=last.stamp, seq=last.seq)
        stopped = lifecycle.wait_stopped()
        assert stopped.x < 10.0 - 0.01
    finally:
        sub.undeclare()
    again = decode(lifecycle.call(CANCEL, Cancel())[0].ok.payload.to_bytes(), Ack)
    assert not again.ok and again.detail == "no goal is running"


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGKILL])
def test_a_caller_that_goes_away_does_not_leave_the_turtle_driving(lifecycle, sig):
    lifecycle.teleport(1.0, 9.0, 0.0)
    start = len(lifecycle.lines)
    goto = subprocess.Popen(
        [*turtlectl(), "goto", "10", "2", "0", "--connect", lifecycle.endpoint],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        lifecycle.wait_moving()
        goto.send_signal(sig)
        goto.wait(5)
        # Ctrl-C: goto cancels it and checks the answer; kill -9: its client token vanishes
        reason = "canceled" if sig == signal.SIGINT else "caller gone"
        lifecycle.wait_line(rf"navigator .*goal failed .*: {reason}", 5.0, start)
        pose = lifecycle.wait_stopped()
        assert math.hypot(pose.x - 10.0, pose.y - 2.0) > 0.5  # stopped on the way, not at the goal
        if sig == signal.SIGINT:
            err = goto.stderr.read()
            assert goto.returncode == 130 and "interrupted: the navigator canceled the goal" in err, err
    finally:
        goto.kill()


def test_walled_in_then_cleared_resumes_by_itself(lifecycle):
    """The navigator remembers the blocking scan for its scan_timeout of 60 s, far longer
    than the test: the way can only clear because the clearing scans say so.  Something all
    round the turtle leaves no way: it stops and plans again with each scan ("replanning")."""
    lifecycle.teleport(2.0, 5.0, 0.0)
    pub = lifecycle.session.declare_publisher(OBSTACLES)
    try:
        goal = Background(lifecycle, 8.0, 5.0, 0.0)
        lifecycle.wait_moving()
        for _ in range(5):  # 1 s of "something 0.3 m ahead" at 5 Hz
            pub.put(encode(scan(True)))
            time.sleep(0.2)  # pacing: the sensor's 5 Hz
        stopped = lifecycle.wait_stopped()
        for _ in range(3):
            pub.put(encode(scan(False)))
            time.sleep(0.2)  # pacing: the sensor's 5 Hz
        response, _, feedback = goal.outcome()
    finally:
        pub.put(encode(scan(False)))  # whatever happened, the next test starts with a clear way
        pub.undeclare()
    assert response.success, response
    states = [f.state for f in feedback]
    assert "replanning" in states and states.index("replanning") < len(states) - 1
    assert states[-1] != "replanning" and feedback[-1].replans >= 1
    assert stopped.x < 8.0 - 1.0


def test_walled_in_too_long_gives_up_blocked(lifecycle):
    lifecycle.teleport(2.0, 5.0, 0.0)
    pub = lifecycle.session.declare_publisher(OBSTACLES)
    goal = Background(lifecycle, 8.0, 5.0, 0.0)
    try:
        deadline = time.monotonic() + 15
        while goal.result.empty() and time.monotonic() < deadline:
            pub.put(encode(scan(True)))
            time.sleep(0.2)  # pacing: the sensor's 5 Hz
        response, _, _ = goal.outcome()
        assert not response.success and response.reason == "blocked"
        assert "no way round what the scan sees" in response.detail
        assert 3.0 <= response.time_taken < 5.0
    finally:
        pub.put(encode(scan(False)))
        pub.undeclare()


def test_teleport_and_reset_like_turtlesim(lifecycle):
    lifecycle.teleport(3.0, 7.0, math.pi / 2)
    bad = lifecycle.call(TELEPORT, TeleportAbsolute(x=-1.0, y=2.0, theta=0.0))
    assert bad[0].err is not None and b"outside the world" in bad[0].err.payload.to_bytes()
    result = lifecycle.run_cli("teleport", "4", "6", "-90")
    assert result.returncode == 0 and "teleported to (4, 6" in result.stdout
    pose = lifecycle.latest_pose()
    assert (pose.x, pose.y) == pytest.approx((4.0, 6.0)) and pose.theta == pytest.approx(-math.pi / 2)
    result = lifecycle.run_cli("teleport", "40", "6", "0")
    assert result.returncode == 2 and "cannot teleport: (40, 6) is outside the world" in result.stderr
    replies = lifecycle.call(RESET, Reset(), everyone=True)
    details = sorted(decode(r.ok.payload.to_bytes(), Ack).detail for r in replies)
    assert details == ["turtle back at its spawn pose", "turtle1: battery full"]
    pose = lifecycle.latest_pose()
    assert (pose.x, pose.y, pose.theta) == pytest.approx((5.544445, 5.544445, 0.0), abs=1e-6)
    result = lifecycle.run_cli("reset")
    assert result.returncode == 0 and result.stdout == "turtle back at its spawn pose\nturtle1: battery full\n"
    status = lifecycle.collect(STATUS, TurtleStatus, 2, timeout=5.0)[-1][1]
    assert status.battery > 99.9


def test_goto_shows_live_progress_on_a_terminal_only(lifecycle):
    lifecycle.teleport(2.0, 2.0, 0.0)
    master, slave = pty.openpty()
    goto = subprocess.Popen(
        [*turtlectl(), "goto", "9", "9", "0", "--connect", lifecycle.endpoint], stdout=slave, stderr=slave
    )
    os.close(slave)
    out = read_until_closed(master)
    assert goto.wait(10) == 0, out.decode(errors="replace")
    text = out.decode()
    assert "\r\x1b[K" in text and "driving" in text and "reached at (9.0" in text
    piped = lifecycle.run_cli("goto", "2", "2", "0")
    assert piped.returncode == 0 and "\r" not in piped.stdout and piped.stdout.count("\n") == 1


def test_battery_low_refuses_goals_and_never_goes_below_zero(tmp_path):
    path = tmp_path / "low.toml"
    path.write_text(LOW_BATTERY)
    with running_system(path, ready=("sim", "navigator", "status_monitor")) as system:
        statuses = system.collect(STATUS, TurtleStatus, 5, timeout=5.0)
        assert all(s.battery >= 0.0 for _, s in statuses) and statuses[-1][1].battery == 0.0
        response, _, _ = system.navigate(3.0, 3.0, 0.0)
        assert not response.success and response.reason == "battery low"
        result = system.run_cli("goto", "3", "3", "0")
        assert result.returncode == 1 and "battery low" in result.stdout
