"""Introspection of the running system: node info, topic info, log levels."""

from __future__ import annotations

import json

import pytest

from turtlectl.runtime.client.errors import ExitCode

pytestmark = pytest.mark.integration


def test_node_info_and_topic_info_describe_the_running_graph(system):
    result = system.run_cli("node", "info", "navigator", "--json")
    assert result.returncode == 0, result.stderr
    info = json.loads(result.stdout)
    assert (info["kind"], info["pid"]) == ("navigator", system.alive["navigator"]) and info["uptime"] > 0
    assert {"key": "turtle1/cmd_vel", "type": "turtlectl/Twist"} in info["publishers"]
    assert {"key": "turtle1/pose", "type": "turtlectl/Pose"} in info["subscribers"]
    assert {"key": "navigate_to", "type": "turtlectl/NavigateToRequest"} in info["services"]
    assert info["parameters"]["goal_timeout"] == 30.0
    text = system.run_cli("node", "info", "sim").stdout
    assert "kind sim" in text and "PUBLISHERS" in text and "turtle1/pose" in text and "cmd_timeout = 1.0" in text
    topic = system.run_cli("topic", "info", "turtle1/pose", "-v", "--json")
    assert topic.returncode == 0, topic.stderr
    pose = json.loads(topic.stdout)
    assert pose["type"] == "turtlectl/Pose" and [p["node"] for p in pose["publishers"]] == ["sim"]
    assert {s["node"] for s in pose["subscribers"]} == {"navigator", "obstacle_detector", "status_monitor"}
    assert pose["publishers"][0]["pid"] == system.alive["sim"]
    assert 30 < pose["rate"] < 100 and pose["messages"] > 30, pose  # 62.5 Hz measured over a second
    plain = json.loads(system.run_cli("topic", "info", "robot/status", "--json").stdout)
    assert plain["rate"] is None and plain["type"] == "turtlectl/TurtleStatus"
    missing = system.run_cli("node", "info", "ghost")
    assert missing.returncode == ExitCode.UNREACHABLE and "no node named 'ghost' answers (running: " in missing.stderr
    for typo in (
        ("node", "info", "navigatr"),
        ("param", "get", "navigatr", "goal_timeout"),
        ("log-level", "navigatr", "debug"),
    ):
        near = system.run_cli(*typo)
        assert near.returncode == ExitCode.UNREACHABLE, near
        assert "no node named 'navigatr' answers; did you mean navigator? (running: " in near.stderr, near.stderr
    near = system.run_cli("log", "--node", "navigatr")
    assert "no running node matches --node navigatr; did you mean navigator? (running: " in near.stderr, near.stderr
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


def test_topic_info_on_a_service_says_it_is_one(system):
    result = system.run_cli("topic", "info", "navigate_to")
    assert result.returncode == ExitCode.BAD_INPUT
    assert "navigate_to is a service (turtlectl/NavigateToRequest, served by navigator), not a topic" in result.stderr
