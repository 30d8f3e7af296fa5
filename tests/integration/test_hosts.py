"""Nodes on another host: two network namespaces joined by a veth pair, made and removed
by the test itself (only their own addresses are used), stand for two machines.

Host A runs the system without its navigator, its router listening on A's veth
address; host B runs only the navigator, joining A's router, and sends a goal.
"""

from __future__ import annotations

import json
import math
import os
import re
import secrets
import signal
import subprocess
import threading
import time
from pathlib import Path

import pytest

from tests.integration.harness import free_port, turtlectl

pytestmark = pytest.mark.integration


def sh(*argv: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(list(argv), capture_output=True, text=True, timeout=20)


def tool(netns: str, *args: str) -> subprocess.CompletedProcess[str]:
    """``turtlectl ARGS`` run on the host that network namespace ``netns`` stands for."""
    return sh("ip", "netns", "exec", netns, *turtlectl(), *args)


@pytest.fixture()
def hosts():
    tag = secrets.token_hex(3)
    a, b = f"tc-a-{tag}", f"tc-b-{tag}"
    made = sh("ip", "netns", "add", a)
    if made.returncode != 0:
        pytest.skip(f"network namespaces are not available here: {made.stderr.strip()}")
    try:
        steps = [
            ("ip", "netns", "add", b),
            ("ip", "link", "add", f"va{tag}", "type", "veth", "peer", "name", f"vb{tag}"),
            ("ip", "link", "set", f"va{tag}", "netns", a),
            ("ip", "link", "set", f"vb{tag}", "netns", b),
            ("ip", "-n", a, "addr", "add", "10.231.7.1/30", "dev", f"va{tag}"),
            ("ip", "-n", b, "addr", "add", "10.231.7.2/30", "dev", f"vb{tag}"),
            ("ip", "-n", a, "link", "set", f"va{tag}", "up"),
            ("ip", "-n", b, "link", "set", f"vb{tag}", "up"),
            ("ip", "-n", a, "link", "set", "lo", "up"),
            ("ip", "-n", b, "link", "set", "lo", "up"),
        ]
        for step in steps:
            done = sh(*step)
            if done.returncode != 0:
                pytest.skip(f"cannot build the test network ({' '.join(step)}): {done.stderr.strip()}")
        yield a, b
    finally:
        sh("ip", "netns", "del", a)
        sh("ip", "netns", "del", b)


def assert_reached_3_3(line: str) -> None:
    """The outcome line says (3, 3) was reached within the navigator's position tolerance (0.01 m):
    "reached at (2.997, 2.997, ...)" is as right as "(3.000, 3.000, ...)" (the CI saw the former)."""
    found = re.search(r"reached at \(([-\d.]+), ([-\d.]+),", line)
    assert found, line
    assert math.hypot(float(found[1]) - 3.0, float(found[2]) - 3.0) <= 0.01, line


class Launch:
    """`turtlectl launch` inside a namespace, its output collected."""

    def __init__(self, netns: str, *args: str):
        self.lines: list[str] = []
        self.proc = subprocess.Popen(
            ["ip", "netns", "exec", netns, *turtlectl(), "launch", *args],
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            start_new_session=True,
            env={**os.environ, "PYTHONUNBUFFERED": "1", "TURTLECTL_LOG_DIR": "/tmp/turtlectl-test-logs"},
        )
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        assert self.proc.stdout is not None
        for line in self.proc.stdout:
            self.lines.append(line.rstrip())

    def wait_for(self, pattern: str, timeout: float) -> None:
        deadline = time.monotonic() + timeout
        while not any(re.search(pattern, line) for line in self.lines):
            assert self.proc.poll() is None or any(re.search(pattern, line) for line in self.lines), "\n".join(
                self.lines
            )
            assert time.monotonic() < deadline, f"no {pattern!r}:\n" + "\n".join(self.lines)
            time.sleep(0.05)  # pacing: polling collected output under a deadline

    def stop(self) -> None:
        if self.proc.poll() is None:
            os.killpg(self.proc.pid, signal.SIGINT)
            try:
                self.proc.wait(8)
            except subprocess.TimeoutExpired:
                os.killpg(self.proc.pid, signal.SIGKILL)


def test_a_navigator_on_another_host_joins_the_system(hosts):
    a, b = hosts
    port = free_port()
    endpoint = f"tcp/10.231.7.1:{port}"
    host_a = Launch(a, "--exclude", "navigator", "--listen", "10.231.7.1", "--insecure", "--port", str(port))
    host_b = None
    try:
        host_a.wait_for(r"all 3 nodes ready", 30)
        host_b = Launch(b, "--only", "navigator", "--connect", endpoint)
        host_b.wait_for(r"1 node ready", 30)
        goal = tool(b, "goto", "3", "3", "45", "--connect", endpoint)
        assert goal.returncode == 0, goal.stdout + goal.stderr
        assert_reached_3_3(goal.stdout)
        listed = tool(a, "list", "--connect", endpoint)
        assert "navigator" in listed.stdout and "obstacle_detector" in listed.stdout
        # host A's own tools reach it on loopback too, with no --connect but the port
        local = tool(a, "echo", "robot/status", "--once", "--connect", f"tcp/127.0.0.1:{port}")
        assert local.returncode == 0 and "battery" in local.stdout, local.stdout + local.stderr
        # and nothing of the system is reachable from the root namespace on loopback
        assert sh(*turtlectl(), "list", "--connect", f"tcp/127.0.0.1:{port}").returncode == 3
    finally:
        if host_b is not None:
            host_b.stop()
        host_a.stop()


def test_listen_on_a_network_address_keeps_loopback_for_the_hosts_own_tools(hosts):
    """`launch --listen ADDRESS` on the default port: host A's own tools reach the router with
    no --connect at all (loopback, as on one machine), host B at ADDRESS. Each namespace has a
    network of its own, so the default port is free in it."""
    a, b = hosts
    env = {k: v for k, v in os.environ.items() if k != "TURTLECTL_CONNECT"}
    host_a = Launch(a, "--listen", "10.231.7.1", "--insecure")
    try:
        host_a.wait_for(r"all 4 nodes ready", 30)
        host_a.wait_for(r"router listening on tcp/10\.231\.7\.1:7447 and tcp/127\.0\.0\.1:7447", 1)
        for argv in (
            (a, "echo", "robot/status", "--once"),
            (a, "node", "list"),
            (b, "echo", "robot/status", "--once", "--connect", "tcp/10.231.7.1:7447"),
        ):
            done = subprocess.run(
                ["ip", "netns", "exec", argv[0], *turtlectl(), *argv[1:]],
                capture_output=True,
                text=True,
                timeout=20,
                env=env,
            )
            assert done.returncode == 0, f"{argv}: {done.stdout}{done.stderr}"
            assert ("battery" in done.stdout) if argv[1] == "echo" else ("navigator" in done.stdout), done.stdout
    finally:
        host_a.stop()


def test_listen_on_a_network_address_with_loopbacks_port_taken_says_so_and_a_port_free_on_both(hosts):
    """A router listening on ADDRESS listens on loopback too: a port busy on loopback alone is
    busy for it, and the message names both endpoints and a port free on both (7448 is taken on
    loopback as well here, so 7449)."""
    a, _ = hosts
    held = [Launch(a, "--only", "status_monitor"), Launch(a, "--only", "status_monitor", "--port", "7448")]
    try:
        for launch in held:
            launch.wait_for(r"1 node ready", 30)
        done = tool(a, "router", "--listen", "10.231.7.1", "--insecure")
        assert done.returncode != 0, done.stdout
        assert "cannot listen on tcp/10.231.7.1:7447 and tcp/127.0.0.1:7447: the port is already in use" in done.stderr
        assert done.stderr.rstrip().endswith("--listen 10.231.7.1 --insecure --port 7449"), done.stderr
    finally:
        for launch in held:
            launch.stop()


def test_a_client_on_another_host_drives_a_secure_system_over_mutual_tls(hosts, tmp_path, monkeypatch):
    """Beyond loopback, --secure --tls: logins and data encrypted, both ends certified."""
    a, b = hosts
    port = free_port()
    certs, other = tmp_path / "tls", tmp_path / "other"
    assert sh(*turtlectl(), "certs", str(certs), "--host", "10.231.7.1").returncode == 0
    assert sh(*turtlectl(), "certs", str(other)).returncode == 0  # another authority's
    monkeypatch.setenv("TURTLECTL_CREDENTIALS", str(tmp_path / "credentials.json"))
    monkeypatch.setenv("TURTLECTL_TLS", str(certs))
    endpoint = f"tls/10.231.7.1:{port}"
    host_a = Launch(a, "--secure", "--tls", str(certs), "--listen", "10.231.7.1", "--port", str(port))
    try:
        host_a.wait_for(r"all 4 nodes ready", 30)
        goal = tool(b, "goto", "3", "3", "45", "--connect", endpoint)
        assert goal.returncode == 0, goal.stdout + goal.stderr
        assert_reached_3_3(goal.stdout)
        # host A's own tools reach it on loopback too, over TLS with the logins of the same file
        local = tool(a, "echo", "robot/status", "--once", "--connect", f"tls/127.0.0.1:{port}")
        assert local.returncode == 0 and "battery" in local.stdout, local.stdout + local.stderr
        plain = tool(b, "list", "--connect", f"tcp/10.231.7.1:{port}")
        assert plain.returncode == 3 and "speaks TLS only (connect with tls/HOST:PORT)" in plain.stderr, plain.stderr
        monkeypatch.setenv("TURTLECTL_TLS", str(other))
        foreign = tool(b, "list", "--connect", endpoint)
        assert foreign.returncode == 3 and "is not one its authority signed" in foreign.stderr, foreign.stderr
    finally:
        host_a.stop()


FLEET = str(Path(__file__).resolve().parents[2] / "examples" / "fleet" / "launch.toml")


def test_a_turtles_nodes_on_another_host_join_the_fleet(hosts):
    """Host A runs the world and turtle1's and turtle3's nodes, host B turtle2's
    (``--only turtle2``, a namespace's nodes), joining A's router; B drives turtle2."""
    a, b = hosts
    port = free_port()
    endpoint = f"tcp/10.231.7.1:{port}"
    host_a = Launch(a, FLEET, "--exclude", "turtle2", "--listen", "10.231.7.1", "--insecure", "--port", str(port))
    host_b = None
    try:
        host_a.wait_for(r"all 7 nodes ready", 60)
        host_b = Launch(b, FLEET, "--only", "turtle2", "--connect", endpoint)
        host_b.wait_for(r"all 3 nodes ready", 60)
        goal = sh(
            "ip", "netns", "exec", b, *turtlectl(), "goto", "3", "3", "45", "--turtle", "turtle2", "--connect", endpoint
        )
        assert goal.returncode == 0, goal.stdout + goal.stderr
        assert_reached_3_3(goal.stdout)
        listed = tool(a, "list", "--connect", endpoint).stdout
        assert "turtle2/navigator" in listed and "turtle3/navigator" in listed, listed
    finally:
        if host_b is not None:
            host_b.stop()
        host_a.stop()


def test_a_turtles_nodes_on_another_host_join_a_secure_fleet_with_their_own_logins(hosts, tmp_path, monkeypatch):
    """Under --secure --tls, the nodes A leaves to another host (--exclude turtle2) get
    their logins in A's entry of the credentials file (copied to B with the clients'); B's
    nodes log in with them over mutual TLS, each allowed its interface, and drive turtle2."""
    a, b = hosts
    port = free_port()
    certs = tmp_path / "tls"
    assert sh(*turtlectl(), "certs", str(certs), "--host", "10.231.7.1").returncode == 0
    store = tmp_path / "credentials.json"
    monkeypatch.setenv("TURTLECTL_CREDENTIALS", str(store))
    monkeypatch.setenv("TURTLECTL_TLS", str(certs))
    endpoint = f"tls/10.231.7.1:{port}"
    host_a = Launch(
        a, FLEET, "--exclude", "turtle2", "--secure", "--tls", str(certs), "--listen", "10.231.7.1", "--port", str(port)
    )
    host_b = None
    try:
        host_a.wait_for(r"all 7 nodes ready", 60)
        entry = json.loads(store.read_text())[endpoint]
        assert {"node turtle2/navigator", "node turtle2/status_monitor", "node turtle2/obstacle_detector"} <= set(entry)
        assert "node turtle3/navigator" not in entry  # A runs it: its login stays with A
        host_b = Launch(b, FLEET, "--only", "turtle2", "--connect", endpoint)
        host_b.wait_for(r"all 3 nodes ready", 60)
        goal = sh(
            "ip", "netns", "exec", b, *turtlectl(), "goto", "3", "3", "45", "--turtle", "turtle2", "--connect", endpoint
        )
        assert goal.returncode == 0, goal.stdout + goal.stderr + "\n".join(host_b.lines)
        assert_reached_3_3(goal.stdout)
        status = tool(b, "echo", "robot/status", "--turtle", "turtle2", "--once", "--connect", endpoint)
        assert status.returncode == 0 and "TurtleStatus" in status.stdout, status.stdout + status.stderr
    finally:
        if host_b is not None:
            host_b.stop()
        host_a.stop()
