"""Parameters of running nodes against the real system: param set takes effect at once and publishes an
event, refusals as the launch file's, respawn and --persist."""

from __future__ import annotations

import json
import os
import signal
import statistics
import subprocess

import pytest

from tests.integration.harness import running_system, turtlectl
from turtlectl.messages import ParameterEvent, TurtleStatus, decode
from turtlectl.messages.keys import PARAMETER_EVENTS, STATUS
from turtlectl.runtime.client.errors import ExitCode

pytestmark = pytest.mark.integration


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


def test_after_a_respawn_brings_back_a_launch_value_that_breaks_a_rule_other_changes_still_go_through(system):
    """scan_timeout 2 s, detector at 0.8 Hz, then the navigator respawned with scan_timeout 1 s:
    `param set` still takes what does not make it worse (not every change refused from then on)."""
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
