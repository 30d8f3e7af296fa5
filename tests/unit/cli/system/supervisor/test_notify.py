"""The launch tells whoever started it how it goes, in systemd's notify protocol: READY=1 with
the ready line, each node's exit, STOPPING=1; a real datagram socket, the policy on a fake clock."""

from __future__ import annotations

import os
import socket
from pathlib import Path

import pytest

from turtlectl.cli.system.supervisor.notify import EXIT, NODE, NOTIFY_SOCKET, Notifier, parse

from .test_supervision import System, node


@pytest.fixture
def listener(tmp_path: Path):
    sock = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
    sock.bind(str(tmp_path / "notify"))
    sock.setblocking(False)
    yield sock, str(tmp_path / "notify")
    sock.close()


def received(sock: socket.socket) -> list[dict[str, str]]:
    out = []
    while True:
        try:
            out.append(parse(sock.recv(4096)))
        except BlockingIOError:
            return out


def test_the_notifier_is_taken_out_of_the_environment_so_the_nodes_never_inherit_it(monkeypatch, listener):
    sock, path = listener
    monkeypatch.setenv(NOTIFY_SOCKET, path)
    notifier = Notifier.from_environment()
    assert NOTIFY_SOCKET not in os.environ
    notifier.ready("all 2 nodes ready in 0.40 s")
    assert received(sock) == [{"READY": "1", "STATUS": "all 2 nodes ready in 0.40 s"}]


def test_nobody_to_tell_or_a_socket_gone_is_no_error(tmp_path):
    Notifier().ready("x")
    Notifier(str(tmp_path / "gone")).exited("sim", 1, "exited with code 1")


def test_the_launch_says_ready_with_its_ready_line_then_each_exit_then_stopping(listener):
    sock, path = listener
    system = System(node("sim") + node("navigator"))
    system.process("navigator", runs=(3.0,), code=1)
    system.supervision.notifier = Notifier(path)
    system.stop_at(5.0)
    system.run()
    said = received(sock)
    ready_line = next(line for line in system.lines() if "ready in" in line)
    assert said[0] == {"READY": "1", "STATUS": ready_line}
    assert said[1] == {NODE: "navigator", EXIT: "1", "STATUS": "navigator exited with code 1"}
    assert said[2] == {"STOPPING": "1", "STATUS": "stopping"}
    assert said[3:] == []  # the others stopped on request after STOPPING: nothing more to say


def test_parse_ignores_lines_without_a_value():
    assert parse(b"READY=1\nnonsense\nSTATUS=a=b\n") == {"READY": "1", "STATUS": "a=b"}
