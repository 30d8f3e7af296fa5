"""Every participant visible: the clients (tools, a script's Client) in `list`, `node list` and
`topic info` with their host and pid, and a second teleop on one turtle refused unless --force."""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import time
from collections.abc import Callable
from typing import Any

import pytest

from tests.integration.harness import in_pty, pump, set_winsize, turtlectl
from tests.integration.test_teleop import Screen, finish, teleop
from turtlectl.runtime.client.errors import ExitCode

pytestmark = pytest.mark.integration

SCRIPT = """
import sys
import turtlectl
with turtlectl.Client(sys.argv[1]) as client:
    client.subscribe("turtle1/pose")
    print("subscribed", flush=True)
    sys.stdin.read()  # until the test closes it
"""


def listed(system, until: Callable[[dict[str, Any]], bool], timeout: float = 15.0) -> dict[str, Any]:
    """`list --json`, asked again until ``until`` holds (a token reaches the router in a few ms)."""
    deadline = time.monotonic() + timeout
    while True:
        out = system.run_cli("list", "--json")
        assert out.returncode == 0, out.stderr
        graph = json.loads(out.stdout)
        if until(graph):
            return graph
        assert time.monotonic() < deadline, out.stdout
        time.sleep(0.1)  # polling the graph under a deadline, not a wait for readiness


def client(graph: dict[str, Any], pid: int) -> dict[str, Any] | None:
    return next((c for c in graph["clients"] if c["pid"] == pid), None)


def test_an_echo_and_a_script_s_client_are_listed_with_tool_host_pid_and_their_subscriptions(system):
    echo = subprocess.Popen(
        [*turtlectl(), "echo", "robot/status", "--connect", system.endpoint],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        stdin=subprocess.DEVNULL,
    )
    script = subprocess.Popen(
        [sys.executable, "-c", SCRIPT, system.endpoint], stdout=subprocess.PIPE, stdin=subprocess.PIPE, text=True
    )
    try:
        assert script.stdout.readline().strip() == "subscribed"
        graph = listed(system, lambda g: client(g, echo.pid) is not None and client(g, script.pid) is not None)
        mine, theirs = client(graph, echo.pid), client(graph, script.pid)
        assert (mine["name"], mine["tool"], mine["host"]) == (f"echo-{echo.pid}", "echo", socket.gethostname())
        assert (theirs["name"], theirs["tool"]) == (f"python-{script.pid}", "python")
        topics = {t["key"]: t for t in graph["topics"]}
        assert f"echo-{echo.pid}" in topics["robot/status"]["subscribers"]
        assert f"python-{script.pid}" in topics["turtle1/pose"]["subscribers"]
        assert not any(c["tool"] == "list" for c in graph["clients"])  # the one asking is not listed

        names = system.run_cli("node", "list").stdout.splitlines()
        assert (
            "sim" in names and f"echo-{echo.pid}  (client: echo, pid {echo.pid}, host {socket.gethostname()})" in names
        )
        nodes = json.loads(system.run_cli("node", "list", "--json").stdout)
        assert "navigator" in [n["name"] for n in nodes["nodes"]] and client(nodes, script.pid)["tool"] == "python"

        info = json.loads(system.run_cli("topic", "info", "robot/status", "--json").stdout)
        (sub,) = [s for s in info["subscribers"] if s["pid"] == echo.pid]
        assert (sub["node"], sub["tool"], sub["host"]) == (f"echo-{echo.pid}", "echo", socket.gethostname())
        asked = system.run_cli("node", "info", f"echo-{echo.pid}")
        assert asked.returncode == ExitCode.BAD_INPUT and "is a client (echo, pid" in asked.stderr, asked.stderr
        text = system.run_cli("topic", "info", "-v", "turtle1/pose").stdout
        assert f"python-{script.pid} (client: python, pid {script.pid}, host {socket.gethostname()})" in text
    finally:
        echo.send_signal(signal.SIGINT)
        script.stdin.close()
        assert echo.wait(10) == 0 and script.wait(10) == 0
    listed(system, lambda g: client(g, echo.pid) is None and client(g, script.pid) is None)  # gone with them


def test_a_second_teleop_on_a_turtle_is_refused_naming_the_first_and_with_force_both_are_warned(system):
    first, fd1, screen1 = teleop(system)
    host = socket.gethostname()
    try:
        graph = listed(system, lambda g: client(g, first) is not None)
        cmd_vel = next(t for t in graph["topics"] if t["key"] == "turtle1/cmd_vel")
        assert f"teleop-{first}" in cmd_vel["publishers"] and client(graph, first)["tool"] == "teleop"

        second, fd2 = in_pty("teleop", "--connect", system.endpoint)
        set_winsize(fd2, 30, 200)
        screen2 = Screen()
        assert finish(second, fd2, screen2) == ExitCode.CANNOT_START, screen2.text
        os.close(fd2)
        assert f"turtle1/cmd_vel is already driven by teleop-{first} (pid {first}, host {host})" in screen2.text
        assert "--force" in screen2.text

        forced, fd3, screen3 = teleop(system, "--force")
        try:
            assert (
                f"warning: turtle1/cmd_vel is also driven by teleop-{first} (pid {first}, host {host})" in screen3.text
            )
            deadline = time.monotonic() + 10
            warned = f"teleop-{forced} (pid {forced}, host {host}) also drives turtle1/cmd_vel"
            while warned not in screen1.text:
                assert time.monotonic() < deadline, screen1.text[-400:]
                pump(fd1, screen1, 0.1)
            os.write(fd3, b"q")
            assert finish(forced, fd3, screen3) == 0
        finally:
            _kill(forced)
            os.close(fd3)
        os.write(fd1, b"q")
        assert finish(first, fd1, screen1) == 0
    finally:
        _kill(first)
        os.close(fd1)


def _kill(pid: int) -> None:
    try:
        os.kill(pid, signal.SIGKILL)
        os.waitpid(pid, 0)
    except (ProcessLookupError, ChildProcessError):
        pass
