"""Issue 13 against the real system: parameters changed while nodes run (set, describe, events,
--persist), node and topic info, log levels, and keyboard teleop through a pseudo-terminal."""

from __future__ import annotations

import json
import os
import signal
import statistics
import subprocess
import termios
import time

import pytest

from cli.errors import ExitCode
from messages import ParameterEvent, TurtleStatus, Twist, decode
from messages.keys import CMD_VEL, PARAMETER_EVENTS, STATUS
from tests.integration.harness import in_pty, pump, running_system, set_winsize, turtlectl

pytestmark = pytest.mark.integration


class Screen:
    """What a program in a pseudo-terminal wrote (raw text is enough for a status line)."""

    def __init__(self):
        self.text = ""

    def feed(self, data: bytes) -> None:
        self.text += data.decode("utf-8", "replace")


def get(system, node: str, name: str):
    result = system.run_cli("param", "get", node, name)
    assert result.returncode == 0, result.stderr
    return json.loads(result.stdout)


def test_param_set_takes_effect_at_once_and_publishes_an_event(system):
    events = []
    sub = system.session.declare_subscriber(PARAMETER_EVENTS, lambda s: events.append(s.payload.to_bytes()))
    try:
        result = system.run_cli("param", "set", "status_monitor", "rate", "2")
        assert result.returncode == 0, result.stderr
        assert result.stdout.strip() == "status_monitor rate = 2.0 (was 10.0)"
        system.wait_until(lambda: bool(events), 5.0, "a parameter event")
    finally:
        sub.undeclare()
    event = decode(events[0], ParameterEvent)
    assert (event.node, event.name, event.old_value, event.new_value) == ("status_monitor", "rate", 10.0, 2.0)
    assert get(system, "status_monitor", "rate") == 2.0
    statuses = system.collect(STATUS, TurtleStatus, 5, timeout=10.0)
    periods = [b[0] - a[0] for a, b in zip(statuses, statuses[1:], strict=False)]
    assert statistics.median(periods) > 0.3, periods  # 2 Hz now, not 10 Hz
    described = system.run_cli("param", "describe", "status_monitor", "rate", "--json")
    assert described.returncode == 0, described.stderr
    info = json.loads(described.stdout)
    assert (info["value"], info["unit"], info["range"], info["default"], info["run_time"]) == (
        2.0,
        "Hz",
        "0.1 to 100",
        "10",
        True,
    )
    assert system.run_cli("param", "set", "status_monitor", "rate", "10").returncode == 0


def test_a_goal_runs_with_the_navigator_parameters_set_a_moment_ago(system):
    system.teleport(1.0, 5.5, 0.0)
    assert system.run_cli("param", "set", "navigator", "goal_timeout", "0.3").returncode == 0
    try:
        goal = system.run_cli("goto", "10", "5.5", "0")
        assert goal.returncode == ExitCode.FAILED and "timeout" in goal.stdout + goal.stderr, goal
    finally:
        assert system.run_cli("param", "set", "navigator", "goal_timeout", "30").returncode == 0
    assert system.run_cli("goto", "3", "5.5", "0").returncode == 0


def test_param_set_refuses_as_the_launch_file_does_and_names_what_cannot_change(system):
    typo = system.run_cli("param", "set", "navigator", "goal_timeot", "5")
    launch = subprocess.run(
        [*turtlectl(), "launch", "--check", "--set", "navigator.goal_timeot=5"], capture_output=True, text=True
    )
    assert typo.returncode == launch.returncode == ExitCode.BAD_INPUT
    same = "navigator.goal_timeot: unknown key; did you mean goal_timeout?"
    assert same in typo.stderr and same in launch.stderr, (typo.stderr, launch.stderr)
    low = system.run_cli("param", "set", "navigator", "goal_timeout", "-5")
    assert low.returncode == ExitCode.BAD_INPUT and "navigator: goal_timeout must be >= 0.1 (got -5)" in low.stderr
    slow_scan = system.run_cli("param", "set", "obstacle_detector", "rate", "0.5")
    assert slow_scan.returncode == ExitCode.BAD_INPUT and "is not longer than the scan period" in slow_scan.stderr
    spawn = system.run_cli("param", "set", "sim", "x", "3")
    assert spawn.returncode == ExitCode.BAD_INPUT
    assert "cannot change while sim runs: the spawn pose is read once, at start" in spawn.stderr
    # the node refuses too, for a client that skips the command line's checks
    direct = system.run_cli("call", "turtlectl/params/sim/set", '{"name": "x", "value": 3}')
    assert direct.returncode == ExitCode.BAD_INPUT and "x cannot change at run time" in direct.stderr
    assert get(system, "sim", "x") == pytest.approx(5.544445)
    nobody = system.run_cli("param", "set", "nobody", "rate", "1")
    assert nobody.returncode == ExitCode.UNREACHABLE and "no node named 'nobody'" in nobody.stderr
    listed = json.loads(system.run_cli("param", "list", "--json").stdout)
    assert (
        set(listed) == {"navigator", "obstacle_detector", "sim", "status_monitor"}
        and "rate" in listed["status_monitor"]
    )


def test_a_respawned_node_starts_with_the_launch_file_values(system):
    assert system.run_cli("param", "set", "status_monitor", "drain_per_metre", "0.5").returncode == 0
    pid = system.alive["status_monitor"]
    os.kill(pid, signal.SIGKILL)
    system.wait_until(lambda: system.alive.get("status_monitor", pid) != pid, 15.0, "status_monitor respawned")
    assert get(system, "status_monitor", "drain_per_metre") == 0.1


def test_persist_keeps_a_change_for_the_respawned_node_and_launch_log_level_sets_every_node():
    with running_system(extra_args=("--persist", "--log-level", "warning")) as system:
        assert system.run_cli("param", "set", "status_monitor", "drain_per_metre", "0.5").returncode == 0
        system.wait_line(r"status_monitor drain_per_metre = 0.5 kept for its next start \(--persist\)", 5.0)
        pid = system.alive["status_monitor"]
        os.kill(pid, signal.SIGKILL)
        system.wait_until(lambda: system.alive.get("status_monitor", pid) != pid, 15.0, "status_monitor respawned")
        assert get(system, "status_monitor", "drain_per_metre") == 0.5
        info = json.loads(system.run_cli("node", "info", "navigator", "--json").stdout)
        assert info["log_level"] == "WARNING"
        assert not [line for line in system.output().splitlines() if "| INFO ready" in line], system.output()


def test_node_info_and_topic_info_describe_the_running_graph(system):
    result = system.run_cli("node", "info", "navigator", "--json")
    assert result.returncode == 0, result.stderr
    info = json.loads(result.stdout)
    assert (info["kind"], info["pid"]) == ("navigator", system.alive["navigator"]) and info["uptime"] > 0
    assert {"key": "turtle1/cmd_vel", "type": "Twist"} in info["publishers"]
    assert {"key": "turtle1/pose", "type": "Pose"} in info["subscribers"]
    assert {"key": "navigate_to", "type": "NavigateToRequest"} in info["services"]
    assert info["parameters"]["goal_timeout"] == 30.0
    text = system.run_cli("node", "info", "sim").stdout
    assert "kind sim" in text and "PUBLISHERS" in text and "turtle1/pose" in text and "cmd_timeout = 1.0" in text
    topic = system.run_cli("topic", "info", "turtle1/pose", "-v", "--json")
    assert topic.returncode == 0, topic.stderr
    pose = json.loads(topic.stdout)
    assert pose["type"] == "Pose" and [p["node"] for p in pose["publishers"]] == ["sim"]
    assert {s["node"] for s in pose["subscribers"]} == {"navigator", "obstacle_detector", "status_monitor"}
    assert pose["publishers"][0]["pid"] == system.alive["sim"]
    assert 30 < pose["rate"] < 100 and pose["messages"] > 30, pose  # 62.5 Hz measured over a second
    plain = json.loads(system.run_cli("topic", "info", "robot/status", "--json").stdout)
    assert plain["rate"] is None and plain["type"] == "TurtleStatus"
    missing = system.run_cli("node", "info", "ghost")
    assert missing.returncode == ExitCode.UNREACHABLE and "no node named 'ghost' answers (running: " in missing.stderr
    nowhere = system.run_cli("topic", "info", "no/such")
    assert (
        nowhere.returncode == ExitCode.UNREACHABLE and "no node publishes or subscribes to 'no/such'" in nowhere.stderr
    )


def test_log_level_changes_what_a_running_node_writes(system):
    system.teleport(2.0, 8.0, 0.0)
    quiet = system.run_cli("log-level", "navigator", "warning")
    assert (quiet.returncode, quiet.stdout.strip()) == (0, "navigator logs WARNING and above (was INFO)")
    start = len(system.lines)
    assert system.run_cli("goto", "3", "8", "0").returncode == 0
    loud = system.run_cli("log-level", "navigator", "DEBUG")
    assert loud.returncode == 0, loud.stderr
    after = len(system.lines)
    assert not [line for line in system.lines[start:after] if line.startswith("navigator") and "INFO" in line]
    assert system.run_cli("goto", "4", "8", "0").returncode == 0
    system.wait_line(r"^navigator\s+\| DEBUG planned 1\.00 m straight", 5.0, after)
    assert system.run_cli("log-level", "navigator", "info").returncode == 0
    bad = system.run_cli("log-level", "navigator", "loud")
    assert (
        bad.returncode == ExitCode.BAD_INPUT
        and "unknown log level 'loud' (known: DEBUG, INFO, WARNING, ERROR)" in bad.stderr
    )


# -- teleop ------------------------------------------------------------------
def teleop(system, *extra: str) -> tuple[int, int, Screen]:
    pid, fd = in_pty("teleop", "--connect", system.endpoint, *extra)
    set_winsize(fd, 30, 200)  # wide enough for the status line's note
    screen = Screen()
    deadline = time.monotonic() + 15
    while "| x " not in screen.text:  # the status line shows a pose: it is subscribed and drawing
        assert time.monotonic() < deadline, screen.text
        assert pump(fd, screen, 0.1), screen.text
    return pid, fd, screen


def hold(fd: int, screen: Screen, key: bytes, seconds: float) -> None:
    """A held key: the terminal repeats it every 40 ms."""
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        os.write(fd, key)
        pump(fd, screen, 0.04)


def ended(proc: subprocess.Popen, fd: int, screen: Screen, timeout: float = 10.0) -> tuple[str, str]:
    """Wait for ``proc`` to end while reading the terminal (unread, its buffer fills and teleop,
    blocked writing its status line, would read no key)."""
    deadline = time.monotonic() + timeout
    while proc.poll() is None:
        assert time.monotonic() < deadline, f"{proc.args} did not end within {timeout} s"
        pump(fd, screen, 0.05)
    return proc.communicate()


def finish(pid: int, fd: int, screen: Screen) -> int:
    while pump(fd, screen, 0.1):
        pass
    _, status = os.waitpid(pid, 0)
    return os.WEXITSTATUS(status) if os.WIFEXITED(status) else -1


def test_teleop_keys_move_the_turtle_the_right_way_space_stops_q_restores_the_terminal(system):
    system.teleport(3.0, 5.5, 0.0)
    pid, fd, screen = teleop(system, "--linear", "1.0")
    try:
        assert not termios.tcgetattr(fd)[3] & termios.ECHO  # cbreak: keys are read, not echoed
        hold(fd, screen, b"\x1b[A", 0.6)  # up: forward along the heading (+x)
        moving = system.wait_moving(0.5)
        assert moving.x > 3.1 and abs(moving.y - 5.5) < 1e-6 and "sending linear +1.00 m/s" in screen.text
        os.write(fd, b" ")
        stopped = system.wait_stopped(timeout=0.9)  # before the simulator's own 1 s command timeout
        hold(fd, screen, b"a", 0.6)  # a (left): counter-clockwise
        turned = system.latest_pose()
        assert 0.0 < turned.theta < 3.0 and abs(turned.x - stopped.x) < 1e-6, turned
        os.write(fd, b"q")
        assert finish(pid, fd, screen) == 0
        lflag = termios.tcgetattr(fd)[3]
        assert lflag & termios.ECHO and lflag & termios.ICANON  # the terminal as it was
    finally:
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        os.close(fd)


def test_teleop_cancels_a_running_goal_and_leaves_on_sigterm_with_a_stop_sent(system):
    system.teleport(2.0, 3.0, 0.0)
    commands: list[bytes] = []
    sub = system.session.declare_subscriber(CMD_VEL, lambda s: commands.append(s.payload.to_bytes()))
    pid, fd, screen = teleop(system)
    try:
        goal = subprocess.Popen(
            [*turtlectl(), "goto", "9", "3", "0", "--connect", system.endpoint],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            stdin=subprocess.DEVNULL,
            text=True,
        )
        try:
            system.wait_moving(0.5)
            hold(fd, screen, b"\x1b[D", 0.3)  # the keys take over
            out, err = ended(goal, fd, screen)
        finally:
            goal.kill()
        assert goal.returncode == ExitCode.FAILED and "teleop" in out + err, (out, err)
        assert "canceled the running goal (reason teleop)" in screen.text
        deadline = time.monotonic() + 5  # the keys released: teleop stops sending (a goal now would be canceled)
        while not screen.text.rsplit("\x1b[K", 1)[-1].startswith("stopped"):
            assert time.monotonic() < deadline, screen.text[-300:]
            assert pump(fd, screen, 0.1)
        goal = subprocess.Popen(  # a goal started while the keys rest: space stops it too
            [*turtlectl(), "goto", "2", "8", "0", "--connect", system.endpoint],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            stdin=subprocess.DEVNULL,
            text=True,
        )
        try:
            system.wait_moving(0.5)
            os.write(fd, b" ")
            out, err = ended(goal, fd, screen)
        finally:
            goal.kill()
        assert goal.returncode == ExitCode.FAILED and "teleop" in out + err, (out, err)
        hold(fd, screen, b"\x1b[D", 0.3)
        os.kill(pid, signal.SIGTERM)
        assert finish(pid, fd, screen) == 0
        lflag = termios.tcgetattr(fd)[3]
        assert lflag & termios.ECHO and lflag & termios.ICANON

        def stopped() -> bool:
            last = decode(commands[-1], Twist) if commands else None
            return last is not None and (last.linear, last.angular) == (0.0, 0.0) and last.seq > 0

        system.wait_until(stopped, 5.0, "teleop's stop command, the last on turtle1/cmd_vel")
    finally:
        sub.undeclare()
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        os.close(fd)


def test_teleop_without_a_terminal_is_bad_input(system):
    result = system.run_cli("teleop")
    assert result.returncode == ExitCode.BAD_INPUT
    assert "teleop reads keys from a terminal, and its input is not one" in result.stderr


def test_after_a_respawn_brings_back_a_launch_value_that_breaks_a_rule_other_changes_still_go_through(system):
    """Review of issue 13: scan_timeout 2 s, detector at 0.8 Hz, then the navigator respawned with
    scan_timeout 1 s: every `param set` on every node was refused from then on."""
    assert system.run_cli("param", "set", "navigator", "scan_timeout", "2").returncode == 0
    assert system.run_cli("param", "set", "obstacle_detector", "rate", "0.8").returncode == 0
    pid = system.alive["navigator"]
    os.kill(pid, signal.SIGKILL)
    system.wait_until(lambda: system.alive.get("navigator", pid) != pid, 15.0, "navigator respawned")
    assert get(system, "navigator", "scan_timeout") == 1.0
    unrelated = system.run_cli("param", "set", "status_monitor", "drain_per_second", "0.01")
    assert unrelated.returncode == 0, unrelated.stderr
    repair = system.run_cli("param", "set", "obstacle_detector", "rate", "5")
    assert repair.returncode == 0, repair.stderr


def test_topic_info_on_a_service_says_it_is_one(system):
    result = system.run_cli("topic", "info", "navigate_to")
    assert result.returncode == ExitCode.BAD_INPUT
    assert "navigate_to is a service (NavigateToRequest, served by navigator), not a topic" in result.stderr
