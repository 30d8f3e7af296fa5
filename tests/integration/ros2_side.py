"""The ROS 2 side of the bridge's tests: a network namespace holding only loopback (no DDS packet
can leave 127.0.0.1: Fast DDS's localhost mode still advertises the network card's address), and in
it turtlectl's launched system, turtlectl's tools, and real rclpy nodes (``.venv-ros2``, the
pip-installed wheels: never imported in ``.venv``).

Every process runs in its own process group (killed whole at the end); readiness is what a process
prints (``READY``, the launch's "ready" line), waited for under a deadline.
"""

from __future__ import annotations

import json
import os
import re
import secrets
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest

from tests.integration.harness import free_port, turtlectl

ROOT = Path(__file__).resolve().parents[2]
ROS2_PYTHON = ROOT / ".venv-ros2" / "bin" / "python"
SCRIPTS = Path(__file__).resolve().parent / "ros2_scripts"
DEADLINE = 40.0  # s: matching takes 0.4-1.5 s; a launch about 1 s; generous on 2 shared cores

#: the default launch file plus the bridge (its default table)
BRIDGE_NODE = """
[[node]]
name = "ros2_bridge"
run = "ros2_bridge"
"""


def require_ros2_side() -> Path:
    """The rclpy venv's python; a clear failure (not a skip: `make test` makes it) without it."""
    if not ROS2_PYTHON.exists():
        pytest.fail(f"{ROS2_PYTHON} is missing: run `make ros2-side` (the real rclpy wheels for these tests)")
    return ROS2_PYTHON


def _sh(*argv: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(list(argv), capture_output=True, text=True, timeout=20)


@contextmanager
def loopback_netns() -> Iterator[str]:
    """A fresh network namespace with only ``lo``, up; removed after."""
    name = f"tc-ros-{secrets.token_hex(3)}"
    made = _sh("ip", "netns", "add", name)
    if made.returncode != 0:
        pytest.skip(f"network namespaces are not available here: {made.stderr.strip()}")
    try:
        up = _sh("ip", "-n", name, "link", "set", "lo", "up")
        assert up.returncode == 0, up.stderr
        yield name
    finally:
        _sh("ip", "netns", "del", name)


def ros_env(domain: int = 0) -> dict[str, str]:
    from turtlectl.nodes.ros2_dds import rclpy_environment

    env = {k: v for k, v in os.environ.items() if not k.startswith(("VIRTUAL_ENV", "PYTHON"))}
    return {**env, **rclpy_environment(domain), "PYTHONUNBUFFERED": "1"}


class Proc:
    """A process in the namespace, its output (stdout and stderr) collected line by line."""

    def __init__(self, netns: str, argv: list[str], env: dict[str, str] | None = None, stdin: bool = False):
        self.lines: list[str] = []
        self.proc = subprocess.Popen(
            ["ip", "netns", "exec", netns, *argv],
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            stdin=subprocess.PIPE if stdin else subprocess.DEVNULL,
            text=True,
            start_new_session=True,
            env=env or {**os.environ, "PYTHONUNBUFFERED": "1", "TURTLECTL_LOG_DIR": "/tmp/turtlectl-test-logs"},
        )
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self) -> None:
        assert self.proc.stdout is not None
        for line in self.proc.stdout:
            self.lines.append(line.rstrip())

    def text(self) -> str:
        return "\n".join(self.lines)

    def wait_for(self, pattern: str, timeout: float = DEADLINE) -> str:
        """The first line matching ``pattern``, waited for under a deadline (the process's output on failure)."""
        deadline = time.monotonic() + timeout
        while True:
            for line in list(self.lines):
                if re.search(pattern, line):
                    return line
            if self.proc.poll() is not None:
                self._reader.join(2)
                for line in self.lines:
                    if re.search(pattern, line):
                        return line
                raise AssertionError(f"exited {self.proc.returncode} before {pattern!r}:\n{self.text()}")
            assert time.monotonic() < deadline, f"no {pattern!r} within {timeout} s:\n{self.text()}"
            time.sleep(0.02)  # pacing: polling collected output under a deadline

    def json_line(self, prefix: str, timeout: float = DEADLINE) -> dict:
        return json.loads(self.wait_for(f"^{prefix} ", timeout).split(" ", 1)[1])

    def finish(self, timeout: float = DEADLINE) -> int:
        try:
            code = self.proc.wait(timeout)
        except subprocess.TimeoutExpired:
            self.stop()
            raise AssertionError(f"still running after {timeout} s:\n{self.text()}") from None
        self._reader.join(2)
        return code

    def stop(self, sig: int = signal.SIGINT, grace: float = 8.0) -> None:
        if self.proc.poll() is None:
            try:
                os.killpg(self.proc.pid, sig)
                self.proc.wait(grace)
            except subprocess.TimeoutExpired:
                os.killpg(self.proc.pid, signal.SIGKILL)
                self.proc.wait(5)
            except ProcessLookupError:
                pass


class RosSide:
    """One namespace: turtlectl's system (``launch``), its tools (``tool``), rclpy nodes (``rclpy``)."""

    def __init__(self, netns: str):
        self.netns = netns
        self.port = free_port()
        self.endpoint = f"tcp/127.0.0.1:{self.port}"
        self.procs: list[Proc] = []

    def launch(self, launch_text: str, folder: Path, *args: str, nodes: int) -> Proc:
        path = folder / "launch.toml"
        path.write_text(launch_text)
        proc = self.spawn([*turtlectl(), "launch", str(path), "--port", str(self.port), *args])
        proc.wait_for(rf"all {nodes} nodes ready")
        return proc

    def spawn(self, argv: list[str], env: dict[str, str] | None = None, stdin: bool = False) -> Proc:
        proc = Proc(self.netns, argv, env, stdin)
        self.procs.append(proc)
        return proc

    def tool(self, *args: str, timeout: float = DEADLINE) -> subprocess.CompletedProcess[str]:
        """``turtlectl ARGS --connect`` the system, in the namespace."""
        return subprocess.run(
            ["ip", "netns", "exec", self.netns, *turtlectl(), *args, "--connect", self.endpoint],
            capture_output=True,
            text=True,
            timeout=timeout,
        )

    def rclpy(self, script: str, *args: str, domain: int = 0) -> Proc:
        """``.venv-ros2/bin/python ros2_scripts/SCRIPT ARGS``: a real rclpy node."""
        return self.spawn([str(require_ros2_side()), str(SCRIPTS / script), *args], env=ros_env(domain))

    def turtlectl_python(self, *argv: str, env: dict[str, str] | None = None) -> Proc:
        return self.spawn([sys.executable, *argv], env=env)

    def close(self) -> None:
        for proc in reversed(self.procs):
            proc.stop()


@contextmanager
def ros_side() -> Iterator[RosSide]:
    """A namespace holding only loopback, and what runs in it, stopped whole at the end."""
    require_ros2_side()
    with loopback_netns() as netns:
        side = RosSide(netns)
        try:
            yield side
        finally:
            side.close()


def default_launch_with_bridge(extra: str = "") -> str:
    """The packaged default launch file, the bridge added (and ``extra``: its params or more rows)."""
    return (ROOT / "launch.toml").read_text() + BRIDGE_NODE + extra
